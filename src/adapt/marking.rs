//! Turning the local estimators η_T into target mesh sizes: by marking (the marked cells
//! get half their size) or by equidistribution (every cell gets the size that would bring its
//! η_T to a common target).

use crate::geometry::{bounding_box, distance};
use crate::mesh::Mesh;
use serde::{Deserialize, Serialize};

/// How the next sizes follow from η_T and the fraction θ (never below a smallest size, at
/// least [`smallest_size`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Marking {
    /// Dörfler bulk criterion: the fewest cells with Σ_marked η_T² ≥ θ Σ_T η_T² get h_T/2.
    Dorfler,
    /// Maximum strategy: every T with η_T ≥ θ max_T η_T gets h_T/2.
    Maximum,
    /// Equidistribution: h_T (η_target/η_T)^{1/p} within [h_T/4, 2 h_T], with
    /// η_target = max(θ η_tot, tol)/√N over N cells.
    Equidistribution,
}

impl Marking {
    /// Target sizes on `mesh` for the local estimators `eta`, none below `floor`; `tol` is
    /// the absolute tolerance on η_tot, if any (equidistribution does not aim below it).
    pub fn target_sizes(self, theta: f64, eta: &[f64], mesh: &Mesh, tol: Option<f64>, floor: f64) -> Vec<f64> {
        let sizes = match self {
            Marking::Dorfler => halved(mesh, &dorfler(eta, theta)),
            Marking::Maximum => halved(mesh, &maximum(eta, theta)),
            Marking::Equidistribution => equidistributed(theta, eta, mesh, tol),
        };
        sizes.into_iter().map(|h: f64| h.max(floor)).collect()
    }
}

/// The smallest target size on `mesh` whatever the mesher allows: `SMALLEST_SIZE` times the
/// domain's extent.
pub fn smallest_size(mesh: &Mesh) -> f64 {
    SMALLEST_SIZE * extent(mesh)
}

/// No target size is below this fraction of the domain's extent, where gmsh's own
/// tolerances start to merge points. (A strong singularity asks for small cells: at the
/// r^{1/2} corner of Scene A, P2 equidistribution shrinks the corner cell by 4 per step.)
const SMALLEST_SIZE: f64 = 1e-8;

/// Diagonal of the bounding box of the mesh.
fn extent(mesh: &Mesh) -> f64 {
    let [lo, hi] = bounding_box(mesh.points.iter().copied());
    distance(lo, hi)
}

/// h_T/2 on the marked cells, h_T elsewhere.
fn halved(mesh: &Mesh, marked: &[bool]) -> Vec<f64> {
    (0..mesh.n_cells()).map(|c| if marked[c] { 0.5 } else { 1.0 } * cell_size(mesh, c)).collect()
}

fn dorfler(eta: &[f64], theta: f64) -> Vec<bool> {
    let mut order: Vec<usize> = (0..eta.len()).collect();
    order.sort_unstable_by(|&a, &b| eta[b].total_cmp(&eta[a]));
    let total: f64 = eta.iter().map(|e| e * e).sum();
    let mut marked = vec![false; eta.len()];
    let mut sum = 0.0;
    for c in order {
        if sum >= theta * total {
            break;
        }
        marked[c] = true;
        sum += eta[c] * eta[c];
    }
    marked
}

fn maximum(eta: &[f64], theta: f64) -> Vec<bool> {
    let max = eta.iter().copied().fold(0.0, f64::max);
    eta.iter().map(|&e| e >= theta * max).collect()
}

/// h_T (η_target/η_T)^{1/p} clipped to [h_T/4, 2 h_T]. On a mesh where every η_T equals
/// η_tot/√N, the sizes shrink by θ^{1/p} and, with η_T ~ h_T^{p+1}, η_tot by θ.
fn equidistributed(theta: f64, eta: &[f64], mesh: &Mesh, tol: Option<f64>) -> Vec<f64> {
    let total = eta.iter().map(|e| e * e).sum::<f64>().sqrt();
    let target = (theta * total).max(tol.unwrap_or(0.0)) / (eta.len() as f64).sqrt();
    let exponent = 1.0 / mesh.order as f64;
    eta.iter()
        .enumerate()
        .map(|(c, &e)| {
            let ratio = if e > 0.0 { (target / e).powf(exponent) } else { f64::INFINITY };
            ratio.clamp(0.25, 2.0) * cell_size(mesh, c)
        })
        .collect()
}

/// Edge of the equilateral triangle of the same area, √(4|T|/√3): the size gmsh aims at
/// when it meshes T (the longest edge would overstate it and coarsen the mesh step by step).
pub fn cell_size(mesh: &Mesh, c: usize) -> f64 {
    (4.0 * mesh.cell_area(c) / 3f64.sqrt()).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dorfler_marks_the_fewest_largest_cells() {
        let eta = [1.0, 3.0, 2.0, 0.5];
        // Σ η² = 14.25: θ = 0.5 needs 7.125, and 3² = 9 is enough
        assert_eq!(dorfler(&eta, 0.5), [false, true, false, false]);
        // θ = 0.9 needs 12.825: 9 + 4 = 13
        assert_eq!(dorfler(&eta, 0.9), [false, true, true, false]);
        assert_eq!(dorfler(&eta, 1.0), [true; 4]);
    }

    #[test]
    fn equidistribution_scales_each_cell_by_its_own_estimator() {
        let size = |order, theta, eta: &[f64], tol| {
            let mesh = crate::mesh::structured::unit_square(4, order);
            let h = cell_size(&mesh, 0);
            Marking::Equidistribution
                .target_sizes(theta, eta, &mesh, tol, 0.0)
                .iter()
                .map(|s| s / h)
                .collect::<Vec<_>>()
        };
        let close = |sizes: &[f64], expected: f64| sizes.iter().all(|s| (s - expected).abs() < 1e-12);
        let n = 32;
        // equal η_T: every size shrinks by θ^{1/p}
        assert!(close(&size(1, 0.5, &vec![1.0; n], None), 0.5));
        assert!(close(&size(2, 0.5, &vec![1.0; n], None), 0.5f64.sqrt()));
        // a tolerance above θ η_tot is the target instead
        assert!(close(&size(1, 0.5, &vec![1.0; n], Some(1.5 * (n as f64).sqrt())), 1.5));
        // the clip: a dominant cell gets h/4, cells without error 2h
        let mut eta = vec![0.0; n];
        eta[3] = 1.0;
        let sizes = size(1, 0.5, &eta, None);
        assert!(close(&sizes[3..4], 0.25) && close(&sizes[..3], 2.0), "{sizes:?}");
    }

    #[test]
    fn maximum_marks_cells_near_the_largest() {
        assert_eq!(maximum(&[1.0, 3.0, 2.0, 0.5], 0.5), [false, true, true, false]);
    }
}
