//! Cells of zero area along a straight boundary, and their repair by an edge flip.
//!
//! gmsh's 2D Delaunay-based algorithms (Frontal-Delaunay, Delaunay) triangulate the boundary
//! nodes first, each moved by a random amount of up to `Mesh.RandomFactor` × the surface's
//! size ε (10⁻⁹ by default) to break ties. Three consecutive nodes a, b, c of a straight
//! boundary then make a triangle of height up to ε; when |ac| is small enough that its
//! circumcircle, of radius about |ac|²/(8ε), holds no other node, that sliver is a Delaunay
//! triangle, and inside the surface when b moved inwards. Its circumcentre lies outside the
//! surface, so refinement never removes it, and once gmsh puts the nodes back on the line its
//! area is 0. This happens where the sizes fall below about (RandomFactor)^{1/2} × the
//! surface's size (a few mm on a rock block 150 m wide; a smaller RandomFactor postpones it,
//! a larger one brings it sooner). [`flip_flat_cells`] replaces such a cell (a, b, c), b
//! between a and c, and its neighbour (a, c, d) across the chord ac by (a, b, d) and
//! (b, c, d): both have positive area, the boundary segments ab and bc stay, and the mesh
//! stays conforming.

use super::topology::NONE;
use super::{Mesh, Topology};
use crate::geometry::{CellType, Point};

/// Flips every cell of zero area with its neighbour across its longest edge (the chord), in
/// rounds until none is left; P2 cells get the midpoint of the new edge bd, and the chord's
/// midpoint is dropped (nodes are renumbered in order of first use by a cell). Returns the
/// number of flips, or Err with a vertex of a flat cell that cannot be flipped (two of its
/// vertices coincide, or its chord is on the boundary or faces another flat cell).
pub fn flip_flat_cells(mesh: &mut Mesh) -> Result<usize, Point> {
    let mut flips = 0;
    loop {
        let flat: Vec<usize> = (0..mesh.n_cells()).filter(|&c| mesh.cell_area(c) == 0.0).collect();
        let Some(&first) = flat.first() else { break };
        let topology = Topology::new(mesh);
        let mut touched = vec![false; mesh.n_cells()];
        let before = flips;
        for c in flat {
            let Some((chord, b)) = chord(mesh, &topology, c) else { continue };
            let [p, q] = topology.facet_cells[chord];
            let n = if p == c { q } else { p };
            if n == NONE || touched[c] || touched[n] || mesh.cell_area(n) == 0.0 {
                continue;
            }
            flip(mesh, c, n, topology.facets[chord], b);
            touched[c] = true;
            touched[n] = true;
            flips += 1;
        }
        if flips == before {
            return Err(mesh.points[mesh.cell(first)[0]]);
        }
    }
    if flips > 0 {
        compact(mesh);
    }
    Ok(flips)
}

/// The longest edge of the flat cell `c` and the vertex opposite it, if that vertex lies
/// strictly between the edge's ends.
fn chord(mesh: &Mesh, topology: &Topology, c: usize) -> Option<(usize, usize)> {
    let length =
        |e: usize| crate::geometry::distance(mesh.points[topology.facets[e][0]], mesh.points[topology.facets[e][1]]);
    let edges = topology.cell_facets[c];
    let chord = edges.into_iter().max_by(|&e, &f| length(e).total_cmp(&length(f)))?;
    let b = *mesh.cell(c)[..3].iter().find(|v| !topology.facets[chord].contains(v))?;
    edges.iter().all(|&e| length(e) > 0.0).then_some((chord, b))
}

/// Replaces the flat cell `c` = (a, b, c′) and its neighbour `n` = (a, c′, d) across the chord
/// `[a, c′]` by (a, b, d) and (b, c′, d).
fn flip(mesh: &mut Mesh, c: usize, n: usize, [a, c1]: [usize; 2], b: usize) {
    let npc = mesh.nodes_per_cell();
    let (flat, other) = (mesh.cell(c).to_vec(), mesh.cell(n).to_vec());
    let d = *other[..3].iter().find(|&&v| v != a && v != c1).expect("a triangle has a third vertex");
    let mut first = vec![a, b, d];
    let mut second = vec![b, c1, d];
    if npc == 6 {
        let bd = mesh.points.len();
        let (pb, pd) = (mesh.points[b], mesh.points[d]);
        mesh.points.push([0.5 * (pb[0] + pd[0]), 0.5 * (pb[1] + pd[1])]);
        first.extend([midpoint(&flat, a, b), bd, midpoint(&other, d, a)]);
        second.extend([midpoint(&flat, b, c1), midpoint(&other, c1, d), bd]);
    }
    mesh.cell_nodes[c * npc..(c + 1) * npc].copy_from_slice(&first);
    mesh.cell_nodes[n * npc..(n + 1) * npc].copy_from_slice(&second);
}

