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

/// The two physical surfaces on either side of the curve `curve`, from its segments: Err (a
/// sentence) if a segment lies on the outer boundary, inside one surface, or between another
/// pair of surfaces than the first segment.
pub fn sides(mesh: &Mesh, topology: &Topology, curve: i32) -> Result<[i32; 2], String> {
    let name = group_name(mesh, 1, curve);
    let mut pair: Option<[i32; 2]> = None;
    for f in mesh.facets_tagged(&[curve]) {
        let [a, b] = topology.edge_cells[topology.facet_edges[f]];
        if b == NONE {
            return Err(format!(
                "curve '{name}' is not shared by two surfaces: part of it bounds '{}' only; a joint lies between \
                 two meshed surfaces (a rigid foundation is role = \"contact\")",
                group_name(mesh, 2, mesh.cell_tags[a])
            ));
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
    pair.ok_or_else(|| format!("curve '{name}' has no segments in the mesh"))
}

/// Splits the nodes of the curve `curve` between its two sides; the cells of the surface
/// `slave_surface` (one of [`sides`]) get the copies. Err: why the curve is not a joint.
pub fn split(mesh: &mut Mesh, curve: i32, slave_surface: i32) -> Result<Interface, String> {
    let topology = Topology::new(mesh);
    let pair = sides(mesh, &topology, curve)?;
    let master_surface = if pair[0] == slave_surface { pair[1] } else { pair[0] };
    let joint_facets: Vec<usize> = mesh.facets_tagged(&[curve]).collect();
    let joint_edges: BTreeSet<usize> = joint_facets.iter().map(|&f| topology.facet_edges[f]).collect();
    let is_slave = |c: usize| c != NONE && mesh.cell_tags[c] == slave_surface;
    // a vertex on an edge off the joint between a slave cell and another cell stays bonded
    let mut bonded = BTreeSet::new();
    for (e, &[a, b]) in topology.edge_cells.iter().enumerate() {
        if b != NONE && is_slave(a) != is_slave(b) && !joint_edges.contains(&e) {
            bonded.extend(topology.edges[e]);
        }
    }
    let mut copy: HashMap<usize, usize> = HashMap::new();
    for &f in &joint_facets {
        for node in mesh.facet(f).to_vec() {
            if !bonded.contains(&node) && !copy.contains_key(&node) {
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
    // facets off the joint follow the slave cells they bound
    let npf = mesh.nodes_per_facet();
    for f in (0..mesh.n_facets()).filter(|&f| mesh.facet_tags[f] != curve) {
        if topology.edge_cells[topology.facet_edges[f]].iter().any(|&c| is_slave(c)) {
            renumber(&mut mesh.facet_nodes[f * npf..(f + 1) * npf]);
        }
    }
    let master_curve = mesh.groups.iter().map(|g| g.tag).max().unwrap_or(0).max(curve) + 1;
    let name = format!("{}:{}", group_name(mesh, 1, curve), group_name(mesh, 2, master_surface));
    mesh.groups.push(PhysicalGroup { dim: 1, tag: master_curve, name });
    for &f in &joint_facets {
        let mut slave: Vec<usize> = mesh.facet(f).to_vec();
        renumber(&mut slave);
        mesh.facet_tags[f] = master_curve;
        mesh.facet_nodes.extend(slave);
        mesh.facet_tags.push(curve);
    }
    Ok(Interface { slave_curve: curve, master_curve, slave_surface, master_surface })
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
        for (e, &[a, b]) in topology.edges.iter().enumerate() {
            let (pa, pb) = (mesh.points[a], mesh.points[b]);
            let on_cut = pa[1] == 0.5 && pb[1] == 0.5 && !(bonded && pa[0].max(pb[0]) > 1.0 - 0.5 / n as f64);
            if on_cut {
                let c = topology.edge_cells[e][0];
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
                assert!(topology.is_boundary_edge(topology.facet_edges[f]));
                let side = mesh.cell_tags[topology.facet_cell(f)];
                let expected = if mesh.facet_tags[f] == 5 { 2 } else { 1 };
                assert_eq!(side, expected);
                let normal = topology.outward_normal(&mesh, f);
                assert_eq!(normal, if side == 2 { [0.0, -1.0] } else { [0.0, 1.0] });
            }
            // the two sides of a 4 × 4 square cut in two: the boundary is two closed loops
            let boundary = (0..topology.n_edges()).filter(|&e| topology.is_boundary_edge(e)).count();
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
