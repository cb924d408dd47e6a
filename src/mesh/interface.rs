//! Joints between two meshed bodies: the nodes of an interface curve split in two.
//!
//! gmsh meshes two physical surfaces that share a curve conformingly: the nodes of the curve
//! belong to the cells of both. A joint must let the two sides open and slide, so [`split`]
//! gives the cells of one side, the slave, their own copies of the curve's nodes (vertices and,
//! for P2, midpoints). Each segment of the curve becomes two boundary facets: the slave's, on
//! the copies, keeps the curve's tag; the master's, on the original nodes, gets a new physical
//! curve `<curve>:<master surface>`. Where the curve meets a part of the two sides' common
//! boundary that is not a joint (a bonded part), its end vertex is not split: the joint is
//! closed there, as at the tip of a crack.

use super::topology::NONE;
use super::{Mesh, PhysicalGroup, Topology};
use std::collections::{BTreeSet, HashMap};

/// A split interface: the physical tags of its two sides.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Interface {
    /// The curve tag of the slave's facets (the joint curve's own tag) and of the master's.
    pub slave_curve: i32,
    pub master_curve: i32,
    /// The physical surface tags of the slave and the master.
    pub slave_surface: i32,
    pub master_surface: i32,
}

/// The two physical surfaces on either side of the curve `curve`, from its segments: each
/// segment bounds a cell on either side (a conforming mesh) or, on sides meshed apart
/// ([`merge_sides`]), every segment bounds one cell and the segments of the two sides have the
/// same length. Err (a sentence) if a segment lies on the outer boundary, inside one surface,
/// or between another pair of surfaces than the first segment.
pub fn sides(mesh: &Mesh, topology: &Topology, curve: i32) -> Result<[i32; 2], String> {
    let name = group_name(mesh, 1, curve);
    let outer = |tag: i32| {
        format!(
            "curve '{name}' is not shared by two surfaces: part of it bounds '{}' only; a joint lies between \
             two meshed surfaces (a rigid foundation is role = \"contact\")",
            group_name(mesh, 2, tag)
        )
    };
    let mut pair: Option<[i32; 2]> = None;
    // the surface and length of each segment that bounds one cell
    let mut one_sided: Vec<(i32, f64)> = Vec::new();
    for f in mesh.facets_tagged(&[curve]) {
        let [a, b] = topology.facet_cells[topology.tagged_facet[f]];
        if b == NONE {
            one_sided.push((mesh.cell_tags[a], mesh.facet_length(f)));
            continue;
        }
        let tags = [mesh.cell_tags[a].min(mesh.cell_tags[b]), mesh.cell_tags[a].max(mesh.cell_tags[b])];
        if tags[0] == tags[1] {
            return Err(format!(
                "curve '{name}' lies inside the surface '{}': a joint separates two physical surfaces, so give each \
                 side of it its own physical surface",
                group_name(mesh, 2, tags[0])
            ));
        }
        match pair {
            Some(p) if p != tags => {
                return Err(format!(
                    "curve '{name}' separates '{}' from '{}' on one part and '{}' from '{}' on another; a joint lies \
                     between two surfaces only: split the curve into one physical curve per pair",
                    group_name(mesh, 2, p[0]),
                    group_name(mesh, 2, p[1]),
                    group_name(mesh, 2, tags[0]),
                    group_name(mesh, 2, tags[1])
                ))
            }
            _ => pair = Some(tags),
        }
    }
    match (pair, one_sided.first()) {
        (Some(_), Some(&(tag, _))) => Err(outer(tag)),
        (Some(pair), None) => Ok(pair),
        (None, None) => Err(format!("curve '{name}' has no segments in the mesh")),
        (None, Some(&(tag, _))) => {
            let other = one_sided.iter().map(|s| s.0).find(|&t| t != tag).ok_or_else(|| outer(tag))?;
            let length = |t: i32| one_sided.iter().filter(|s| s.0 == t).map(|s| s.1).sum::<f64>();
            let (l, m) = (length(tag), length(other));
            if one_sided.iter().any(|s| s.0 != tag && s.0 != other) || (l - m).abs() > 1e-9 * l.max(m) {
                return Err(outer(if l < m { other } else { tag }));
            }
            Ok([tag.min(other), tag.max(other)])
        }
    }
}

