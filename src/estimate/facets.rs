//! The facets of Γ_C on both sides of a joint, each with the traction it carries
//! (docs/method.md §5.6).
//!
//! On a rigid foundation every contact face of the Nitsche terms is a whole boundary facet F,
//! and F carries t = t₁ + t₂ + t₃ of that face. On a joint between two bodies a contact face
//! is a piece of a slave facet that faces one master cell: the slave facet carries t on each of
//! its pieces, and the master facet F_m carries, at the point y(x) that faces x, the opposite
//! traction t^m(y) = −t(x) dx/dy, so that ∫_{F_m} t^m·v dy = −∫ t·v(y(x)) dx, the master part
//! of the jump term ∫ t·\[v\]. Parts of a slave facet that face no master carry nothing. The
//! reconstruction, the equilibration checks and the estimators see only facets and their
//! samples, so one body and two bodies take the same path.

use crate::contact::nitsche::FaceDisplacement;
use crate::contact::projection::Smoothing;
use crate::contact::Linearisation;
use crate::elasticity::Displacement;
use crate::fem::lagrange::reference_vertex;
use crate::fem::quadrature::gauss_segment_cached;
use crate::geometry::{distance, dot, sub, Point, Segment, Vector};
use crate::mesh::{Mesh, Topology};
use rayon::prelude::*;
use std::collections::HashMap;

/// A facet of Γ_C, on the slave side or on the master side of a joint.
pub struct ContactFacet {
    /// Its index among the topology's facets, and the cell that owns it.
    pub index: usize,
    pub cell: usize,
    /// Its end nodes; the facet parameter r ∈ [0, 1] runs from the first to the second.
    pub ends: [usize; 2],
    /// |F| and the outward unit normal of `cell`.
    pub length: f64,
    pub normal: Vector,
    pieces: Vec<Piece>,
}

/// A contact face seen from a facet: r = r₀ + s (r₁ − r₀) at its parameter s, and the datum
/// `sign` · t / dy_dx in the facet's measure dy = dy_dx · dx.
struct Piece {
    face: usize,
    r: [f64; 2],
    sign: f64,
    dy_dx: f64,
}

/// A point of a facet's rule: its parameter r, its weight in the facet's measure (× |F|), and
/// the facet's datum (t₁, t₂, t₃) there.
pub struct Sample {
    pub r: f64,
    pub weight: f64,
    pub t: [Vector; 3],
}

/// The facets of Γ_C of `state`: one per contact face on a rigid foundation; on a joint, the
/// slave facets with their pieces and the master facets with the pieces that face them.
pub fn contact_facets(mesh: &Mesh, topology: &Topology, state: &Linearisation) -> Vec<ContactFacet> {
    let mut facets: Vec<ContactFacet> = Vec::new();
    let mut index: HashMap<usize, usize> = HashMap::new();
    let mut add = |facet: ContactFacet, piece: Piece| {
        let k = *index.entry(facet.index).or_insert_with(|| {
            facets.push(facet);
            facets.len() - 1
        });
        facets[k].pieces.push(piece);
    };
    for (k, face) in state.nitsche.faces.iter().enumerate() {
        let ends = mesh.facet(face.facet);
        let slave = new_facet(mesh, topology.tagged_facet[face.facet], face.cell, [ends[0], ends[1]]);
        let r = face.ends.map(|xi| parameter(mesh, face.cell, slave.ends, xi));
        let Some(opposite) = &face.opposite else {
            add(slave, Piece { face: k, r, sign: 1.0, dy_dx: 1.0 });
            continue;
        };
        let ends = mesh.facet(opposite.facet);
        let master = new_facet(mesh, topology.tagged_facet[opposite.facet], opposite.cell, [ends[0], ends[1]]);
        let r_master = opposite.ends.map(|xi| parameter(mesh, opposite.cell, master.ends, xi));
        let dy_dx = (r_master[1] - r_master[0]).abs() * master.length / face.length;
        add(slave, Piece { face: k, r, sign: 1.0, dy_dx: 1.0 });
        add(master, Piece { face: k, r: r_master, sign: -1.0, dy_dx });
    }
    facets
}

/// A facet of Γ_C with its samples at one iterate ([`ContactFacet::samples`]).
pub struct SampledFacet {
    pub facet: ContactFacet,
    pub samples: Vec<Sample>,
}

/// The facets of Γ_C of `state` with their samples at `u`, computed once for the
/// reconstruction, the checks and the estimators of one estimate.
pub fn sampled_facets(mesh: &Mesh, topology: &Topology, state: &Linearisation, u: &Displacement) -> Vec<SampledFacet> {
    contact_facets(mesh, topology, state)
        .into_par_iter()
        .map(|facet| SampledFacet { samples: facet.samples(mesh, state, u), facet })
        .collect()
}

fn new_facet(mesh: &Mesh, index: usize, cell: usize, ends: [usize; 2]) -> ContactFacet {
    let (a, b) = (mesh.points[ends[0]], mesh.points[ends[1]]);
    let inside = mesh.cell(cell)[..3].iter().find(|&&v| v != ends[0] && v != ends[1]).map(|&v| mesh.points[v]);
    let normal = Segment::new(a, b).outward_normal(inside.expect("a triangle has a vertex off each edge"));
    ContactFacet { index, cell, ends, length: distance(a, b), normal, pieces: Vec::new() }
}

