//! Marking cells for refinement and turning the marks into target mesh sizes.

use crate::mesh::Mesh;
use serde::{Deserialize, Serialize};

/// Which cells to refine, from the local estimators η_T and a fraction θ.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Marking {
    /// Dörfler bulk criterion: the fewest cells with Σ_marked η_T² ≥ θ Σ_T η_T².
    Dorfler,
    /// Maximum strategy: every T with η_T ≥ θ max_T η_T.
    Maximum,
}

impl Marking {
    /// The marked cells for local estimators `eta`.
    pub fn mark(self, theta: f64, eta: &[f64]) -> Vec<bool> {
        match self {
            Marking::Dorfler => dorfler(eta, theta),
            Marking::Maximum => {
                let max = eta.iter().copied().fold(0.0, f64::max);
                eta.iter().map(|&e| e >= theta * max).collect()
            }
        }
    }
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

/// Edge of the equilateral triangle of the same area, √(4|T|/√3): the size gmsh aims at
/// when it meshes T (the longest edge would overstate it and coarsen the mesh step by step).
pub fn cell_size(mesh: &Mesh, c: usize) -> f64 {
    (4.0 * mesh.cell_area(c) / 3f64.sqrt()).sqrt()
}

/// Target sizes: h_T / 2 on marked cells, h_T elsewhere.
pub fn target_sizes(mesh: &Mesh, marked: &[bool]) -> Vec<f64> {
    (0..mesh.n_cells()).map(|c| if marked[c] { 0.5 } else { 1.0 } * cell_size(mesh, c)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dorfler_marks_the_fewest_largest_cells() {
        let eta = [1.0, 3.0, 2.0, 0.5];
        // Σ η² = 14.25: θ = 0.5 needs 7.125, and 3² = 9 is enough
        assert_eq!(Marking::Dorfler.mark(0.5, &eta), [false, true, false, false]);
        // θ = 0.9 needs 12.825: 9 + 4 = 13
        assert_eq!(Marking::Dorfler.mark(0.9, &eta), [false, true, true, false]);
        assert_eq!(Marking::Dorfler.mark(1.0, &eta), [true; 4]);
    }

    #[test]
    fn maximum_marks_cells_near_the_largest() {
        assert_eq!(Marking::Maximum.mark(0.5, &[1.0, 3.0, 2.0, 0.5]), [false, true, true, false]);
    }
}
