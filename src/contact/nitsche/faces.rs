//! The contact faces of Γ_C on a mesh: one per facet on a rigid foundation, and on a joint
//! between two bodies the pieces of each slave facet that face one master cell.

use super::{ContactFace, NitscheParameters, Opposite};
use crate::elasticity::Material;
use crate::fem::lagrange;
use crate::geometry::{distance, dot, sub, AffineMap, Point, Segment};
use crate::mesh::{Mesh, Topology};

/// The pieces of the slave face `face` that face one master facet each (`master`: facet and
/// its cell). A point x(s) = A + s(B − A) of the slave facet faces the point where the ray
/// x(s) + t ν meets a master facet C D, at r(s) = r₀ + s(r₁ − r₀) along it (affine in s): the
/// piece is where r ∈ [0, 1], kept if that master facet faces ν (n²·ν < 0) and lies within
/// |t| ≤ h_F + h_{F'}. On the matching sides of a split interface each slave facet faces one
/// master facet; a part of a slave facet that faces none carries no contact term.
pub(super) fn pieces(
    mesh: &Mesh,
    topology: &Topology,
    face: &ContactFace,
    master: &[(usize, usize)],
) -> Vec<ContactFace> {
    let ends = |f: usize| [mesh.points[mesh.facet(f)[0]], mesh.points[mesh.facet(f)[1]]];
    let [a, b] = ends(face.facet);
    let nu = face.direction;
    let h = mesh.facet_length(face.facet);
    let mut pieces: Vec<(f64, ContactFace)> = Vec::new();
    for &(f, cell) in master {
        let normal = topology.outward_normal(mesh, f);
        if dot(normal, nu) >= 0.0 {
            continue;
        }
        let [c, d] = ends(f);
        // x + t ν = C + r (D − C): t ν − r (D − C) = C − x, by Cramer's rule
        let e = sub(d, c);
        let det = -nu[0] * e[1] + nu[1] * e[0];
        if det.abs() <= 1e-12 * distance(c, d) {
            continue;
        }
        let solve = |x: Point| {
            let rhs = sub(c, x);
            let t = (-rhs[0] * e[1] + rhs[1] * e[0]) / det;
            let r = (nu[0] * rhs[1] - nu[1] * rhs[0]) / det;
            (t, r)
        };
        let [(t0, r0), (t1, r1)] = [a, b].map(solve);
        if r1 == r0 || t0.abs().max(t1.abs()) > h + distance(c, d) {
            continue;
        }
        let s_at = |r: f64| (r - r0) / (r1 - r0);
        let (lo, hi) = (s_at(0.0).min(s_at(1.0)).max(0.0), s_at(0.0).max(s_at(1.0)).min(1.0));
        if hi - lo <= 1e-12 {
            continue;
        }
        let local = |node: usize| lagrange::reference_vertex(mesh.cell(cell), node);
        let [rc, rd] = [local(mesh.facet(f)[0]), local(mesh.facet(f)[1])];
        let at = |s: f64| {
            let r = r0 + s * (r1 - r0);
            [rc[0] + r * (rd[0] - rc[0]), rc[1] + r * (rd[1] - rc[1])]
        };
        let slave = Segment::new(face.ends[0], face.ends[1]);
        pieces.push((
            lo,
            ContactFace {
                ends: [slave.point(lo), slave.point(hi)],
                length: (hi - lo) * h,
                opposite: Some(Opposite {
                    facet: f,
                    cell,
                    map: AffineMap::new(mesh.cell_vertices(cell)),
                    ends: [at(lo), at(hi)],
                }),
                ..face.clone()
            },
        ));
    }
    pieces.sort_by(|p, q| p.0.total_cmp(&q.0));
    pieces.into_iter().map(|(_, piece)| piece).collect()
}

pub(super) fn face(
    mesh: &Mesh,
    topology: &Topology,
    materials: &[Material],
    f: usize,
    curve: usize,
    parameters: &NitscheParameters,
) -> ContactFace {
    let cell = topology.tagged_cell(f);
    let nodes = mesh.facet(f);
    let length = mesh.facet_length(f);
    let (lambda, mu) = materials[cell].lame();
    let normal = topology.outward_normal(mesh, f);
    ContactFace {
        facet: f,
        cell,
        curve,
        map: AffineMap::new(mesh.cell_vertices(cell)),
        ends: [nodes[0], nodes[1]].map(|n| lagrange::reference_vertex(mesh.cell(cell), n)),
        normal,
        direction: parameters.direction.unwrap_or(normal),
        length,
        gamma: parameters.gamma0 * materials[cell].young / length,
        lambda,
        mu,
        opposite: None,
    }
}
