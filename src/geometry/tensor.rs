//! Second-order tensors of the plane as rows of vectors (`t[i][j]`), with the operations the
//! weak forms of elasticity are written in: ε(u) = sym ∇u, tr, and the double contraction.

use super::{Vector, D};

/// A D × D tensor, `t[i][j]` its entry in row i and column j (for ∇u: ∂_j u_i).
pub type Tensor = [Vector; D];

/// sym t = ½ (t + tᵀ); of ∇u, the small strain ε(u). (Of any dimension N, as the two below.)
pub fn sym_grad<const N: usize>(t: [[f64; N]; N]) -> [[f64; N]; N] {
    std::array::from_fn(|i| std::array::from_fn(|j| 0.5 * (t[i][j] + t[j][i])))
}

/// tr t = Σ_i t_ii.
pub fn trace<const N: usize>(t: [[f64; N]; N]) -> f64 {
    (1..N).fold(t[0][0], |s, i| s + t[i][i])
}

/// a : b = Σ_ij a_ij b_ij.
pub fn ddot<const N: usize>(a: [[f64; N]; N], b: [[f64; N]; N]) -> f64 {
    (0..N).flat_map(|i| (0..N).map(move |j| (i, j))).fold(0.0, |s, (i, j)| s + a[i][j] * b[i][j])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strain_trace_and_contraction() {
        let grad = [[1.0, 2.0], [4.0, -3.0]];
        let e = sym_grad(grad);
        assert_eq!(e, [[1.0, 3.0], [3.0, -3.0]]);
        assert_eq!(trace(e), -2.0);
        // a skew tensor is orthogonal to every symmetric one
        let w = [[0.0, -1.0], [1.0, 0.0]];
        assert_eq!(ddot(e, w), 0.0);
        assert_eq!(ddot(grad, grad), 1.0 + 4.0 + 16.0 + 9.0);
    }
}