/// Splits the nodes of the curve `curve` between its two sides; the cells of the surface
/// `slave_surface` (one of [`sides`]) get the copies of the nodes they share with the other
/// side (all the curve's nodes on a conforming mesh, its ends on sides meshed apart).
/// Err: why the curve is not a joint.
pub fn split(mesh: &mut Mesh, curve: i32, slave_surface: i32) -> Result<Interface, String> {
    let topology = Topology::new(mesh);
    let pair = sides(mesh, &topology, curve)?;
    let master_surface = if pair[0] == slave_surface { pair[1] } else { pair[0] };
    let joint_facets: Vec<usize> = mesh.facets_tagged(&[curve]).collect();
    let joint_edges: BTreeSet<usize> = joint_facets.iter().map(|&f| topology.tagged_facet[f]).collect();
    let is_slave = |c: usize| c != NONE && mesh.cell_tags[c] == slave_surface;
    // a vertex on an edge off the joint between a slave cell and another cell stays bonded
    let mut bonded = BTreeSet::new();
    for (e, &[a, b]) in topology.facet_cells.iter().enumerate() {
        if b != NONE && is_slave(a) != is_slave(b) && !joint_edges.contains(&e) {
            bonded.extend(topology.facets[e]);
        }
    }
    let mut side = vec![[false; 2]; mesh.n_points()];
    for c in 0..mesh.n_cells() {
        mesh.cell(c).iter().for_each(|&n| side[n][usize::from(is_slave(c))] = true);
    }
    let mut copy: HashMap<usize, usize> = HashMap::new();
    for &f in &joint_facets {
        for node in mesh.facet(f).to_vec() {
            if side[node] == [true; 2] && !bonded.contains(&node) && !copy.contains_key(&node) {
                copy.insert(node, mesh.points.len());
                mesh.points.push(mesh.points[node]);
            }
        }
    }
    let renumber = |nodes: &mut [usize]| nodes.iter_mut().for_each(|n| *n = *copy.get(n).unwrap_or(n));
    let npc = mesh.nodes_per_cell();
    for c in (0..mesh.n_cells()).filter(|&c| mesh.cell_tags[c] == slave_surface) {
        renumber(&mut mesh.cell_nodes[c * npc..(c + 1) * npc]);
    }
    // facets off the joint, and the joint's own on sides meshed apart, follow the cells they bound
    let npf = mesh.nodes_per_facet();
    let master_curve = mesh.groups.iter().map(|g| g.tag).max().unwrap_or(0).max(curve) + 1;
    for f in 0..mesh.n_facets() {
        let [a, b] = topology.facet_cells[topology.tagged_facet[f]];
        if mesh.facet_tags[f] == curve && b == NONE && !is_slave(a) {
            mesh.facet_tags[f] = master_curve;
        } else if (mesh.facet_tags[f] != curve || b == NONE) && (is_slave(a) || is_slave(b)) {
            renumber(&mut mesh.facet_nodes[f * npf..(f + 1) * npf]);
        }
    }
    let name = format!("{}:{}", group_name(mesh, 1, curve), group_name(mesh, 2, master_surface));
    mesh.groups.push(PhysicalGroup { dim: 1, tag: master_curve, name });
    // a segment between two cells becomes the master's facet and a copy on the slave's nodes
    for &f in joint_facets.iter().filter(|&&f| topology.facet_cells[topology.tagged_facet[f]][1] != NONE) {
        let mut slave: Vec<usize> = mesh.facet(f).to_vec();
        renumber(&mut slave);
        mesh.facet_tags[f] = master_curve;
        mesh.facet_nodes.extend(slave);
        mesh.facet_tags.push(curve);
    }
    Ok(Interface { slave_curve: curve, master_curve, slave_surface, master_surface })
}

