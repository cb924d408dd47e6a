//! Uniform red refinement and local newest-vertex bisection of triangle meshes.
//!
//! Red refinement cuts every triangle into four through its edge midpoints m01, m12, m20:
//!
//! ```text
//!   children (v0, m01, m20), (m01, v1, m12), (m20, m12, v2), (m01, m12, m20)
//! ```
//!
//! all with the orientation of the parent. Boundary facets a → b become a → m and m → b with
//! the tag of the parent; cell tags and physical groups are kept. The refined mesh has the
//! order of the input: for degree 2 the coarse midpoint nodes become fine vertices and new
//! midpoints are placed at the middle of the new (straight) edges. Every coarse node keeps
//! its index in the refined mesh, so a nodal field of the coarse mesh is the restriction to
//! the first `coarse.n_points()` nodes of a fine one.
//!
//! Newest-vertex bisection ([`bisect`]) cuts a cell (a, b, c), whose refinement edge is b–c,
//! at the midpoint m of b–c into (m, a, b) and (m, c, a), each with the refinement edge
//! opposite m; the first refinement edge of a cell is its longest edge. A cell with a
//! midpoint on one of its edges is bisected until no midpoint hangs (Mitchell 1991), so the
//! result is conforming. Both children keep the parent's orientation.
//!
//! The fine mesh is nested in the coarse one: each fine cell lies in its parent coarse cell
//! and each fine boundary facet in its parent facet, which [`Refinement`] records.

use crate::mesh::midpoints::Midpoints;
use crate::mesh::Mesh;

/// A refined mesh and where its cells and facets come from.
#[derive(Debug, Clone)]
pub struct Refinement {
    pub mesh: Mesh,
    /// The coarse cell containing each fine cell.
    pub cell_parents: Vec<usize>,
    /// The coarse boundary facet containing each fine boundary facet.
    pub facet_parents: Vec<usize>,
}

/// One level of uniform red refinement (4 cells per cell, 2 facets per facet).
pub fn refine(mesh: &Mesh) -> Refinement {
    let p = mesh.order;
    assert!(p == 1 || p == 2, "order must be 1 or 2");
    let mut points = mesh.points.clone();
    let mut coarse_mid = Midpoints::new(); // midpoints of coarse edges (order 1 only)
    let mut fine_mid = Midpoints::new(); // midpoints of fine edges (order 2 only)
    let npc = mesh.nodes_per_cell();
    let mut cell_nodes = Vec::with_capacity(4 * mesh.cell_nodes.len());
    let mut cell_tags = Vec::with_capacity(4 * mesh.n_cells());
    let mut cell_parents = Vec::with_capacity(4 * mesh.n_cells());
    for c in 0..mesh.n_cells() {
        let n = mesh.cell(c);
        let [v0, v1, v2] = [n[0], n[1], n[2]];
        let [m01, m12, m20] = if p == 2 {
            [n[3], n[4], n[5]]
        } else {
            [
                coarse_mid.get(v0, v1, &mut points),
                coarse_mid.get(v1, v2, &mut points),
                coarse_mid.get(v2, v0, &mut points),
            ]
        };
        for [a, b, d] in [[v0, m01, m20], [m01, v1, m12], [m20, m12, v2], [m01, m12, m20]] {
            cell_nodes.extend([a, b, d]);
            if p == 2 {
                let m =
                    [fine_mid.get(a, b, &mut points), fine_mid.get(b, d, &mut points), fine_mid.get(d, a, &mut points)];
                cell_nodes.extend(m);
            }
            cell_tags.push(mesh.cell_tags[c]);
            cell_parents.push(c);
        }
    }
    debug_assert_eq!(cell_nodes.len(), 4 * mesh.n_cells() * npc);
    let mut facet_nodes = Vec::with_capacity(2 * mesh.facet_nodes.len());
    let mut facet_tags = Vec::with_capacity(2 * mesh.n_facets());
    let mut facet_parents = Vec::with_capacity(2 * mesh.n_facets());
    for f in 0..mesh.n_facets() {
        let n = mesh.facet(f);
        let (a, b) = (n[0], n[1]);
        let m = if p == 2 { n[2] } else { coarse_mid.get(a, b, &mut points) };
        for (s, e) in [(a, m), (m, b)] {
            facet_nodes.extend([s, e]);
            if p == 2 {
                facet_nodes.push(fine_mid.get(s, e, &mut points));
            }
            facet_tags.push(mesh.facet_tags[f]);
            facet_parents.push(f);
        }
    }
    let fine = Mesh { points, order: p, cell_nodes, cell_tags, facet_nodes, facet_tags, groups: mesh.groups.clone() };
    Refinement { mesh: fine, cell_parents, facet_parents }
}

