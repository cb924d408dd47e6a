//! The tetrahedral mesh of a solid: its cells' vertices, volumes and sizes, and their
//! orientation.

use super::Mesh;
use crate::geometry::tetrahedron::{signed_volume, triangle_area_vector, EDGES, FACES};
use crate::geometry::{distance3, norm3, Point3};
use std::collections::HashMap;

impl Mesh<3> {
    /// Vertex coordinates of cell `c`.
    pub fn cell_vertices(&self, c: usize) -> [Point3; 4] {
        let n = self.cell(c);
        std::array::from_fn(|k| self.points[n[k]])
    }

    /// Vertex coordinates of boundary facet `f`.
    pub fn facet_vertices(&self, f: usize) -> [Point3; 3] {
        let n = self.facet(f);
        std::array::from_fn(|k| self.points[n[k]])
    }

    /// Whether each boundary facet is a face of two cells (an interface inside the solid)
    /// rather than of one.
    pub fn interior_facets(&self) -> Vec<bool> {
        let key = |mut nodes: [usize; 3]| {
            nodes.sort_unstable();
            nodes
        };
        let mut cells: HashMap<[usize; 3], usize> =
            (0..self.n_facets()).map(|f| (key(std::array::from_fn(|k| self.facet(f)[k])), 0)).collect();
        for c in 0..self.n_cells() {
            let cell = self.cell(c);
            for face in FACES {
                if let Some(count) = cells.get_mut(&key(face.map(|k| cell[k]))) {
                    *count += 1;
                }
            }
        }
        (0..self.n_facets()).map(|f| cells[&key(std::array::from_fn(|k| self.facet(f)[k]))] > 1).collect()
    }

    /// Total area of the facets carrying physical tag `tag`.
    pub fn boundary_area(&self, tag: i32) -> f64 {
        self.facets_tagged(&[tag]).map(|f| norm3(triangle_area_vector(self.facet_vertices(f)))).sum()
    }

    /// Signed volume of cell `c` (positive for a positively oriented cell).
    pub fn cell_volume(&self, c: usize) -> f64 {
        signed_volume(self.cell_vertices(c))
    }

    /// Diameter h_T of cell `c` (its longest edge).
    pub fn cell_diameter(&self, c: usize) -> f64 {
        let v = self.cell_vertices(c);
        EDGES.iter().map(|&[i, j]| distance3(v[i], v[j])).fold(0.0, f64::max)
    }

    /// Reorders every cell to a positive orientation (gmsh may hand out either).
    pub fn orient_positively(&mut self) {
        let n = self.nodes_per_cell();
        for c in 0..self.n_cells() {
            if self.cell_volume(c) < 0.0 {
                let cell = &mut self.cell_nodes[c * n..(c + 1) * n];
                // swap vertices 1 and 2: edges 01 ↔ 20 and 31 ↔ 32 swap, 12 and 30 stay
                cell.swap(1, 2);
                if n == 10 {
                    cell.swap(4, 6);
                    cell.swap(8, 9);
                }
            }
        }
    }
}