/// One mesh made of the cells of `parts`, each a mesh of the same geometry and the physical
/// surface tags whose cells it gives (docs/method.md §5.4, two bodies): nodes at the same
/// point are one node, except those inside the curves tagged `joints` (not at their ends),
/// which each part keeps its own, so that a joint's two sides may be meshed apart. Facets
/// come from the part whose cells they bound, once. Err (a sentence) where two parts do not
/// match off the joints: a boundary edge that is no part's boundary.
pub fn merge_sides(parts: &[(Mesh, Vec<i32>)], joints: &[i32]) -> Result<Mesh, String> {
    let first = &parts[0].0;
    let mut merged = Mesh {
        points: Vec::new(),
        order: first.order,
        cell_nodes: Vec::new(),
        cell_tags: Vec::new(),
        facet_nodes: Vec::new(),
        facet_tags: Vec::new(),
        groups: first.groups.clone(),
    };
    let mut at: HashMap<[u64; 2], usize> = HashMap::new();
    let mut facets: BTreeSet<(i32, Vec<usize>)> = BTreeSet::new();
    // the edges (vertex pairs) of merged cells on their part's boundary or on a joint
    let mut boundary: BTreeSet<[usize; 2]> = BTreeSet::new();
    for (mesh, surfaces) in parts {
        let topology = Topology::new(mesh);
        let kept = |c: usize| c != NONE && surfaces.contains(&mesh.cell_tags[c]);
        let inside = joint_interior(mesh, joints);
        let mut map = vec![NONE; mesh.n_points()];
        let mut node = |n: usize, merged: &mut Mesh| {
            if map[n] == NONE {
                let p = mesh.points[n];
                let new = merged.points.len();
                map[n] = if inside.contains(&n) { new } else { *at.entry(p.map(f64::to_bits)).or_insert(new) };
                if map[n] == new {
                    merged.points.push(p);
                }
            }
            map[n]
        };
        for c in (0..mesh.n_cells()).filter(|&c| kept(c)) {
            for &n in mesh.cell(c) {
                let m = node(n, &mut merged);
                merged.cell_nodes.push(m);
            }
            merged.cell_tags.push(mesh.cell_tags[c]);
        }
        let on_joint: BTreeSet<usize> = mesh.facets_tagged(joints).map(|f| topology.tagged_facet[f]).collect();
        for (e, &[a, b]) in topology.facet_cells.iter().enumerate() {
            if kept(a) != kept(b) && (b == NONE || on_joint.contains(&e)) {
                let [p, q] = topology.facets[e].map(|n| node(n, &mut merged));
                boundary.insert([p.min(q), p.max(q)]);
            }
        }
        for f in 0..mesh.n_facets() {
            if topology.facet_cells[topology.tagged_facet[f]].iter().any(|&c| kept(c)) {
                let nodes: Vec<usize> = mesh.facet(f).iter().map(|&n| node(n, &mut merged)).collect();
                let mut key = nodes.clone();
                key.sort_unstable();
                if facets.insert((mesh.facet_tags[f], key)) {
                    merged.facet_nodes.extend(nodes);
                    merged.facet_tags.push(mesh.facet_tags[f]);
                }
            }
        }
    }
    let topology = Topology::new(&merged);
    for (e, &[a, b]) in topology.facets.iter().enumerate() {
        if topology.is_boundary_facet(e) && !boundary.contains(&[a.min(b), a.max(b)]) {
            let [x, y] = merged.points[a];
            return Err(format!(
                "the meshes of the bodies do not match at ({x:.6}, {y:.6}), off the joints: gmsh meshed a curve \
                 they share differently for each"
            ));
        }
    }
    Ok(merged)
}

/// The nodes of `mesh` on the facets tagged `joints` other than the ends of those curves (the
/// vertices of a single facet of their curve).
fn joint_interior(mesh: &Mesh, joints: &[i32]) -> BTreeSet<usize> {
    let mut ends: HashMap<(i32, usize), usize> = HashMap::new();
    for f in mesh.facets_tagged(joints) {
        for &v in &mesh.facet(f)[..2] {
            *ends.entry((mesh.facet_tags[f], v)).or_default() += 1;
        }
    }
    (mesh.facets_tagged(joints))
        .flat_map(|f| mesh.facet(f).iter().map(move |&n| (mesh.facet_tags[f], n)))
        .filter(|key| ends.get(key) != Some(&1))
        .map(|(_, n)| n)
        .collect()
}

