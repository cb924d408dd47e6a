//! The dense linear algebra of the patch problems: columns of the cell matrices, the change
//! to a cell's orthonormal basis, and Householder QR with its reflectors kept (`Factors`).

use nalgebra::DMatrix;

/// Most coefficients of a cell, 4 n_basis for p ≤ 2.
pub(super) const MAX_WIDTH: usize = 24;

/// Most basis functions n_basis of a cell, for p ≤ 2.
pub(super) const MAX_BASIS: usize = 6;

/// Column j of `m`.
pub(super) fn column(m: &DMatrix<f64>, j: usize) -> &[f64] {
    let rows = m.nrows();
    &m.as_slice()[j * rows..(j + 1) * rows]
}

/// Column j of `m`, mutable.
pub(super) fn column_mut(m: &mut DMatrix<f64>, j: usize) -> &mut [f64] {
    let rows = m.nrows();
    &mut m.as_mut_slice()[j * rows..(j + 1) * rows]
}

/// a · b with four partial sums, so that the products of short columns run in parallel.
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let mut sums = [0.0; 4];
    for (x, y) in a[..n].chunks_exact(4).zip(b[..n].chunks_exact(4)) {
        for l in 0..4 {
            sums[l] += x[l] * y[l];
        }
    }
    let tail = n - n % 4;
    let rest: f64 = a[tail..n].iter().zip(&b[tail..n]).map(|(x, y)| x * y).sum();
    (sums[0] + sums[2]) + (sums[1] + sums[3]) + rest
}

/// v ← C v for C lower triangular, row-major.
pub(super) fn to_orthonormal(c: &[f64], v: &mut [f64]) {
    let n = v.len();
    for k in (0..n).rev() {
        v[k] = dot(&c[k * n..k * n + k + 1], &v[..=k]);
    }
}

/// v ← Cᵀ v for C lower triangular, row-major.
pub(super) fn from_orthonormal(c: &[f64], v: &mut [f64]) {
    let n = v.len();
    for k in 0..n {
        v[k] = (k..n).map(|l| c[l * n + k] * v[l]).sum();
    }
}

/// Householder factors Q R of a column-major m × n matrix (m ≥ n) from [`householder_qr`],
/// kept between cells and patches so that the usual shapes do not allocate; Q is the square
/// product of the reflectors, never formed.
#[derive(Default)]
pub(super) struct Factors {
    a: Vec<f64>,
    tau: Vec<f64>,
    m: usize,
}

impl Factors {
    /// The zeroed m × n matrix to factor.
    pub(super) fn matrix(&mut self, m: usize, n: usize) -> &mut [f64] {
        self.m = m;
        self.tau.resize(n, 0.0);
        self.a.clear();
        self.a.resize(m * n, 0.0);
        &mut self.a
    }

    /// Number of columns n.
    pub(super) fn n(&self) -> usize {
        self.tau.len()
    }

    /// Factors the matrix in place; false if m < n or a diagonal entry of R is at most
    /// `dependent` times the largest.
    pub(super) fn factor(&mut self, dependent: f64) -> bool {
        let (m, n) = (self.m, self.n());
        if m < n {
            return false;
        }
        householder_qr(&mut self.a, m, n, &mut self.tau);
        let diagonal = |j: usize| self.a[j * m + j].abs();
        let largest = (0..n).map(diagonal).fold(0.0, f64::max);
        (0..n).all(|j| diagonal(j) > dependent * largest)
    }

    /// x ← Q x (x of length m).
    pub(super) fn apply(&self, x: &mut [f64]) {
        householder_apply(&self.a, self.m, &self.tau, x);
    }

    /// x ← Qᵀ x = H_{n−1} ⋯ H_0 x (x of length m).
    pub(super) fn apply_transpose(&self, x: &mut [f64]) {
        let m = self.m;
        for (j, &tau) in self.tau.iter().enumerate() {
            reflect(&self.a[j * m + j + 1..(j + 1) * m], tau, &mut x[j..]);
        }
    }

    /// c ← R⁻ᵀ c (c of length n).
    pub(super) fn solve_transpose(&self, c: &mut [f64]) {
        let m = self.m;
        for i in 0..self.n() {
            let sum = dot(&self.a[i * m..i * m + i], &c[..i]);
            c[i] = (c[i] - sum) / self.a[i * m + i];
        }
    }
}

/// Below this, a diagonal entry of R relative to the largest marks dependent local rows.
pub(super) const DEPENDENT_LOCAL: f64 = 1e-13;

