//! Lagrange P1 and P2 bases on the reference tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1).
//!
//! Node order (gmsh): vertices 0–3, then the midpoints of the edges of
//! [`EDGES`]: 01, 12, 20, 30, 32, 31. With barycentric coordinates λ0 = 1 − ξ − η − ζ,
//! λ1 = ξ, λ2 = η, λ3 = ζ:
//!
//! * P1: φᵢ = λᵢ;
//! * P2: vertex φᵢ = λᵢ (2λᵢ − 1), midpoint of edge ij: φ = 4 λᵢ λⱼ.
//!
//! Evaluators write into caller-owned buffers of length at least [`n_basis`].

use crate::geometry::tetrahedron::EDGES;
use crate::geometry::{Point3, Vector3};

/// Reference gradients of the barycentric coordinates λ0 … λ3.
const GRAD_LAMBDA: [Vector3; 4] = [[-1.0, -1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// Number of basis functions: 4 for P1, 10 for P2.
pub fn n_basis(order: usize) -> usize {
    match order {
        1 => 4,
        2 => 10,
        _ => panic!("Lagrange order {order} not supported (1 or 2)"),
    }
}

/// Reference coordinates of the nodes, in basis order.
pub fn reference_nodes(order: usize) -> Vec<Point3> {
    let vertices: [Point3; 4] = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let midpoints = EDGES.map(|[i, j]| std::array::from_fn(|r| 0.5 * (vertices[i][r] + vertices[j][r])));
    vertices.into_iter().chain(midpoints).take(n_basis(order)).collect()
}

fn barycentric(xi: Point3) -> [f64; 4] {
    [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]]
}

/// Basis values φᵢ(ξ) written to `out[..n_basis(order)]`.
pub fn values(order: usize, xi: Point3, out: &mut [f64]) {
    let l = barycentric(xi);
    match order {
        1 => out[..4].copy_from_slice(&l),
        2 => {
            for i in 0..4 {
                out[i] = l[i] * (2.0 * l[i] - 1.0);
            }
            for (k, &[i, j]) in EDGES.iter().enumerate() {
                out[4 + k] = 4.0 * l[i] * l[j];
            }
        }
        _ => panic!("Lagrange order {order} not supported (1 or 2)"),
    }
}

/// Reference gradients ∇̂φᵢ(ξ) written to `out[..n_basis(order)]`.
///
/// P2: vertex (4λᵢ − 1) ∇λᵢ, midpoint 4 (λⱼ ∇λᵢ + λᵢ ∇λⱼ).
pub fn gradients(order: usize, xi: Point3, out: &mut [Vector3]) {
    let g = GRAD_LAMBDA;
    match order {
        1 => out[..4].copy_from_slice(&g),
        2 => {
            let l = barycentric(xi);
            for i in 0..4 {
                out[i] = g[i].map(|x| (4.0 * l[i] - 1.0) * x);
            }
            for (k, &[i, j]) in EDGES.iter().enumerate() {
                out[4 + k] = std::array::from_fn(|r| 4.0 * (l[j] * g[i][r] + l[i] * g[j][r]));
            }
        }
        _ => panic!("Lagrange order {order} not supported (1 or 2)"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_basis_is_nodal_and_reproduces_quadratics_with_their_gradients() {
        let f = |x: Point3| 1.0 + 2.0 * x[0] - x[1] + 0.5 * x[2] + 3.0 * x[0] * x[2] - x[1] * x[1] + x[1] * x[2];
        let grad_f = |x: Point3| [2.0 + 3.0 * x[2], -1.0 - 2.0 * x[1] + x[2], 0.5 + 3.0 * x[0] + x[1]];
        for order in 1..=2 {
            let nodes = reference_nodes(order);
            let mut phi = [0.0; 10];
            for (j, &p) in nodes.iter().enumerate() {
                values(order, p, &mut phi);
                for (i, &v) in phi[..n_basis(order)].iter().enumerate() {
                    assert!((v - if i == j { 1.0 } else { 0.0 }).abs() < 1e-15, "P{order}: φ{i} at node {j}");
                }
            }
            let xi = [0.21, 0.13, 0.34];
            values(order, xi, &mut phi);
            assert!((phi[..n_basis(order)].iter().sum::<f64>() - 1.0).abs() < 1e-15);
            if order == 2 {
                let mut grads = [[0.0; 3]; 10];
                gradients(2, xi, &mut grads);
                let interp: f64 = nodes.iter().zip(phi).map(|(&n, p)| p * f(n)).sum();
                assert!((interp - f(xi)).abs() < 1e-14);
                for r in 0..3 {
                    let d: f64 = nodes.iter().zip(grads).map(|(&n, g)| g[r] * f(n)).sum();
                    assert!((d - grad_f(xi)[r]).abs() < 1e-13, "∂{r}: {d} against {}", grad_f(xi)[r]);
                }
            }
        }
    }
}