/// The facet parameter of the reference point ξ of `cell` on the facet with nodes `ends`,
/// taken in reference coordinates (exact for ξ on the facet, with no rounding of |x|).
fn parameter(mesh: &Mesh, cell: usize, ends: [usize; 2], xi: Point) -> f64 {
    let [a, b] = ends.map(|n| reference_vertex(mesh.cell(cell), n));
    let d = sub(b, a);
    dot(sub(xi, a), d) / dot(d, d)
}

impl ContactFacet {
    /// The reference point of `cell` at facet parameter r.
    pub fn reference_point(&self, mesh: &Mesh, r: f64) -> Point {
        let [a, b] = self.ends.map(|n| reference_vertex(mesh.cell(self.cell), n));
        Segment::new(a, b).point(r)
    }

    /// The physical midpoint, where a violation on the facet is reported.
    pub fn midpoint(&self, mesh: &Mesh) -> Point {
        Segment::new(mesh.points[self.ends[0]], mesh.points[self.ends[1]]).point(0.5)
    }

    /// The facet's rule with its datum (t₁, t₂, t₃): every piece's rule (split at the kinks of
    /// t), and a Gauss rule of `order` + 1 points with t = 0 on the parts no piece covers, so that
    /// the rule integrates P_{2p} over the whole facet.
    pub fn samples(&self, mesh: &Mesh, state: &Linearisation, u: &Displacement) -> Vec<Sample> {
        let mut samples = Vec::new();
        let mut covered = Vec::new();
        let mut dofs = Vec::new();
        for piece in &self.pieces {
            state.nitsche.face_dofs(mesh, piece.face, &mut dofs);
            let hi: Vec<f64> = dofs.iter().map(|&g| u.hi[g / 2][g % 2]).collect();
            let lo: Option<Vec<f64>> = u.lo.as_ref().map(|lo| dofs.iter().map(|&g| lo[g / 2][g % 2]).collect());
            let hi_prev: Vec<f64> = dofs.iter().map(|&g| state.u_prev[g / 2][g % 2]).collect();
            let nitsche = state.nitsche;
            let uk = nitsche.local(piece.face, &hi, lo.as_deref());
            let u_prev = nitsche.local(piece.face, &hi_prev, None);
            let step = nitsche.increment(piece.face, &hi, lo.as_deref(), &hi_prev);
            let scale = piece.sign / piece.dy_dx;
            for (s, w) in contact_rule(state, piece.face, &uk, &u_prev) {
                let t = tractions(state, piece.face, s, [&uk, &u_prev, &step]).map(|t| t.map(|ti| scale * ti));
                samples.push(Sample { r: piece.r[0] + s * (piece.r[1] - piece.r[0]), weight: w * piece.dy_dx, t });
            }
            covered.push([piece.r[0].min(piece.r[1]), piece.r[0].max(piece.r[1])]);
        }
        let rule = gauss_segment_cached(mesh.order + 1);
        for [lo, hi] in uncovered(covered) {
            for (&s, &w) in rule.points.iter().zip(&rule.weights) {
                samples.push(Sample { r: lo + s * (hi - lo), weight: w * (hi - lo) * self.length, t: [[0.0; 2]; 3] });
            }
        }
        samples
    }
}

/// The parts of [0, 1] that the intervals leave uncovered, longer than round-off.
fn uncovered(mut intervals: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    intervals.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let mut gaps = Vec::new();
    let mut reached = 0.0_f64;
    for [lo, hi] in intervals.into_iter().chain([[1.0, 1.0]]) {
        if lo - reached > 1e-12 {
            gaps.push([reached, lo]);
        }
        reached = reached.max(hi);
    }
    gaps
}

/// The Γ_C tractions (t₁, t₂, t₃) at parameter `s` of contact face k, for the displacements
/// `u` and `u_prev` of its cells and the increment `step` = u − u_prev: the exact traction, the
/// smoothing's part and the linearisation's part, t₁ + t₂ + t₃ the traction of the Newton step
/// (docs/method.md §4.3).
fn tractions(c: &Linearisation, k: usize, s: f64, [u, u_prev, step]: [&FaceDisplacement; 3]) -> [Vector; 3] {
    let point = c.nitsche.point(k, s);
    let exact = c.nitsche.traction(k, &point, u, Smoothing::NONE);
    let regularised = c.nitsche.traction(k, &point, u, c.smoothing);
    let linearised = c.nitsche.linearised_traction(k, &point, u_prev, step, c.smoothing);
    [exact, sub(regularised, exact), sub(linearised, regularised)]
}

/// The rule on contact face k split at every kink of t₁, t₂ and t₃: (s, weight · |F|).
fn contact_rule(c: &Linearisation, k: usize, u: &FaceDisplacement, u_prev: &FaceDisplacement) -> Vec<(f64, f64)> {
    let mut cuts = c.nitsche.kinks(k, u, Smoothing::NONE);
    cuts.extend(c.nitsche.kinks(k, u, c.smoothing));
    cuts.extend(c.nitsche.kinks(k, u_prev, c.smoothing));
    cuts.sort_by(f64::total_cmp);
    c.nitsche.split_rule(k, &cuts)
}

#[cfg(test)]
mod tests {
    use super::uncovered;

    #[test]
    fn uncovered_parts_are_the_gaps_between_the_pieces() {
        assert_eq!(uncovered(vec![[0.5, 1.0], [0.0, 0.25]]), vec![[0.25, 0.5]]);
        assert!(uncovered(vec![[0.0, 0.5], [0.5, 1.0]]).is_empty());
        assert_eq!(uncovered(Vec::new()), vec![[0.0, 1.0]]);
    }
}
