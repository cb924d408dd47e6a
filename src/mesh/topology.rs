//! Cell ↔ facet ↔ vertex adjacency and vertex patches.
//!
//! Facets (where fluxes cross, contact faces lie and patches end) are numbered once per mesh.
//! Facet `e` has vertex nodes `facets[e] = [a, b]` with a < b; local facet i of a cell is
//! [`CellType::facets`](crate::geometry::CellType::facets)\[i\], opposite local vertex i. The
//! mesh's own facets ([`Mesh::facet`]: the line elements of its physical curves) map to these
//! by [`Topology::tagged_facet`]. The edges, where P2's midpoint nodes sit, are the facets in
//! 2D; a tetrahedral mesh keeps them apart. The patch ω_a of a vertex a is the set of cells
//! that share it.

use super::Mesh;
use crate::geometry::{Segment, Vector};
use rayon::prelude::*;

/// Marker for "no neighbour" in [`Topology::facet_cells`].
pub const NONE: usize = usize::MAX;

/// Adjacency of a [`Mesh`].
#[derive(Debug, Clone)]
pub struct Topology {
    /// Vertex nodes of every facet, smaller index first.
    pub facets: Vec<[usize; 2]>,
    /// Facets of each cell; local facet i is opposite local vertex i.
    pub cell_facets: Vec<[usize; 3]>,
    /// The one or two cells sharing each facet (second is [`NONE`] on the boundary).
    pub facet_cells: Vec<[usize; 2]>,
    /// The facet of each of the mesh's facets ([`Mesh::facet`]).
    pub tagged_facet: Vec<usize>,
    /// Vertex nodes (nodes that are a corner of some cell), in increasing order.
    pub vertices: Vec<usize>,
    /// CSR offsets into `patch_cells`, one range per entry of `vertices`.
    pub patch_offsets: Vec<usize>,
    /// Cells of each vertex patch.
    pub patch_cells: Vec<usize>,
}

impl Topology {
    /// Builds the adjacency of `mesh`. Panics if one of the mesh's facets is not a cell's.
    pub fn new(mesh: &Mesh) -> Self {
        // every (facet key, cell, local facet), sorted by key: equal keys are one facet
        let local = mesh.cell_type().facets();
        let mut half: Vec<([usize; 2], usize, usize)> = (0..mesh.n_cells())
            .flat_map(|c| {
                let v = &mesh.cell(c)[..3];
                local.iter().enumerate().map(move |(i, &[a, b])| (sorted([v[a], v[b]]), c, i))
            })
            .collect();
        // the keys are distinct: the same order on any number of threads
        half.par_sort_unstable();
        let mut facets: Vec<[usize; 2]> = Vec::with_capacity(half.len() / 2 + 1);
        let mut facet_cells: Vec<[usize; 2]> = Vec::with_capacity(half.len() / 2 + 1);
        let mut cell_facets = vec![[0; 3]; mesh.n_cells()];
        for (key, c, i) in half {
            if facets.last() == Some(&key) {
                facet_cells.last_mut().expect("facet just pushed")[1] = c;
            } else {
                facets.push(key);
                facet_cells.push([c, NONE]);
            }
            cell_facets[c][i] = facets.len() - 1;
        }
        let tagged_facet = (0..mesh.n_facets())
            .into_par_iter()
            .map(|f| {
                let n = mesh.facet(f);
                facets.binary_search(&sorted([n[0], n[1]])).expect("a facet of the mesh is not a cell's")
            })
            .collect();
        let (vertices, patch_offsets, patch_cells) = patches(mesh);
        Topology { facets, cell_facets, facet_cells, tagged_facet, vertices, patch_offsets, patch_cells }
    }

    pub fn n_facets(&self) -> usize {
        self.facets.len()
    }

    /// The number of edges, where P2's midpoint nodes sit: in 2D, each edge is a facet.
    pub fn n_edges(&self) -> usize {
        self.facets.len()
    }

    /// Cells of the patch of the `k`-th vertex (`self.vertices[k]`).
    pub fn patch(&self, k: usize) -> &[usize] {
        &self.patch_cells[self.patch_offsets[k]..self.patch_offsets[k + 1]]
    }

    /// True if facet `e` lies on the boundary (has one cell).
    pub fn is_boundary_facet(&self, e: usize) -> bool {
        self.facet_cells[e][1] == NONE
    }

    /// The cell owning the mesh's facet `f` (the first of two on an interior curve).
    pub fn tagged_cell(&self, f: usize) -> usize {
        self.facet_cells[self.tagged_facet[f]][0]
    }

    /// Outward unit normal of the mesh's facet `f`: perpendicular to the facet, pointing away
    /// from the vertex of the owning cell that is not on the facet.
    pub fn outward_normal(&self, mesh: &Mesh, f: usize) -> Vector {
        let nodes = mesh.facet(f);
        let opposite = mesh.cell(self.tagged_cell(f))[..3]
            .iter()
            .find(|&&v| v != nodes[0] && v != nodes[1])
            .map(|&v| mesh.points[v])
            .expect("a triangle has a vertex off each edge");
        Segment::new(mesh.points[nodes[0]], mesh.points[nodes[1]]).outward_normal(opposite)
    }
}

fn sorted([a, b]: [usize; 2]) -> [usize; 2] {
    [a.min(b), a.max(b)]
}

/// Vertex list and the CSR arrays of vertex patches.
fn patches(mesh: &Mesh) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let mut count = vec![0usize; mesh.n_points()];
    for c in 0..mesh.n_cells() {
        for &v in &mesh.cell(c)[..3] {
            count[v] += 1;
        }
    }
    let vertices: Vec<usize> = (0..mesh.n_points()).filter(|&v| count[v] > 0).collect();
    let mut slot = vec![NONE; mesh.n_points()];
    let mut offsets = vec![0; vertices.len() + 1];
    for (k, &v) in vertices.iter().enumerate() {
        slot[v] = k;
        offsets[k + 1] = offsets[k] + count[v];
    }
    let mut fill = offsets.clone();
    let mut cells = vec![0; offsets[vertices.len()]];
    for c in 0..mesh.n_cells() {
        for &v in &mesh.cell(c)[..3] {
            let k = slot[v];
            cells[fill[k]] = c;
            fill[k] += 1;
        }
    }
    (vertices, offsets, cells)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::unit_square;

    #[test]
    fn euler_and_patches() {
        let mesh = unit_square(3, 2);
        let topo = Topology::new(&mesh);
        let (v, e, c) = (topo.vertices.len(), topo.n_facets(), mesh.n_cells());
        assert_eq!(v as i64 - e as i64 + c as i64, 1); // Euler characteristic of a disk
        let boundary = (0..e).filter(|&k| topo.is_boundary_facet(k)).count();
        assert_eq!(boundary, mesh.n_facets());
        assert_eq!(topo.patch_cells.len(), 3 * c);
        // the centre vertex (1,1)/3 of a 3×3 grid lies in 6 cells
        let centre = topo.vertices.iter().position(|&p| p == 5).unwrap();
        assert_eq!(topo.patch(centre).len(), 6);
        // outward normals of the unit square's sides
        for f in 0..mesh.n_facets() {
            let n = topo.outward_normal(&mesh, f);
            let m = mesh.points[mesh.facet(f)[0]];
            let expected = match mesh.facet_tags[f] {
                1 => [0.0, -1.0],
                2 => [1.0, 0.0],
                3 => [0.0, 1.0],
                _ => [-1.0, 0.0],
            };
            assert_eq!(n, expected, "facet at {m:?}");
        }
    }
}
