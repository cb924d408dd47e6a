//! Element kernels of plane-strain elasticity.
//!
//! Local dofs are ordered node by node, x before y: local dof 2i + a is component a of node i.
//! Kernels write into caller-owned buffers and allocate nothing.

use crate::fem::lagrange;
use crate::fem::tabulate::Tabulation;
use crate::geometry::{sym_grad, trace, AffineMap, Point, Segment, Tensor, Vector, D};

/// Element stiffness K_{2i+a, 2j+b} = ∫_T ε(φ_i e_a) : C ε(φ_j e_b), row-major in `k`: with
/// D_kl = ∫_T ∂_k φ_i ∂_l φ_j, the 2 × 2 block of nodes (i, j) is
/// λ D_ab + μ (δ_ab (D_00 + D_11) + D_ba). Computed for j ≥ i and mirrored, so K is exactly
/// symmetric. `tab` must integrate degree 2(p−1) exactly; `grads` is scratch of length
/// n_points × n_basis.
pub fn stiffness(map: &AffineMap, tab: &Tabulation, lambda: f64, mu: f64, grads: &mut [Vector], k: &mut [f64]) {
    let nb = tab.n_basis;
    let n = 2 * nb;
    for (g, &gr) in grads.iter_mut().zip(&tab.gradients) {
        *g = map.physical_gradient(gr);
    }
    for i in 0..nb {
        for j in i..nb {
            // D_kl at index 2k + l: Σ_q ∂_k φ_i ∂_l φ_j |J| w_q
            let mut d = [0.0; 4];
            for (q, &wq) in tab.weights.iter().enumerate() {
                let (gi, gj, wq) = (grads[q * nb + i], grads[q * nb + j], wq * map.det.abs());
                for (kl, dkl) in d.iter_mut().enumerate() {
                    *dkl += gi[kl / 2] * gj[kl % 2] * wq;
                }
            }
            let [d00, d01, d10, d11] = d;
            let block = [
                [(lambda + 2.0 * mu) * d00 + mu * d11, lambda * d01 + mu * d10],
                [lambda * d10 + mu * d01, (lambda + 2.0 * mu) * d11 + mu * d00],
            ];
            for (a, b) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                let (r, s) = (2 * i + a, 2 * j + b);
                if r <= s {
                    k[r * n + s] = block[a][b];
                    k[s * n + r] = block[a][b];
                }
            }
        }
    }
}

/// Element load F_{2i+a} = f_a |det J| m_i of a body force f constant on the cell, with
/// `integrals` m_i = ∫_T̂ φ̂_i ([`Tabulation::integrals`]).
pub fn constant_body_load(map: &AffineMap, integrals: &[f64], f: Vector, out: &mut [f64]) {
    let det = map.det.abs();
    for (i, &m) in integrals.iter().enumerate() {
        out[2 * i] = f[0] * (m * det);
        out[2 * i + 1] = f[1] * (m * det);
    }
}

/// Element load F_{2i+a} = ∫_T f_a φ_i for a body force `f(x)`.
pub fn body_load(map: &AffineMap, tab: &Tabulation, f: impl Fn(Point) -> Vector, out: &mut [f64]) {
    let nb = tab.n_basis;
    out[..2 * nb].fill(0.0);
    for q in 0..tab.n_points() {
        let w = tab.weights[q] * map.det.abs();
        let fx = f(map.to_physical(tab.points[q]));
        for (i, &phi) in tab.phi(q).iter().enumerate() {
            out[2 * i] += fx[0] * phi * w; // f_x φ_i |J| w_q
            out[2 * i + 1] += fx[1] * phi * w; // f_y φ_i |J| w_q
        }
    }
}

/// Facet load F_{2i+a} = ∫_F g_a φ_i for a traction `g(x)` on the straight segment a → b whose
/// nodes are ordered (a, b, midpoint), with a rule (s, weight) on [0, 1]. `phi` is scratch of
/// length order + 1.
pub fn traction_load(
    ends: [Point; 2],
    order: usize,
    rule: &[(f64, f64)],
    g: impl Fn(Point) -> Vector,
    phi: &mut [f64],
    out: &mut [f64],
) {
    let segment = Segment::new(ends[0], ends[1]);
    let length = segment.length();
    out[..2 * (order + 1)].fill(0.0);
    for &(s, ws) in rule {
        let x = segment.point(s);
        let gx = g(x);
        lagrange::segment_values(order, s, phi);
        for (i, &p) in phi.iter().enumerate() {
            out[2 * i] += gx[0] * p * ws * length; // g_x φ_i |F| w_q
            out[2 * i + 1] += gx[1] * p * ws * length; // g_y φ_i |F| w_q
        }
    }
}

/// Displacement gradient ∇u_h (∂_j u_i at `[i][j]`) at reference point `xi` of a cell with
/// nodal displacements `u`. `grads` is scratch of length n_basis.
///
/// ∇u_h = Σ_k (u_k − u_0) ⊗ ∇φ_k (Σ_k ∇φ_k = 0): the differences to the first node are
/// exact for nearby nodes, so a displacement |u| much larger than h |∇u| (a thin cell, or a
/// cell far along a sliding base) costs no digits of the gradient.
pub fn displacement_gradient(map: &AffineMap, order: usize, xi: Point, u: &[Vector], grads: &mut [Vector]) -> Tensor {
    lagrange::gradients(order, xi, grads);
    let mut g = [[0.0; D]; D];
    for (gr, ui) in grads.iter().zip(u).skip(1) {
        let d = map.physical_gradient(*gr);
        for a in 0..D {
            let du = ui[a] - u[0][a];
            for b in 0..D {
                g[a][b] += du * d[b];
            }
        }
    }
    g
}

