//! Stresses of a displacement field, for output.

use super::kernels::{displacement_gradient, stress};
use super::problem::Problem;
use crate::fem::lagrange;
use crate::geometry::{AffineMap, Vector};

/// Cell mean of σ(u_h) as [σ_xx, σ_yy, σ_xy, σ_zz]. For p ≤ 2, σ(u_h) is affine on each
/// cell, so its mean is its value at the centroid.
pub fn cell_mean_stress(problem: &Problem, u: &[Vector]) -> Vec<[f64; 4]> {
    let mesh = &problem.mesh;
    let mut grads = vec![[0.0; 2]; lagrange::n_basis(mesh.order)];
    let mut nodal = Vec::with_capacity(grads.len());
    (0..mesh.n_cells())
        .map(|c| {
            let map = AffineMap::new(mesh.cell_vertices(c));
            nodal.clear();
            nodal.extend(mesh.cell(c).iter().map(|&n| u[n]));
            let g = displacement_gradient(&map, mesh.order, [1.0 / 3.0; 2], &nodal, &mut grads);
            let (lambda, mu) = problem.materials[c].lame();
            stress(g, lambda, mu)
        })
        .collect()
}
