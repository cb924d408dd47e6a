//! Cell ↔ edge ↔ vertex adjacency and vertex patches.
//!
//! Edges are numbered once per mesh. Edge `e` joins vertex nodes `edges[e] = [a, b]` with
//! a < b. Local edge i of a cell is its facet i ([`CellType::facets`](crate::geometry::CellType::facets)),
//! opposite local vertex i. The patch ω_a of a vertex a is the set of cells that share it.

use super::Mesh;
use crate::geometry::{Segment, Vector};
use rayon::prelude::*;

/// Marker for "no neighbour" in [`Topology::edge_cells`].
pub const NONE: usize = usize::MAX;

/// Adjacency of a [`Mesh`].
#[derive(Debug, Clone)]
pub struct Topology {
    /// Vertex node pairs of every edge, smaller index first.
    pub edges: Vec<[usize; 2]>,
    /// Edges of each cell; local edge i is opposite local vertex i.
    pub cell_edges: Vec<[usize; 3]>,
    /// The one or two cells sharing each edge (second is [`NONE`] on the boundary).
    pub edge_cells: Vec<[usize; 2]>,
    /// Edge of each boundary facet.
    pub facet_edges: Vec<usize>,
    /// Vertex nodes (nodes that are a corner of some cell), in increasing order.
    pub vertices: Vec<usize>,
    /// CSR offsets into `patch_cells`, one range per entry of `vertices`.
    pub patch_offsets: Vec<usize>,
    /// Cells of each vertex patch.
    pub patch_cells: Vec<usize>,
}

impl Topology {
    /// Builds the adjacency of `mesh`. Panics if a boundary facet is not a cell edge.
    pub fn new(mesh: &Mesh) -> Self {
        // every (edge key, cell, local edge), sorted by key: equal keys are one edge
        let facets = mesh.cell_type().facets();
        let mut half: Vec<([usize; 2], usize, usize)> = (0..mesh.n_cells())
            .flat_map(|c| {
                let v = &mesh.cell(c)[..3];
                facets.iter().enumerate().map(move |(i, &[a, b])| (sorted([v[a], v[b]]), c, i))
            })
            .collect();
        // the keys are distinct: the same order on any number of threads
        half.par_sort_unstable();
        let mut edges: Vec<[usize; 2]> = Vec::with_capacity(half.len() / 2 + 1);
        let mut edge_cells: Vec<[usize; 2]> = Vec::with_capacity(half.len() / 2 + 1);
        let mut cell_edges = vec![[0; 3]; mesh.n_cells()];
        for (key, c, i) in half {
            if edges.last() == Some(&key) {
                edge_cells.last_mut().expect("edge just pushed")[1] = c;
            } else {
                edges.push(key);
                edge_cells.push([c, NONE]);
            }
            cell_edges[c][i] = edges.len() - 1;
        }
        let facet_edges = (0..mesh.n_facets())
            .into_par_iter()
            .map(|f| {
                let n = mesh.facet(f);
                edges.binary_search(&sorted([n[0], n[1]])).expect("boundary facet is not a cell edge")
            })
            .collect();
        let (vertices, patch_offsets, patch_cells) = patches(mesh);
        Topology { edges, cell_edges, edge_cells, facet_edges, vertices, patch_offsets, patch_cells }
    }

    pub fn n_edges(&self) -> usize {
        self.edges.len()
    }

    /// Cells of the patch of the `k`-th vertex (`self.vertices[k]`).
    pub fn patch(&self, k: usize) -> &[usize] {
        &self.patch_cells[self.patch_offsets[k]..self.patch_offsets[k + 1]]
    }

    /// True if edge `e` lies on the boundary (has one cell).
    pub fn is_boundary_edge(&self, e: usize) -> bool {
        self.edge_cells[e][1] == NONE
    }

    /// The cell owning boundary facet `f`.
    pub fn facet_cell(&self, f: usize) -> usize {
        self.edge_cells[self.facet_edges[f]][0]
    }

    /// Outward unit normal of boundary facet `f`: perpendicular to the facet, pointing away
    /// from the vertex of the owning cell that is not on the facet.
    pub fn outward_normal(&self, mesh: &Mesh, f: usize) -> Vector {
        let nodes = mesh.facet(f);
        let opposite = mesh.cell(self.facet_cell(f))[..3]
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
        let (v, e, c) = (topo.vertices.len(), topo.n_edges(), mesh.n_cells());
        assert_eq!(v as i64 - e as i64 + c as i64, 1); // Euler characteristic of a disk
        let boundary = (0..e).filter(|&k| topo.is_boundary_edge(k)).count();
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
