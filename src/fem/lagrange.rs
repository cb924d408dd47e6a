//! Lagrange P1 and P2 bases on the reference triangle `(0,0), (1,0), (0,1)` and on the
//! reference segment `[0, 1]`.
//!
//! Triangle node order (gmsh/VTK): vertices 0, 1, 2, then the midpoints of edges 01, 12, 20.
//! With barycentric coordinates `λ0 = 1 − ξ − η`, `λ1 = ξ`, `λ2 = η`:
//!
//! * P1: `φᵢ = λᵢ`;
//! * P2: vertex `φᵢ = λᵢ (2λᵢ − 1)`, midpoint of edge `ij`: `φ = 4 λᵢ λⱼ`.
//!
//! Segment node order: end 0, end 1, then the midpoint (as the mesh's boundary facets).
//!
//! All evaluators write into caller-owned buffers of length at least [`n_basis`] and never
//! allocate.

use crate::geometry::{Point, Vector};

/// Edges `(i, j)` carrying the P2 midpoint nodes 3, 4, 5.
const EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// Reference gradients of the barycentric coordinates `λ0, λ1, λ2`.
const GRAD_LAMBDA: [Vector; 3] = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];

#[rustfmt::skip]
const NODES_P2: [Point; 6] = [
    [0.0, 0.0], [1.0, 0.0], [0.0, 1.0],
    [0.5, 0.0], [0.5, 0.5], [0.0, 0.5],
];

/// Number of basis functions on the triangle: 3 for P1, 6 for P2.
pub fn n_basis(order: usize) -> usize {
    match order {
        1 => 3,
        2 => 6,
        _ => panic!("Lagrange order {order} not supported (1 or 2)"),
    }
}

/// Reference coordinates of the nodes, in basis order.
pub fn reference_nodes(order: usize) -> &'static [Point] {
    &NODES_P2[..n_basis(order)]
}

/// The reference coordinates of vertex `node` of the cell with nodes `cell`.
pub fn reference_vertex(cell: &[usize], node: usize) -> Point {
    reference_nodes(1)[cell[..3].iter().position(|&v| v == node).expect("the vertex belongs to the cell")]
}

/// Barycentric coordinates `[1 − ξ − η, ξ, η]`.
fn barycentric(xi: Point) -> [f64; 3] {
    [1.0 - xi[0] - xi[1], xi[0], xi[1]]
}

/// Basis values `φᵢ(ξ)` written to `out[..n_basis(order)]`.
pub fn values(order: usize, xi: Point, out: &mut [f64]) {
    let l = barycentric(xi);
    match order {
        1 => out[..3].copy_from_slice(&l),
        2 => {
            for i in 0..3 {
                out[i] = l[i] * (2.0 * l[i] - 1.0);
            }
            for (k, &(i, j)) in EDGES.iter().enumerate() {
                out[3 + k] = 4.0 * l[i] * l[j];
            }
        }
        _ => panic!("Lagrange order {order} not supported (1 or 2)"),
    }
}

/// Reference gradients `∇̂φᵢ(ξ)` written to `out[..n_basis(order)]`.
///
/// P2: vertex `(4λᵢ − 1) ∇λᵢ`, midpoint `4 (λⱼ ∇λᵢ + λᵢ ∇λⱼ)`.
pub fn gradients(order: usize, xi: Point, out: &mut [Vector]) {
    let g = GRAD_LAMBDA;
    match order {
        1 => out[..3].copy_from_slice(&g),
        2 => {
            let l = barycentric(xi);
            for i in 0..3 {
                let c = 4.0 * l[i] - 1.0;
                out[i] = [c * g[i][0], c * g[i][1]];
            }
            for (k, &(i, j)) in EDGES.iter().enumerate() {
                out[3 + k] = [4.0 * (l[j] * g[i][0] + l[i] * g[j][0]), 4.0 * (l[j] * g[i][1] + l[i] * g[j][1])];
            }
        }
        _ => panic!("Lagrange order {order} not supported (1 or 2)"),
    }
}

/// Segment basis values at `s ∈ [0, 1]`, written to `out[..order + 1]`.
///
/// P1: `[1 − s, s]`; P2 (nodes 0, 1, 1/2): `[(1 − s)(1 − 2s), s (2s − 1), 4 s (1 − s)]`.
pub fn segment_values(order: usize, s: f64, out: &mut [f64]) {
    match order {
        1 => out[..2].copy_from_slice(&[1.0 - s, s]),
        2 => out[..3].copy_from_slice(&[(1.0 - s) * (1.0 - 2.0 * s), s * (2.0 * s - 1.0), 4.0 * s * (1.0 - s)]),
        _ => panic!("Lagrange order {order} not supported (1 or 2)"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_nodality_and_partition_of_unity() {
        let nodes = [0.0, 1.0, 0.5];
        let mut phi = [0.0; 3];
        for order in 1..=2 {
            for (j, &s) in nodes[..order + 1].iter().enumerate() {
                segment_values(order, s, &mut phi);
                for (i, &p) in phi[..order + 1].iter().enumerate() {
                    assert_eq!(p, if i == j { 1.0 } else { 0.0 });
                }
            }
            segment_values(order, 0.37, &mut phi);
            assert!((phi[..order + 1].iter().sum::<f64>() - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn p2_reproduces_quadratics() {
        let f = |x: Point| 1.0 + 2.0 * x[0] - x[1] + 3.0 * x[0] * x[1] - x[0] * x[0];
        let xi = [0.21, 0.43];
        let mut phi = [0.0; 6];
        values(2, xi, &mut phi);
        let interp: f64 = reference_nodes(2).iter().zip(phi).map(|(&n, p)| p * f(n)).sum();
        assert!((interp - f(xi)).abs() < 1e-14);
    }
}
