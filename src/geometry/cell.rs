//! Reference cells as data: their vertices, edges and facets by local index.
//!
//! Two numberings of a triangle's sides are in use, and the tables keep them apart: its
//! **facets** (fluxes, contact faces, patch boundaries, the topology's per-cell sides), facet i
//! opposite vertex i, and its **edges** in gmsh's order (where a 6-node triangle puts its
//! midpoint nodes: node 3 + i on edge i). In 2D both are the three sides; in 3D a tetrahedron's
//! facets are triangles and its edges six segments.

/// The shape of a reference cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellType {
    /// The triangle with vertices (0, 0), (1, 0), (0, 1), counter-clockwise.
    Triangle,
}

impl CellType {
    /// Its number of vertices.
    pub const fn vertices(self) -> usize {
        match self {
            CellType::Triangle => 3,
        }
    }

    /// The local vertices of each facet: facet i is opposite vertex i and runs from vertex
    /// i + 1 to vertex i + 2 (mod 3), counter-clockwise.
    pub const fn facets(self) -> &'static [[usize; 2]] {
        match self {
            CellType::Triangle => &[[1, 2], [2, 0], [0, 1]],
        }
    }

    /// The local vertices of each edge in gmsh's order: edge i from vertex i to vertex i + 1
    /// (mod 3), whose midpoint is node 3 + i of a 6-node triangle.
    pub const fn edges(self) -> &'static [[usize; 2]] {
        match self {
            CellType::Triangle => &[[0, 1], [1, 2], [2, 0]],
        }
    }

    /// The edge of gmsh's order that joins the local vertices `i` and `j`, either way round.
    pub fn edge_between(self, i: usize, j: usize) -> usize {
        (self.edges().iter())
            .position(|&[a, b]| (a, b) == (i, j) || (a, b) == (j, i))
            .expect("two distinct vertices of the cell")
    }
}

#[cfg(test)]
mod tests {
    use super::CellType;

    #[test]
    fn the_facet_opposite_a_vertex_holds_the_other_two() {
        let cell = CellType::Triangle;
        for (i, facet) in cell.facets().iter().enumerate() {
            assert!(!facet.contains(&i));
            assert_eq!(facet[0] + facet[1] + i, 3, "facet {i}: {facet:?}");
            let e = cell.edge_between(facet[0], facet[1]);
            let [a, b] = cell.edges()[e];
            assert!((a, b) == (facet[0], facet[1]) || (a, b) == (facet[1], facet[0]));
        }
        assert_eq!((0..3).map(|i| cell.edge_between(i, (i + 1) % 3)).collect::<Vec<_>>(), [0, 1, 2]);
    }
}