/// Plane-strain stress σ = λ tr ε I + 2μ ε from a displacement gradient, as
/// [σ_xx, σ_yy, σ_xy, σ_zz] with σ_zz = λ tr ε.
pub fn stress(grad_u: Tensor, lambda: f64, mu: f64) -> [f64; 4] {
    let e = sym_grad(grad_u);
    let tr = trace(e);
    [lambda * tr + 2.0 * mu * e[0][0], lambda * tr + 2.0 * mu * e[1][1], 2.0 * mu * e[0][1], lambda * tr]
}

/// von Mises stress √(½((σ₁−σ₂)² + (σ₂−σ₃)² + (σ₃−σ₁)²)) from [σ_xx, σ_yy, σ_xy, σ_zz].
pub fn von_mises(s: [f64; 4]) -> f64 {
    let [xx, yy, xy, zz] = s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2)) + 3.0 * xy * xy).sqrt()
}

/// In-plane principal stresses (σ₁ ≥ σ₂) of [σ_xx, σ_yy, σ_xy, ·].
pub fn principal(s: [f64; 4]) -> [f64; 2] {
    let mean = 0.5 * (s[0] + s[1]);
    let radius = (0.5 * (s[0] - s[1])).hypot(s[2]);
    [mean + radius, mean - radius]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::dot;

    #[test]
    fn stiffness_annihilates_rigid_motions() {
        let map = AffineMap::new([[0.1, 0.2], [1.3, 0.4], [0.35, 1.1]]);
        for order in [1, 2] {
            let tab = Tabulation::new(order, 2 * order);
            let nb = tab.n_basis;
            let mut grads = vec![[0.0; 2]; tab.n_points() * nb];
            let mut k = vec![0.0; 4 * nb * nb];
            stiffness(&map, &tab, 2.0, 1.0, &mut grads, &mut k);
            let nodes: Vec<Point> = lagrange::reference_nodes(order).iter().map(|&x| map.to_physical(x)).collect();
            let rigid = [|_: Point| [1.0, 0.0], |_: Point| [0.0, 1.0], |x: Point| [-x[1], x[0]]];
            for r in rigid {
                let v: Vec<f64> = nodes.iter().flat_map(|&x| r(x)).collect();
                for row in 0..2 * nb {
                    let kv: f64 = (0..2 * nb).map(|j| k[row * 2 * nb + j] * v[j]).sum();
                    assert!(kv.abs() < 1e-12, "K r = {kv}");
                }
            }
        }
    }

    /// Source: [`stiffness`], computed in 2 × 2 blocks of D_kl on the upper triangle. Goal: the
    /// entries equal those of ε(φ_i e_a) : C ε(φ_j e_b) summed entry by entry at the
    /// quadrature points, to round-off, and K is exactly symmetric. Parameters: a skewed cell,
    /// P1 and P2, λ = 2.5, μ = 0.7, the rule of degree 2p.
    #[test]
    fn block_stiffness_equals_entrywise_quadrature() {
        let map = AffineMap::new([[0.1, 0.2], [1.3, 0.4], [0.35, 1.1]]);
        let (lambda, mu) = (2.5, 0.7);
        for order in [1, 2] {
            let tab = Tabulation::new(order, 2 * order);
            let n = 2 * tab.n_basis;
            let mut grads = vec![[0.0; 2]; tab.n_points() * tab.n_basis];
            let mut k = vec![0.0; n * n];
            stiffness(&map, &tab, lambda, mu, &mut grads, &mut k);
            let mut quadrature = vec![0.0; n * n];
            for q in 0..tab.n_points() {
                let w = tab.weights[q] * map.det.abs();
                let g: Vec<Vector> = tab.grad(q).iter().map(|&gr| map.physical_gradient(gr)).collect();
                for (r, s) in (0..n).flat_map(|r| (0..n).map(move |s| (r, s))) {
                    let (gi, gj, a, b) = (g[r / 2], g[s / 2], r % 2, s % 2);
                    let delta = if a == b { dot(gi, gj) } else { 0.0 };
                    quadrature[r * n + s] += (lambda * gi[a] * gj[b] + mu * (delta + gi[b] * gj[a])) * w;
                }
            }
            let scale = quadrature.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
            for (r, s) in (0..n).flat_map(|r| (0..n).map(move |s| (r, s))) {
                assert!((k[r * n + s] - quadrature[r * n + s]).abs() < 1e-14 * scale, "P{order}: K[{r}][{s}]");
                assert_eq!(k[r * n + s], k[s * n + r], "P{order}: K is not symmetric");
            }
        }
    }

    #[test]
    fn principal_and_von_mises() {
        let s = [3.0, 1.0, 1.0, 0.0];
        let [s1, s2] = principal(s);
        assert!((s1 + s2 - 4.0).abs() < 1e-14 && (s1 * s2 - 2.0).abs() < 1e-14);
        // uniaxial stress: von Mises equals |σ|
        assert!((von_mises([5.0, 0.0, 0.0, 0.0]) - 5.0).abs() < 1e-14);
    }
}
