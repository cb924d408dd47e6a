//! Simplex meshes of degree 1 or 2 with physical tags, of the plane (`Mesh`, D = 2) or of
//! space (`Mesh<3>`).
//!
//! A [`Mesh`] stores node coordinates, cells, boundary facets and the physical groups that tag
//! them, all in gmsh's node order:
//! - D = 2: 3-node or 6-node triangles (vertices 0, 1, 2, then the midpoints of edges 01, 12,
//!   20), facets 2-node or 3-node segments (end points, then the midpoint);
//! - D = 3: 4-node or 10-node tetrahedra (vertices, then the midpoints of the edges of
//!   [`tetrahedron::EDGES`](crate::geometry::tetrahedron::EDGES)), facets 3-node or 6-node
//!   triangles.
//!
//! Geometry is affine: midpoint nodes of a degree-2 mesh sit at the middle of straight edges.
//!
//! The mesh knows nothing of finite elements: it only describes the domain.

pub mod flat;
pub mod interface;
pub mod midpoints;
mod solid;
pub mod structured;
pub mod topology;

pub use topology::Topology;

use crate::geometry::{distance, CellType, Point};

/// A named physical group of gmsh: `dim` D for material regions, D − 1 for boundary curves
/// (surfaces in 3D).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PhysicalGroup {
    pub dim: u8,
    pub tag: i32,
    pub name: String,
}

/// Simplex mesh of dimension D and degree `order` (1 or 2).
#[derive(Debug, Clone)]
pub struct Mesh<const D: usize = 2> {
    /// Coordinates of every node (vertices and, for degree 2, edge midpoints).
    pub points: Vec<[f64; D]>,
    /// Polynomial degree of the geometry and of the Lagrange space built on it.
    pub order: usize,
    /// Cell connectivity, `nodes_per_cell()` entries per cell.
    pub cell_nodes: Vec<usize>,
    /// Physical surface tag of each cell.
    pub cell_tags: Vec<i32>,
    /// Boundary facet connectivity, `nodes_per_facet()` entries per facet.
    pub facet_nodes: Vec<usize>,
    /// Physical curve tag of each boundary facet.
    pub facet_tags: Vec<i32>,
    /// Physical groups of dimension D − 1 and D.
    pub groups: Vec<PhysicalGroup>,
}

impl<const D: usize> Mesh<D> {
    /// The nodes of a P_order simplex of dimension `dim`: its dim + 1 vertices, and for P2
    /// one on each of its (dim + 1) dim / 2 edges.
    const fn simplex_nodes(dim: usize, order: usize) -> usize {
        match order {
            1 => dim + 1,
            _ => (dim + 1) * (dim + 2) / 2,
        }
    }

    /// 3 or 6 for P1 or P2 triangles; 4 or 10 for tetrahedra.
    pub fn nodes_per_cell(&self) -> usize {
        Self::simplex_nodes(D, self.order)
    }

    /// 2 or 3 for P1 or P2 segments; 3 or 6 for triangles.
    pub fn nodes_per_facet(&self) -> usize {
        Self::simplex_nodes(D - 1, self.order)
    }

    /// The body of each cell: the connected components of the cells through their nodes.
    pub fn bodies(&self) -> Vec<usize> {
        // union–find over the nodes, each cell joining its nodes
        let mut parent: Vec<usize> = (0..self.n_points()).collect();
        fn root(parent: &mut [usize], mut k: usize) -> usize {
            while parent[k] != k {
                parent[k] = parent[parent[k]];
                k = parent[k];
            }
            k
        }
        for c in 0..self.n_cells() {
            let nodes = self.cell(c);
            for &n in &nodes[1..] {
                let (a, b) = (root(&mut parent, nodes[0]), root(&mut parent, n));
                parent[a] = b;
            }
        }
        let mut label = std::collections::HashMap::new();
        (0..self.n_cells())
            .map(|c| {
                let r = root(&mut parent, self.cell(c)[0]);
                let next = label.len();
                *label.entry(r).or_insert(next)
            })
            .collect()
    }

    pub fn n_cells(&self) -> usize {
        self.cell_tags.len()
    }

    pub fn n_facets(&self) -> usize {
        self.facet_tags.len()
    }

