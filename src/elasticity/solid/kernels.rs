//! Element kernels of 3D elasticity on tetrahedra.
//!
//! Local dofs are ordered node by node, x, y, z: local dof 3i + a is component a of node i.
//! Kernels write into caller-owned buffers.

use crate::fem::tabulate::Tabulation;
use crate::fem::tetrahedron;
use crate::geometry::{sym_grad, trace, Point3, TetMap, Vector3};

/// Element stiffness K_{3i+a, 3j+b} = ∫_T ε(φ_i e_a) : C ε(φ_j e_b), row-major in `k`: with
/// D_kl = ∫_T ∂_k φ_i ∂_l φ_j, the 3 × 3 block of nodes (i, j) is
/// λ D_ab + μ (δ_ab tr D + D_ba). Computed for j ≥ i and mirrored, so K is exactly symmetric.
/// `tab` must integrate degree 2(p − 1) exactly; `grads` is scratch of length
/// n_points × n_basis.
pub fn stiffness(map: &TetMap, tab: &Tabulation<3>, lambda: f64, mu: f64, grads: &mut [Vector3], k: &mut [f64]) {
    let nb = tab.n_basis;
    let n = 3 * nb;
    for (g, &gr) in grads.iter_mut().zip(&tab.gradients) {
        *g = map.physical_gradient(gr);
    }
    for i in 0..nb {
        for j in i..nb {
            let mut d = [[0.0; 3]; 3];
            for (q, &wq) in tab.weights.iter().enumerate() {
                let (gi, gj, wq) = (grads[q * nb + i], grads[q * nb + j], wq * map.det.abs());
                for (k, row) in d.iter_mut().enumerate() {
                    for (l, dkl) in row.iter_mut().enumerate() {
                        *dkl += gi[k] * gj[l] * wq;
                    }
                }
            }
            let tr = d[0][0] + d[1][1] + d[2][2];
            for (a, b) in (0..3).flat_map(|a| (0..3).map(move |b| (a, b))) {
                let value = lambda * d[a][b] + mu * (if a == b { tr } else { 0.0 } + d[b][a]);
                let (r, s) = (3 * i + a, 3 * j + b);
                if i < j || r <= s {
                    k[r * n + s] = value;
                    k[s * n + r] = value;
                }
            }
        }
    }
}

/// Element load F_{3i+a} = ∫_T f_a φ_i of a body force `f(x)`, with the rule of `tab`.
pub fn body_load(map: &TetMap, tab: &Tabulation<3>, f: impl Fn(Point3) -> Vector3, out: &mut [f64]) {
    let nb = tab.n_basis;
    out[..3 * nb].fill(0.0);
    for q in 0..tab.n_points() {
        let w = tab.weights[q] * map.det.abs();
        let fx = f(map.to_physical(tab.points[q]));
        for (i, &phi) in tab.phi(q).iter().enumerate() {
            for a in 0..3 {
                out[3 * i + a] += fx[a] * phi * w;
            }
        }
    }
}

/// ∇u_h (∂_j u_i at `[i][j]`) at reference point `xi` of a cell with nodal displacements `u`,
/// as Σ_k (u_k − u_0) ⊗ ∇φ_k (Σ_k ∇φ_k = 0). `grads` is scratch of length n_basis.
pub fn displacement_gradient(
    map: &TetMap,
    order: usize,
    xi: Point3,
    u: &[Vector3],
    grads: &mut [Vector3],
) -> [Vector3; 3] {
    tetrahedron::gradients(order, xi, grads);
    let mut g = [[0.0; 3]; 3];
    for (gr, ui) in grads.iter().zip(u).skip(1) {
        let d = map.physical_gradient(*gr);
        for a in 0..3 {
            for b in 0..3 {
                g[a][b] += (ui[a] - u[0][a]) * d[b];
            }
        }
    }
    g
}

/// σ = λ tr ε I + 2μ ε of a displacement gradient, in Voigt order
/// [σ_xx, σ_yy, σ_zz, σ_yz, σ_xz, σ_xy].
pub fn stress(grad_u: [Vector3; 3], lambda: f64, mu: f64) -> [f64; 6] {
    let e = sym_grad(grad_u);
    let tr = trace(e);
    let normal = |i: usize| lambda * tr + 2.0 * mu * e[i][i];
    [normal(0), normal(1), normal(2), 2.0 * mu * e[1][2], 2.0 * mu * e[0][2], 2.0 * mu * e[0][1]]
}