/// The name of the physical group `tag` of dimension `dim`, or its tag.
fn group_name(mesh: &Mesh, dim: u8, tag: i32) -> String {
    mesh.groups.iter().find(|g| g.dim == dim && g.tag == tag).map_or_else(|| format!("#{tag}"), |g| g.name.clone())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::rectangle;

    /// The unit square cut at y = ½ into surfaces 1 (below) and 2 (above), with the cut as
    /// curve 5; `bonded` keeps the cut's last segment out of the curve.
    fn two_halves(n: usize, order: usize, bonded: bool) -> Mesh {
        let mut mesh = rectangle(0.0, 1.0, 0.0, 1.0, n, n, order);
        for c in 0..mesh.n_cells() {
            mesh.cell_tags[c] = if mesh.cell_centroid(c)[1] > 0.5 { 2 } else { 1 };
        }
        let topology = Topology::new(&mesh);
        for (e, &[a, b]) in topology.facets.iter().enumerate() {
            let (pa, pb) = (mesh.points[a], mesh.points[b]);
            let on_cut = pa[1] == 0.5 && pb[1] == 0.5 && !(bonded && pa[0].max(pb[0]) > 1.0 - 0.5 / n as f64);
            if on_cut {
                let c = topology.facet_cells[e][0];
                let mid = mesh.cell(c)[3..].iter().copied().find(|&m| {
                    let p = mesh.points[m];
                    (p[0] - 0.5 * (pa[0] + pb[0])).abs() < 1e-12 && p[1] == 0.5
                });
                mesh.facet_nodes.extend([a, b].into_iter().chain(mid));
                mesh.facet_tags.push(5);
            }
        }
        mesh.groups.push(PhysicalGroup { dim: 2, tag: 2, name: "upper".into() });
        mesh.groups.push(PhysicalGroup { dim: 1, tag: 5, name: "cut".into() });
        mesh
    }

    #[test]
    fn the_split_makes_both_sides_boundaries() {
        for order in [1, 2] {
            let n = 4;
            let mut mesh = two_halves(n, order, false);
            let before = mesh.n_points();
            let interface = split(&mut mesh, 5, 2).unwrap();
            assert_eq!(interface.master_surface, 1);
            // every node of the cut is copied: n + 1 vertices and, for P2, n midpoints
            assert_eq!(mesh.n_points() - before, (n + 1) + if order == 2 { n } else { 0 });
            let topology = Topology::new(&mesh);
            for f in mesh.facets_tagged(&[interface.slave_curve, interface.master_curve]) {
                assert!(topology.is_boundary_facet(topology.tagged_facet[f]));
                let side = mesh.cell_tags[topology.tagged_cell(f)];
                let expected = if mesh.facet_tags[f] == 5 { 2 } else { 1 };
                assert_eq!(side, expected);
                let normal = topology.outward_normal(&mesh, f);
                assert_eq!(normal, if side == 2 { [0.0, -1.0] } else { [0.0, 1.0] });
            }
            // the two sides of a 4 × 4 square cut in two: the boundary is two closed loops
            let boundary = (0..topology.n_facets()).filter(|&e| topology.is_boundary_facet(e)).count();
            assert_eq!(boundary, 4 * n + 2 * n);
        }
    }

    #[test]
    fn a_bonded_end_stays_shared() {
        let n = 4;
        let mut mesh = two_halves(n, 1, true);
        let before = mesh.n_points();
        split(&mut mesh, 5, 2).unwrap();
        // the vertices of the joint's n − 1 segments less the bonded end (x = 0.75) and x = 1
        assert_eq!(mesh.n_points() - before, n - 1);
    }

    /// Source: docs/method.md §5.4 (two bodies). Goal: the lower half of one mesh and the upper
    /// half of a finer one make one mesh whose cut has 4 | 6 facets, meeting at its two ends,
    /// which the split copies for the slave; two meshes that differ on a bonded segment are
    /// refused. Parameters: [`two_halves`] of 4 × 4 and 6 × 6 cells, P1 and P2.
    #[test]
    fn sides_meshed_apart_are_merged_and_split() {
        for order in [1, 2] {
            // the lower half from a 4 × 4 mesh, the upper half from a 6 × 6 one
            let parts = [(two_halves(4, order, false), vec![1]), (two_halves(6, order, false), vec![2])];
            let mut mesh = merge_sides(&parts, &[5]).unwrap();
            assert_eq!(mesh.n_cells(), 16 + 36);
            let area: f64 = (0..mesh.n_cells()).map(|c| mesh.cell_area(c)).sum();
            assert!((area - 1.0).abs() < 1e-14);
            // both sides of the cut, 4 and 6 facets, meet at its two ends only
            let before = mesh.n_points();
            let interface = split(&mut mesh, 5, 2).unwrap();
            assert_eq!(interface.master_surface, 1);
            assert_eq!(mesh.n_points() - before, 2, "the two ends get the slave's copies");
            assert_eq!(mesh.facets_tagged(&[5]).count(), 6);
            assert_eq!(mesh.facets_tagged(&[interface.master_curve]).count(), 4);
            let topology = Topology::new(&mesh);
            for f in mesh.facets_tagged(&[5, interface.master_curve]) {
                let side = mesh.cell_tags[topology.tagged_cell(f)];
                assert_eq!(side, if mesh.facet_tags[f] == 5 { 2 } else { 1 });
            }
            // two closed loops: 4 + 4 + 2·2 … edges of the lower half, 6 + 6 + 2·3 of the upper
            let boundary = (0..topology.n_facets()).filter(|&e| topology.is_boundary_facet(e)).count();
            assert_eq!(boundary, (4 + 4 + 2 * 2) + (6 + 6 + 2 * 3));
        }
        // with a bonded end, the two meshes of the bonded segment differ: refused
        let parts = [(two_halves(4, 1, true), vec![1]), (two_halves(6, 1, true), vec![2])];
        let message = merge_sides(&parts, &[5]).unwrap_err();
        assert!(message.contains("do not match"), "{message}");
    }

    #[test]
    fn curves_that_are_not_joints_are_refused() {
        let mut mesh = two_halves(4, 1, false);
        let topology = Topology::new(&mesh);
        let outer = sides(&mesh, &topology, crate::mesh::structured::BOTTOM).unwrap_err();
        assert!(outer.contains("not shared by two surfaces"), "{outer}");
        mesh.cell_tags.fill(1);
        let inside = sides(&mesh, &Topology::new(&mesh), 5).unwrap_err();
        assert!(inside.contains("lies inside the surface 'domain'"), "{inside}");
    }
}