/// Newest-vertex bisection of the degree-1 `refined.mesh`: every cell with `marked[c]` is
/// bisected once, and as many more as conformity asks. Parents are kept relative to the
/// mesh `refined` itself refers to.
pub fn bisect(refined: &Refinement, marked: &[bool]) -> Refinement {
    let mesh = &refined.mesh;
    assert_eq!(mesh.order, 1, "bisection works on degree-1 meshes");
    let mut points = mesh.points.clone();
    let mut midpoints = Midpoints::new();
    let facets = mesh.cell_type().facets();
    let longest_first = |c: usize| {
        let n = mesh.cell(c);
        let length = |i: usize| crate::geometry::distance(mesh.points[n[facets[i][0]]], mesh.points[n[facets[i][1]]]);
        let i = (0..3).fold(0, |best, i| if length(i) > length(best) { i } else { best });
        [n[i], n[facets[i][0]], n[facets[i][1]]]
    };
    let mut cells: Vec<([usize; 3], usize, bool)> =
        (0..mesh.n_cells()).map(|c| (longest_first(c), refined.cell_parents[c], marked[c])).collect();
    let mut tags: Vec<i32> = mesh.cell_tags.clone();
    loop {
        let mut next = Vec::with_capacity(cells.len());
        let mut next_tags = Vec::with_capacity(cells.len());
        for ((cell @ [a, b, c], parent, split), tag) in cells.into_iter().zip(tags) {
            if split || midpoints.find(b, c).is_some() {
                let m = midpoints.get(b, c, &mut points);
                next.extend([([m, a, b], parent, false), ([m, c, a], parent, false)]);
                next_tags.extend([tag, tag]);
            } else {
                next.push((cell, parent, false));
                next_tags.push(tag);
            }
        }
        let hanging =
            |&[a, b, c]: &[usize; 3]| [(a, b), (b, c), (c, a)].iter().any(|&(p, q)| midpoints.find(p, q).is_some());
        let mut any = false;
        for (cell, _, split) in next.iter_mut() {
            *split = hanging(cell);
            any |= *split;
        }
        (cells, tags) = (next, next_tags);
        if !any {
            break;
        }
    }
    let mut facet_nodes = Vec::new();
    let (mut facet_tags, mut facet_parents) = (Vec::new(), Vec::new());
    let mut stack: Vec<(usize, usize, usize)> =
        (0..mesh.n_facets()).rev().map(|f| (mesh.facet(f)[0], mesh.facet(f)[1], f)).collect();
    while let Some((a, b, f)) = stack.pop() {
        match midpoints.find(a, b) {
            Some(m) => stack.extend([(m, b, f), (a, m, f)]),
            None => {
                facet_nodes.extend([a, b]);
                facet_tags.push(mesh.facet_tags[f]);
                facet_parents.push(refined.facet_parents[f]);
            }
        }
    }
    let cell_parents = cells.iter().map(|&(_, parent, _)| parent).collect();
    let cell_nodes = cells.into_iter().flat_map(|(cell, _, _)| cell).collect();
    let fine =
        Mesh { points, order: 1, cell_nodes, cell_tags: tags, facet_nodes, facet_tags, groups: mesh.groups.clone() };
    Refinement { mesh: fine, cell_parents, facet_parents }
}