    pub fn n_points(&self) -> usize {
        self.points.len()
    }

    /// Node indices of cell `c`.
    pub fn cell(&self, c: usize) -> &[usize] {
        let n = self.nodes_per_cell();
        &self.cell_nodes[c * n..(c + 1) * n]
    }

    /// The boundary facets whose physical tag is one of `tags`, in mesh order.
    pub fn facets_tagged<'a>(&'a self, tags: &'a [i32]) -> impl Iterator<Item = usize> + 'a {
        (0..self.n_facets()).filter(move |&f| tags.contains(&self.facet_tags[f]))
    }

    /// Node indices of boundary facet `f`.
    pub fn facet(&self, f: usize) -> &[usize] {
        let n = self.nodes_per_facet();
        &self.facet_nodes[f * n..(f + 1) * n]
    }

    /// The physical group of dimension `dim` called `name` (case-insensitive).
    pub fn group(&self, dim: u8, name: &str) -> Option<&PhysicalGroup> {
        self.groups.iter().find(|g| g.dim == dim && g.name.eq_ignore_ascii_case(name))
    }

    /// Names of the physical groups of dimension `dim`.
    pub fn group_names(&self, dim: u8) -> Vec<&str> {
        self.groups.iter().filter(|g| g.dim == dim).map(|g| g.name.as_str()).collect()
    }
}

impl Mesh {
    /// The P1 mesh in which every cell has its own copies of its three vertices (cell c,
    /// vertex v is point 3c + v), for fields that jump across edges.
    pub fn discontinuous(&self) -> Mesh {
        Mesh {
            points: (0..self.n_cells()).flat_map(|c| self.cell_vertices(c)).collect(),
            order: 1,
            cell_nodes: (0..3 * self.n_cells()).collect(),
            cell_tags: self.cell_tags.clone(),
            facet_nodes: Vec::new(),
            facet_tags: Vec::new(),
            groups: self.groups.clone(),
        }
    }

    /// Vertex coordinates of cell `c`.
    pub fn cell_vertices(&self, c: usize) -> [Point; 3] {
        let n = self.cell(c);
        [self.points[n[0]], self.points[n[1]], self.points[n[2]]]
    }

    /// Centroid of cell `c`: the mean of its vertices.
    pub fn cell_centroid(&self, c: usize) -> Point {
        let [a, b, d] = self.cell_vertices(c);
        [(a[0] + b[0] + d[0]) / 3.0, (a[1] + b[1] + d[1]) / 3.0]
    }

    /// Signed area of cell `c` (positive for counter-clockwise vertices).
    pub fn cell_area(&self, c: usize) -> f64 {
        let [a, b, d] = self.cell_vertices(c);
        0.5 * ((b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1]))
    }

    /// Diameter h_T of cell `c` (its longest edge).
    pub fn cell_diameter(&self, c: usize) -> f64 {
        let v = self.cell_vertices(c);
        self.cell_type().edges().iter().map(|&[i, j]| distance(v[i], v[j])).fold(0.0, f64::max)
    }

    /// The shape of its cells.
    pub fn cell_type(&self) -> CellType {
        CellType::Triangle
    }

    /// Length of boundary facet `f`.
    pub fn facet_length(&self, f: usize) -> f64 {
        let n = self.facet(f);
        distance(self.points[n[0]], self.points[n[1]])
    }

    /// Total length of the facets carrying physical tag `tag`.
    pub fn boundary_length(&self, tag: i32) -> f64 {
        (0..self.n_facets()).filter(|&f| self.facet_tags[f] == tag).map(|f| self.facet_length(f)).sum()
    }

    /// Reorders every cell counter-clockwise (gmsh may hand out either orientation).
    pub fn orient_counter_clockwise(&mut self) {
        let n = self.nodes_per_cell();
        for c in 0..self.n_cells() {
            if self.cell_area(c) < 0.0 {
                let cell = &mut self.cell_nodes[c * n..(c + 1) * n];
                // swap vertices 1 and 2; midpoints 01 ↔ 20, 12 stays
                cell.swap(1, 2);
                if n == 6 {
                    cell.swap(3, 5);
                }
            }
        }
    }
}