/// The midpoint node of the edge (p, q) of the P2 cell `cell` (nodes v₀ v₁ v₂ m₀₁ m₁₂ m₂₀).
fn midpoint(cell: &[usize], p: usize, q: usize) -> usize {
    let i = |v: usize| cell[..3].iter().position(|&w| w == v).expect("a vertex of the cell");
    let (i, j) = (i(p), i(q));
    cell[3 + CellType::Triangle.edge_between(i, j)]
}

/// Renumbers the nodes in order of first use by a cell, dropping those no cell uses.
fn compact(mesh: &mut Mesh) {
    let mut new = vec![NONE; mesh.points.len()];
    let mut points = Vec::new();
    for n in mesh.cell_nodes.iter_mut() {
        if new[*n] == NONE {
            new[*n] = points.len();
            points.push(mesh.points[*n]);
        }
        *n = new[*n];
    }
    mesh.facet_nodes.iter_mut().for_each(|n| *n = new[*n]);
    mesh.points = points;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::rectangle;

    /// Source: docs/method.md §5.4 (cells of zero area). Goal: the sliver gmsh leaves on a
    /// straight boundary is flipped with its neighbour into two cells of positive area that
    /// cover the square, every node used and the P2 midpoints in place; a mesh without flat
    /// cells is left alone. Parameters: the unit square of two cells with a flat cell
    /// (0,0), (1,0), (½,0) below the chord (0,0)–(1,0) of the cell above it, P1 and P2.
    #[test]
    fn a_flat_cell_on_a_straight_boundary_is_flipped_away() {
        for order in [1, 2] {
            let mut mesh = rectangle(0.0, 1.0, 0.0, 1.0, 2, 2, order);
            assert_eq!(flip_flat_cells(&mut mesh), Ok(0), "a mesh without flat cells is left alone");
            let mut sliver = rectangle(0.0, 1.0, 0.0, 1.0, 1, 1, order);
            sliver.points.push([0.5, 0.0]);
            let b = sliver.points.len() - 1;
            let npc = sliver.nodes_per_cell();
            // the cell on (0,0)–(1,0) and the new flat cell (0,0), (1,0), (½,0)
            let c = (0..sliver.n_cells()).find(|&c| {
                sliver.cell_area(c).abs() > 0.0 && {
                    let v = &sliver.cell(c)[..3];
                    v.contains(&0) && v.contains(&1)
                }
            });
            let c = c.expect("a cell on the bottom edge");
            let mut flat = vec![0, 1, b];
            if npc == 6 {
                let m01 = midpoint(sliver.cell(c), 0, 1);
                sliver.points.extend([[0.75, 0.0], [0.25, 0.0]]);
                let (m1b, mb0) = (sliver.points.len() - 2, sliver.points.len() - 1);
                flat.extend([m01, m1b, mb0]);
            }
            sliver.cell_nodes.extend(flat);
            sliver.cell_tags.push(sliver.cell_tags[0]);
            assert_eq!((0..sliver.n_cells()).filter(|&c| sliver.cell_area(c) == 0.0).count(), 1);
            let flips = flip_flat_cells(&mut sliver).unwrap();
            assert_eq!(flips, 1);
            assert!((0..sliver.n_cells()).all(|c| sliver.cell_area(c).abs() > 0.0));
            let total: f64 = (0..sliver.n_cells()).map(|c| sliver.cell_area(c).abs()).sum();
            assert!((total - 1.0).abs() < 1e-15, "area {total}");
            // every node used (5 vertices, 7 edges), P2 midpoints at the middle of their edges
            assert_eq!(sliver.n_points(), if order == 1 { 5 } else { 5 + 7 });
            if order == 2 {
                for c in 0..sliver.n_cells() {
                    let n = sliver.cell(c);
                    for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                        let (p, q, m) = (sliver.points[n[i]], sliver.points[n[j]], sliver.points[n[3 + k]]);
                        assert_eq!(m, [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]);
                    }
                }
            }
        }
    }
}
