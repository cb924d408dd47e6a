//! Error norms of a vector Lagrange field against an exact solution.

use super::tabulate::Tabulation;
use crate::geometry::{ddot, sub, AffineMap, Point, Tensor, Vector, D};
use crate::mesh::Mesh;

/// L² norm and H¹ seminorm of u − u_h, with u_h given by its nodal values `u_h[node]`:
/// ‖u − u_h‖²_{L²} = Σ_T ∫_T |u − u_h|², |u − u_h|²_{H¹} = Σ_T ∫_T |∇u − ∇u_h|².
/// `u` returns the exact value and `grad_u` the exact gradient (∂_j u_i at `[i][j]`).
/// Integrals use a rule exact to degree 2p + 4.
pub fn errors(
    mesh: &Mesh,
    u_h: &[Vector],
    u: impl Fn(Point) -> Vector,
    grad_u: impl Fn(Point) -> Tensor,
) -> (f64, f64) {
    let tab = Tabulation::new(mesh.order, 2 * mesh.order + 4);
    let mut l2 = 0.0;
    let mut h1 = 0.0;
    for c in 0..mesh.n_cells() {
        let map = AffineMap::new(mesh.cell_vertices(c));
        let nodes = mesh.cell(c);
        for q in 0..tab.n_points() {
            let x = map.to_physical(tab.points[q]);
            let w = tab.weights[q] * map.det.abs();
            let (mut v, mut g) = ([0.0; D], [[0.0; D]; D]);
            for (i, &n) in nodes.iter().enumerate() {
                let grad = map.physical_gradient(tab.grad(q)[i]);
                for a in 0..D {
                    v[a] += tab.phi(q)[i] * u_h[n][a];
                    for b in 0..D {
                        g[a][b] += grad[b] * u_h[n][a];
                    }
                }
            }
            let (ue, ge) = (u(x), grad_u(x));
            l2 += w * (0..D).map(|a| (ue[a] - v[a]).powi(2)).sum::<f64>();
            let e: Tensor = std::array::from_fn(|a| sub(ge[a], g[a]));
            h1 += w * ddot(e, e);
        }
    }
    (l2.sqrt(), h1.sqrt())
}