/// The principal stresses σ₁ ≥ σ₂ ≥ σ₃ of a Voigt stress, by the trigonometric solution of
/// the characteristic cubic of the deviator (Smith 1961).
pub fn principal(s: [f64; 6]) -> [f64; 3] {
    let [xx, yy, zz, yz, xz, xy] = s;
    let mean = (xx + yy + zz) / 3.0;
    let (dx, dy, dz) = (xx - mean, yy - mean, zz - mean);
    // J₂ = ½ s:s and J₃ = det s of the deviator s
    let j2 = 0.5 * (dx * dx + dy * dy + dz * dz) + xy * xy + yz * yz + xz * xz;
    if j2 <= 0.0 {
        return [mean; 3];
    }
    let j3 = dx * (dy * dz - yz * yz) - xy * (xy * dz - yz * xz) + xz * (xy * yz - dy * xz);
    let r = (j2 / 3.0).sqrt();
    let cos3 = (j3 / (2.0 * r * r * r)).clamp(-1.0, 1.0);
    let theta = cos3.acos() / 3.0;
    let third = 2.0 * std::f64::consts::PI / 3.0;
    let mut p = [0.0, -third, third].map(|t| mean + 2.0 * r * (theta + t).cos());
    p.sort_by(|a, b| b.total_cmp(a));
    p
}

/// von Mises stress √(3 J₂) of a Voigt stress.
pub fn von_mises(s: [f64; 6]) -> f64 {
    let [xx, yy, zz, yz, xz, xy] = s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2)) + 3.0 * (yz * yz + xz * xz + xy * xy)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    const CELL: [Point3; 4] = [[0.1, 0.2, -0.3], [1.3, 0.4, 0.1], [0.35, 1.1, 0.2], [0.2, 0.3, 0.9]];

    /// Source: ε(r) = 0 for the six rigid motions r = e_a and x ↦ ω × x. Goal: K r = 0 to
    /// round-off, and K is exactly symmetric. Parameters: a skewed cell, P1 and P2, λ = 2, μ = 1.
    #[test]
    fn stiffness_annihilates_the_six_rigid_motions() {
        let map = TetMap::new(CELL);
        for order in [1, 2] {
            let tab = Tabulation::tetrahedron(order, 2 * order - 2);
            let nb = tab.n_basis;
            let mut grads = vec![[0.0; 3]; tab.n_points() * nb];
            let mut k = vec![0.0; 9 * nb * nb];
            stiffness(&map, &tab, 2.0, 1.0, &mut grads, &mut k);
            let nodes: Vec<Point3> = tetrahedron::reference_nodes(order).iter().map(|&x| map.to_physical(x)).collect();
            let rigid: [fn(Point3) -> Vector3; 6] = [
                |_| [1.0, 0.0, 0.0],
                |_| [0.0, 1.0, 0.0],
                |_| [0.0, 0.0, 1.0],
                |x| [0.0, -x[2], x[1]],
                |x| [x[2], 0.0, -x[0]],
                |x| [-x[1], x[0], 0.0],
            ];
            let n = 3 * nb;
            for r in rigid {
                let v: Vec<f64> = nodes.iter().flat_map(|&x| r(x)).collect();
                for row in 0..n {
                    let kv: f64 = (0..n).map(|j| k[row * n + j] * v[j]).sum();
                    assert!(kv.abs() < 1e-12, "P{order}: K r = {kv}");
                }
            }
            for (r, s) in (0..n).flat_map(|r| (0..n).map(move |s| (r, s))) {
                assert_eq!(k[r * n + s], k[s * n + r]);
            }
            // a uniaxial strain u = (x, 0, 0): x K x = ∫ (λ + 2μ) = (λ + 2μ) |T|
            let v: Vec<f64> = nodes.iter().flat_map(|&x| [x[0], 0.0, 0.0]).collect();
            let energy: f64 = (0..n).map(|r| v[r] * (0..n).map(|s| k[r * n + s] * v[s]).sum::<f64>()).sum();
            assert!((energy - 4.0 * map.volume()).abs() < 1e-13, "P{order}: {energy}");
        }
    }

    #[test]
    fn principal_stresses_and_von_mises() {
        let s = [3.0, -1.0, 2.0, 0.5, -0.7, 1.2];
        let p = principal(s);
        assert!(p[0] >= p[1] && p[1] >= p[2]);
        // invariants: tr and the second invariant agree
        assert!((p.iter().sum::<f64>() - 4.0).abs() < 1e-13);
        let i2 = |[xx, yy, zz, yz, xz, xy]: [f64; 6]| xx * yy + yy * zz + zz * xx - yz * yz - xz * xz - xy * xy;
        assert!((p[0] * p[1] + p[1] * p[2] + p[2] * p[0] - i2(s)).abs() < 1e-12);
        let vm = von_mises(s);
        let from_principal = (0.5 * ((p[0] - p[1]).powi(2) + (p[1] - p[2]).powi(2) + (p[2] - p[0]).powi(2))).sqrt();
        assert!((vm - from_principal).abs() < 1e-12);
        assert_eq!(principal([2.0, 2.0, 2.0, 0.0, 0.0, 0.0]), [2.0; 3]);
    }
}