/// `levels` successive red refinements; parents refer to the cells and facets of `mesh`.
/// `levels = 0` returns a copy with identity parents.
pub fn refine_levels(mesh: &Mesh, levels: usize) -> Refinement {
    let mut current = Refinement {
        mesh: mesh.clone(),
        cell_parents: (0..mesh.n_cells()).collect(),
        facet_parents: (0..mesh.n_facets()).collect(),
    };
    for _ in 0..levels {
        let next = refine(&current.mesh);
        current = Refinement {
            cell_parents: next.cell_parents.iter().map(|&c| current.cell_parents[c]).collect(),
            facet_parents: next.facet_parents.iter().map(|&f| current.facet_parents[f]).collect(),
            mesh: next.mesh,
        };
    }
    current
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{sub, AffineMap};
    use crate::mesh::midpoints::{elevate_to_p2, vertex_mesh};
    use crate::mesh::structured::{rectangle, BOTTOM, LEFT, RIGHT, TOP};
    use crate::mesh::Topology;

    /// A test mesh: a structured rectangle with displaced interior nodes, several cell tags;
    /// for P2 elevated, so that midpoints sit at the middle of the moved edges.
    fn skewed(order: usize) -> Mesh {
        let mut mesh = rectangle(-1.0, 2.0, 0.5, 2.5, 3, 4, 1);
        for p in mesh.points.iter_mut() {
            let interior = p[0] > -1.0 && p[0] < 2.0 && p[1] > 0.5 && p[1] < 2.5;
            if interior {
                p[0] += 0.13 * (3.0 * p[1]).sin();
                p[1] += 0.07 * (2.0 * p[0]).cos();
            }
        }
        mesh.cell_tags = (0..mesh.n_cells()).map(|c| 1 + (c % 3) as i32).collect();
        if order == 2 {
            elevate_to_p2(&mesh)
        } else {
            mesh
        }
    }

    fn area(mesh: &Mesh) -> f64 {
        (0..mesh.n_cells()).map(|c| mesh.cell_area(c)).sum()
    }

    #[test]
    fn counts_areas_and_lengths_are_preserved() {
        for order in [1, 2] {
            let coarse = skewed(order);
            let r = refine_levels(&coarse, 2);
            let fine = &r.mesh;
            assert_eq!(fine.order, order);
            assert_eq!(fine.n_cells(), 16 * coarse.n_cells());
            assert_eq!(fine.n_facets(), 4 * coarse.n_facets());
            assert_eq!(fine.groups, coarse.groups);
            assert!((area(fine) - area(&coarse)).abs() < 1e-13);
            assert!((area(fine) - 6.0).abs() < 1e-13);
            for tag in [BOTTOM, RIGHT, TOP, LEFT] {
                assert!((fine.boundary_length(tag) - coarse.boundary_length(tag)).abs() < 1e-13);
            }
            // orientation kept, cell and facet tags inherited, coarse nodes unmoved
            for c in 0..fine.n_cells() {
                let parent = r.cell_parents[c];
                assert!(fine.cell_area(c) > 0.0);
                assert_eq!(fine.cell_tags[c], coarse.cell_tags[parent]);
            }
            for f in 0..fine.n_facets() {
                assert_eq!(fine.facet_tags[f], coarse.facet_tags[r.facet_parents[f]]);
            }
            assert_eq!(&fine.points[..coarse.n_points()], &coarse.points[..]);
            // a conforming mesh: every boundary facet is a cell edge, and Euler's formula holds
            let topo = Topology::new(fine);
            let boundary = (0..topo.n_facets()).filter(|&e| topo.is_boundary_facet(e)).count();
            assert_eq!(boundary, fine.n_facets());
            let euler = topo.vertices.len() as i64 - topo.n_edges() as i64 + fine.n_cells() as i64;
            assert_eq!(euler, 1);
            // P2: no duplicate nodes, every node used, midpoints at the middle of their edge
            let nodes_expected = if order == 1 { topo.vertices.len() } else { topo.vertices.len() + topo.n_edges() };
            assert_eq!(fine.n_points(), nodes_expected);
            if order == 2 {
                for c in 0..fine.n_cells() {
                    let n = fine.cell(c);
                    for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                        let (a, b, m) = (fine.points[n[i]], fine.points[n[j]], fine.points[n[3 + k]]);
                        assert!((0.5 * (a[0] + b[0]) - m[0]).abs() < 1e-15);
                        assert!((0.5 * (a[1] + b[1]) - m[1]).abs() < 1e-15);
                    }
                }
            }
        }
    }

    #[test]
    fn fine_cells_and_facets_are_nested_in_their_parents() {
        for order in [1, 2] {
            let coarse = skewed(order);
            let r = refine_levels(&coarse, 3);
            let fine = &r.mesh;
            for c in 0..fine.n_cells() {
                let x = fine.cell_centroid(c);
                let map = AffineMap::new(coarse.cell_vertices(r.cell_parents[c]));
                let d = sub(x, map.origin);
                // ξ = J⁻¹ (x − v0) = (J⁻ᵀ)ᵀ (x − v0)
                let xi =
                    [map.inv_t[0][0] * d[0] + map.inv_t[1][0] * d[1], map.inv_t[0][1] * d[0] + map.inv_t[1][1] * d[1]];
                let inside = xi[0] > 1e-12 && xi[1] > 1e-12 && xi[0] + xi[1] < 1.0 - 1e-12;
                assert!(inside, "fine cell {c}: centroid {x:?} at ξ = {xi:?} in its parent");
            }
            // the children of a parent tile it
            let mut child_area = vec![0.0; coarse.n_cells()];
            for c in 0..fine.n_cells() {
                child_area[r.cell_parents[c]] += fine.cell_area(c);
            }
            for (c, area) in child_area.into_iter().enumerate() {
                assert!((area - coarse.cell_area(c)).abs() < 1e-14);
            }
            let mut child_length = vec![0.0; coarse.n_facets()];
            for f in 0..fine.n_facets() {
                let parent = coarse.facet(r.facet_parents[f]);
                let (a, b) = (coarse.points[parent[0]], coarse.points[parent[1]]);
                for &node in fine.facet(f) {
                    let x = fine.points[node];
                    let cross = (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]);
                    assert!(cross.abs() < 1e-14, "fine facet {f} off its parent");
                }
                child_length[r.facet_parents[f]] += fine.facet_length(f);
            }
            for (f, length) in child_length.into_iter().enumerate() {
                assert!((length - coarse.facet_length(f)).abs() < 1e-14);
            }
        }
    }

    /// Cells marked in a corner, bisected three times over: the mesh stays conforming, nested
    /// and oriented, the marked cells are halved, and the refinement stays local.
    #[test]
    fn bisection_is_conforming_nested_and_local() {
        let coarse = vertex_mesh(&skewed(2));
        assert_eq!(coarse.order, 1);
        assert_eq!(coarse.n_points(), skewed(1).n_points());
        let mut r = refine_levels(&coarse, 0);
        for _ in 0..3 {
            let corner = |c: usize| r.mesh.cell_vertices(c).iter().any(|p| p[0] < -0.5 && p[1] < 1.0);
            let marked: Vec<bool> = (0..r.mesh.n_cells()).map(corner).collect();
            let before = r.mesh.n_cells();
            let areas: Vec<f64> = (0..before).filter(|&c| marked[c]).map(|c| r.mesh.cell_area(c)).collect();
            r = bisect(&r, &marked);
            assert!(r.mesh.n_cells() >= before + areas.len());
            let largest = areas.iter().fold(0.0_f64, |m, &a| m.max(a));
            let smallest_new = (0..r.mesh.n_cells()).map(|c| r.mesh.cell_area(c)).fold(f64::MAX, f64::min);
            assert!(smallest_new <= 0.5 * largest + 1e-15);
        }
        let fine = &r.mesh;
        assert!(fine.n_cells() < 8 * coarse.n_cells(), "{} cells: not local", fine.n_cells());
        assert!((area(fine) - 6.0).abs() < 1e-13);
        let topo = Topology::new(fine);
        let boundary = (0..topo.n_facets()).filter(|&e| topo.is_boundary_facet(e)).count();
        assert_eq!(boundary, fine.n_facets(), "a hanging node");
        let euler = topo.vertices.len() as i64 - topo.n_edges() as i64 + fine.n_cells() as i64;
        assert_eq!(euler, 1);
        let mut child_area = vec![0.0; coarse.n_cells()];
        for c in 0..fine.n_cells() {
            assert!(fine.cell_area(c) > 0.0);
            let sign = |m: &Mesh, c: usize| {
                let [a, b, d] = m.cell_vertices(c);
                ((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0])).signum()
            };
            assert_eq!(sign(fine, c), sign(&coarse, r.cell_parents[c]));
            assert_eq!(fine.cell_tags[c], coarse.cell_tags[r.cell_parents[c]]);
            child_area[r.cell_parents[c]] += fine.cell_area(c);
        }
        for (c, a) in child_area.into_iter().enumerate() {
            assert!((a - coarse.cell_area(c)).abs() < 1e-14);
        }
        for tag in [BOTTOM, RIGHT, TOP, LEFT] {
            assert!((fine.boundary_length(tag) - coarse.boundary_length(tag)).abs() < 1e-13);
        }
        for f in 0..fine.n_facets() {
            assert_eq!(fine.facet_tags[f], coarse.facet_tags[r.facet_parents[f]]);
        }
    }

    #[test]
    fn zero_levels_is_the_identity_and_elevation_keeps_cells() {
        let coarse = skewed(1);
        let r = refine_levels(&coarse, 0);
        assert_eq!(r.mesh.cell_nodes, coarse.cell_nodes);
        assert_eq!(r.cell_parents, (0..coarse.n_cells()).collect::<Vec<_>>());
        let p2 = elevate_to_p2(&coarse);
        assert_eq!(p2.n_cells(), coarse.n_cells());
        for c in 0..coarse.n_cells() {
            assert_eq!(&p2.cell(c)[..3], coarse.cell(c));
        }
        assert_eq!(elevate_to_p2(&p2).cell_nodes, p2.cell_nodes);
    }
}
