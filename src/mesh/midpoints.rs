//! Edge midpoint nodes, the degree-2 mesh they make of a degree-1 mesh, and the degree-1 mesh
//! of the vertices of a degree-2 mesh.

use super::Mesh;
use crate::geometry::{tetrahedron, CellType};
use std::collections::HashMap;

/// Midpoint nodes created on demand, one per unordered node pair.
pub struct Midpoints {
    index: HashMap<(usize, usize), usize>,
}

impl Default for Midpoints {
    fn default() -> Self {
        Self::new()
    }
}

impl Midpoints {
    pub fn new() -> Self {
        Midpoints { index: HashMap::new() }
    }

    /// The node at the middle of a–b if it was created.
    pub fn find(&self, a: usize, b: usize) -> Option<usize> {
        self.index.get(&(a.min(b), a.max(b))).copied()
    }

    /// The node at the middle of a–b, appended to `points` on first request.
    pub fn get<const D: usize>(&mut self, a: usize, b: usize, points: &mut Vec<[f64; D]>) -> usize {
        *self.index.entry((a.min(b), a.max(b))).or_insert_with(|| {
            let (pa, pb) = (points[a], points[b]);
            points.push(std::array::from_fn(|r| 0.5 * (pa[r] + pb[r])));
            points.len() - 1
        })
    }
}

/// The degree-2 mesh with the same cells: edge midpoints appended after the existing nodes
/// (a degree-2 mesh is returned unchanged). Every midpoint sits at the middle of its straight
/// edge, on the boundary too, as gmsh places them with `Mesh.SecondOrderLinear`: a curved
/// boundary stays the polygon of the degree-1 mesh.
/// Of a mesh of tetrahedra too, whose triangles get the midpoints of their three edges.
pub fn elevate_to_p2<const D: usize>(mesh: &Mesh<D>) -> Mesh<D> {
    if mesh.order == 2 {
        return mesh.clone();
    }
    assert_eq!(mesh.order, 1, "order must be 1 or 2");
    let triangle = CellType::Triangle.edges();
    let (cell_edges, facet_edges): (&[[usize; 2]], &[[usize; 2]]) =
        if D == 3 { (&tetrahedron::EDGES, triangle) } else { (triangle, &[[0, 1]]) };
    let mut points = mesh.points.clone();
    let mut mid = Midpoints::new();
    let mut with_midpoints = |nodes: &[usize], edges: &[[usize; 2]], out: &mut Vec<usize>| {
        out.extend_from_slice(nodes);
        out.extend(edges.iter().map(|&[i, j]| mid.get(nodes[i], nodes[j], &mut points)));
    };
    let mut cell_nodes = Vec::with_capacity(3 * mesh.cell_nodes.len());
    for c in 0..mesh.n_cells() {
        with_midpoints(mesh.cell(c), cell_edges, &mut cell_nodes);
    }
    let mut facet_nodes = Vec::with_capacity(2 * mesh.facet_nodes.len());
    for f in 0..mesh.n_facets() {
        with_midpoints(mesh.facet(f), facet_edges, &mut facet_nodes);
    }
    Mesh {
        points,
        order: 2,
        cell_nodes,
        cell_tags: mesh.cell_tags.clone(),
        facet_nodes,
        facet_tags: mesh.facet_tags.clone(),
        groups: mesh.groups.clone(),
    }
}

/// The degree-1 mesh of the vertices of `mesh`, its nodes renumbered (cells, facets, tags and
/// groups kept).
pub fn vertex_mesh(mesh: &Mesh) -> Mesh {
    if mesh.order == 1 {
        return mesh.clone();
    }
    let mut index = vec![usize::MAX; mesh.n_points()];
    let mut points = Vec::new();
    let mut renumber = |n: usize| {
        if index[n] == usize::MAX {
            index[n] = points.len();
            points.push(mesh.points[n]);
        }
        index[n]
    };
    let cell_nodes: Vec<usize> =
        (0..mesh.n_cells()).flat_map(|c| mesh.cell(c)[..3].to_vec()).map(&mut renumber).collect();
    let facet_nodes: Vec<usize> =
        (0..mesh.n_facets()).flat_map(|f| mesh.facet(f)[..2].to_vec()).map(&mut renumber).collect();
    Mesh {
        points,
        order: 1,
        cell_nodes,
        cell_tags: mesh.cell_tags.clone(),
        facet_nodes,
        facet_tags: mesh.facet_tags.clone(),
        groups: mesh.groups.clone(),
    }
}