/// Householder QR of the column-major m × n matrix `a` (m ≥ n) in place: R in its upper
/// triangle, the reflectors H_j = I − τ_j v_j v_jᵀ (v_j = (0, …, 0, 1, v_j below the
/// diagonal)) under it, τ_j in `tau`. By hand because the patch matrices are small (12 × 6
/// per cell, 54 × 36 on an interior P2 patch of six cells): reflectors applied to the few vectors
/// replace nalgebra's QR with the explicit Q it needs and its allocations (docs/results.md,
/// Error estimation).
fn householder_qr(a: &mut [f64], m: usize, n: usize, tau: &mut [f64]) {
    for j in 0..n {
        let column = &mut a[j * m..(j + 1) * m];
        let (alpha, below) = (column[j], &mut column[j + 1..]);
        let sigma = dot(below, below);
        if sigma == 0.0 {
            tau[j] = 0.0;
            continue;
        }
        let norm = (alpha * alpha + sigma).sqrt();
        let beta = if alpha > 0.0 { -norm } else { norm };
        let scale = 1.0 / (alpha - beta);
        below.iter_mut().for_each(|x| *x *= scale);
        column[j] = beta;
        tau[j] = (beta - alpha) / beta;
        let (left, right) = a.split_at_mut((j + 1) * m);
        for c in right.chunks_exact_mut(m) {
            reflect(&left[j * m + j + 1..], tau[j], &mut c[j..]);
        }
    }
}

/// x ← Q x = H_0 ⋯ H_{n−1} x for the factors of [`householder_qr`] (n = `tau.len()`).
fn householder_apply(a: &[f64], m: usize, tau: &[f64], x: &mut [f64]) {
    for j in (0..tau.len()).rev() {
        reflect(&a[j * m + j + 1..(j + 1) * m], tau[j], &mut x[j..]);
    }
}

/// x ← (I − τ v vᵀ) x for v = (1, `below`).
fn reflect(below: &[f64], tau: f64, x: &mut [f64]) {
    let s = tau * (x[0] + dot(below, &x[1..]));
    x[0] -= s;
    x[1..].iter_mut().zip(below).for_each(|(x, v)| *x -= s * v);
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DVector;

    /// Householder factors of a 7 × 3 matrix W.
    pub(super) fn factors(w: &DMatrix<f64>) -> Factors {
        let mut factors = Factors::default();
        factors.matrix(w.nrows(), w.ncols()).copy_from_slice(w.as_slice());
        assert!(factors.factor(DEPENDENT_LOCAL), "independent columns");
        factors
    }

    /// Source: `Factors` (Householder QR with the reflectors kept). Goal: Q is orthogonal,
    /// W = Q R, and `apply_transpose`, `solve_transpose` give Qᵀ x and R⁻ᵀ b. Parameters: a
    /// fixed 7 × 3 matrix with a dominant diagonal, x and b fixed.
    #[test]
    fn factors_apply_an_orthogonal_q_with_w_equal_q_r() {
        let w = DMatrix::from_fn(7, 3, |i, j| ((i * 5 + j * 3) % 7) as f64 - 2.5 + if i == j { 4.0 } else { 0.0 });
        let f = factors(&w);
        let q = DMatrix::from_fn(7, 7, |i, j| {
            let mut e = [0.0; 7];
            e[j] = 1.0;
            f.apply(&mut e);
            e[i]
        });
        assert!((q.transpose() * &q - DMatrix::identity(7, 7)).amax() < 1e-14, "QᵀQ = I");
        let r = DMatrix::from_fn(7, 3, |i, j| if i <= j { f.a[j * 7 + i] } else { 0.0 });
        assert!((&q * &r - &w).amax() < 1e-13 * w.amax(), "W = Q R");
        let mut x: Vec<f64> = (0..7).map(|i| i as f64 - 3.0).collect();
        let x0 = x.clone();
        f.apply_transpose(&mut x);
        assert!((DVector::from_vec(x.clone()) - q.transpose() * DVector::from_vec(x0)).amax() < 1e-14, "Qᵀ x");
        // Rᵀ c = b
        let b = [1.0, -2.0, 0.5];
        let mut c = b;
        f.solve_transpose(&mut c);
        let rt = r.rows(0, 3).transpose();
        assert!((rt * DVector::from_row_slice(&c) - DVector::from_row_slice(&b)).amax() < 1e-14, "Rᵀ c = b");
    }

    /// Source: `Factors::factor`. Goal: dependent columns, and fewer rows than columns, are
    /// refused. Parameters: a 5 × 2 matrix with equal columns; a 2 × 3 matrix of ones.
    #[test]
    fn factors_refuse_dependent_columns() {
        let mut f = Factors::default();
        f.matrix(5, 2).iter_mut().enumerate().for_each(|(k, a)| *a = (k % 5) as f64 + 1.0);
        assert!(!f.factor(DEPENDENT_LOCAL));
        f.matrix(2, 3).fill(1.0);
        assert!(!f.factor(DEPENDENT_LOCAL), "fewer rows than columns");
    }

    #[test]
    fn orthonormal_coordinates_match_the_triangular_products() {
        let c = [2.0, 0.0, 0.0, -1.0, 3.0, 0.0, 0.5, 0.25, 1.5]; // lower triangular, row-major
        let matrix = DMatrix::from_row_slice(3, 3, &c);
        let v = [1.0, -2.0, 0.5];
        let (mut to, mut from) = (v, v);
        to_orthonormal(&c, &mut to);
        from_orthonormal(&c, &mut from);
        let vector = DVector::from_row_slice(&v);
        assert!((DVector::from_row_slice(&to) - &matrix * &vector).amax() < 1e-15, "C v");
        assert!((DVector::from_row_slice(&from) - matrix.transpose() * &vector).amax() < 1e-15, "Cᵀ v");
    }
}
