//! The nonlinear system of contact, F(x) = 0 over the free displacement dofs, the state of its
//! faces, and the linearisation an iterate hands to the estimator.

use super::bond::BondState;
use super::nitsche::{ContactFace, FaceDisplacement, Nitsche};
use super::projection::Smoothing;
use super::{path, ContactError, ContactJoint, ContactSolution, Cracks, JointLine, Stage};
use crate::elasticity::{BodyForce, Discretisation, Problem, Refined};
use crate::fem::dofs::FIXED;
use crate::fem::sparse::{LinearSystem, SparsePattern};
use crate::geometry::{Point, Vector};
use crate::mesh::Mesh;
use crate::solve::{newton_until, LayerSchur, NewtonError, NewtonOptions, NonlinearSystem};
use std::sync::OnceLock;

/// The elasticity problem with Nitsche contact on some of its boundary curves.
pub struct ContactProblem<'a> {
    pub problem: &'a Problem,
    pub disc: &'a Discretisation,
    pub nitsche: Nitsche,
    pub smoothing: Smoothing,
    /// The pattern of K with the couplings of two-body faces (None: the discretisation's).
    coupled: Option<SparsePattern>,
    /// K over the free dofs and b = f + g_N − K_fc g_D, at the load factor λ of the load path
    /// (docs/method.md §1.11): b(λ) = b_w + λ (b − b_w).
    bulk: LinearSystem,
    /// On a load path: λ, b and b_w of the self-weight alone, and (H_u, H_d) of each uplift
    /// diagram at λ = 1 (None: the loads at λ = 1 only).
    staged: Option<Staged>,
    /// K factorised once with the dofs of the cells along Γ_C last, those of `layer_rows`
    /// after the others, made at the first Newton solve (None: Newton factors J by sparse LU).
    schur: OnceLock<Option<LayerSchur>>,
}

/// The loads of a load path ([`ContactProblem::stage_loads`]).
struct Staged {
    load_factor: f64,
    /// b and b_w over the free dofs.
    full: Vec<f64>,
    weight: Vec<f64>,
    /// (H_u, H_d) of each uplift diagram \[Pa\].
    uplift: Vec<[f64; 2]>,
}

/// Contact quantities of one face, for output.
#[derive(Debug, Clone, Copy, Default)]
pub struct FaceState {
    /// |F|.
    pub length: f64,
    /// Mean contact pressure −(1/|F|) ∫_F \[P_γ(u_h)\]_{reg,δ} ≥ 0: the normal traction of the
    /// solved equations, at the δ of the solve (docs/method.md §1.9).
    pub pressure: f64,
    /// Mean normal displacement (1/|F|) ∫_F u_h^n.
    pub normal_displacement: f64,
    /// Length of the part of F where P_γ(u_h) < 0 (in contact), or, with a bond, where it is not
    /// broken (P_γ(u_h) < γ o_c).
    pub contact_length: f64,
    /// max over the quadrature points of |[P_γ(u_h)]_{reg} − [P_γ(u_h)]_{R⁻}|.
    pub regularisation_error: f64,
    /// Mean tangential traction (1/|F|) ∫_F Π_S(P^t_γ(u_h)) along τ = (−ν_y, ν_x).
    pub tangential_traction: f64,
    /// Mean tangential displacement (1/|F|) ∫_F u_h^t: the slip on a rigid foundation.
    pub slip: f64,
    /// With friction, the lengths of the closed part where |P^t_γ(u_h)| < S (stick) and
    /// where |P^t_γ(u_h)| ≥ S (slip), for the plain projection.
    pub stick_length: f64,
    pub slip_length: f64,
    /// With uplift, the mean pore pressure (1/|F|) ∫_F p_u.
    pub uplift: f64,
    /// The first moment ∫_F x p_c ds of the contact pressure.
    pub pressure_moment: [f64; 2],
    /// ∫_F b(P_γ(u_h)) ds, the length over which the solved equations apply a cohesion: b the
    /// smoothed closed indicator q' of docs/method.md §1.7 (the closed length at δ = 0), or a
    /// bond's intact fraction (§1.13).
    pub cohesive_length: f64,
    /// The ends of the closed part of F (from its first closed point to its last), if any.
    pub closed: Option<[Point; 2]>,
    /// On a bonded joint, the mean damage (1/|F|) ∫_F o/o_c of the exact law.
    pub damage: f64,
    /// On a bonded joint, the lengths of F that are bonded, softening and broken (the exact law).
    pub bond_lengths: BondLengths,
}

/// The lengths of a bonded joint in each state \[m\] (in `summary.json` and `safety.json`).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct BondLengths {
    pub bonded: f64,
    /// Softening: the process zone.
    pub process_zone: f64,
    pub broken: f64,
}

impl BondLengths {
    /// The lengths summed over `faces`.
    pub fn of<'f>(faces: impl IntoIterator<Item = &'f FaceState>) -> BondLengths {
        faces.into_iter().fold(BondLengths::default(), |sum, f| sum.plus(&f.bond_lengths))
    }

    /// These lengths and `other`'s, summed.
    fn plus(&self, other: &BondLengths) -> BondLengths {
        BondLengths {
            bonded: self.bonded + other.bonded,
            process_zone: self.process_zone + other.process_zone,
            broken: self.broken + other.broken,
        }
    }

    /// `length` more in `state`.
    fn add(&mut self, state: BondState, length: f64) {
        *match state {
            BondState::Bonded => &mut self.bonded,
            BondState::Softening => &mut self.process_zone,
            BondState::Broken => &mut self.broken,
        } += length;
    }
}

impl FaceState {
    /// The state of the union of `parts` (of one facet): lengths and moments summed, means
    /// weighted by length, the largest regularisation error, closed from the first closed part
    /// to the last.
    pub fn merged<'s>(parts: impl IntoIterator<Item = &'s FaceState>) -> FaceState {
        let mut sum = FaceState::default();
        for part in parts {
            let w = part.length;
            sum.length += w;
            sum.pressure += part.pressure * w;
            sum.normal_displacement += part.normal_displacement * w;
            sum.tangential_traction += part.tangential_traction * w;
            sum.slip += part.slip * w;
            sum.uplift += part.uplift * w;
            sum.contact_length += part.contact_length;
            sum.cohesive_length += part.cohesive_length;
            sum.stick_length += part.stick_length;
            sum.slip_length += part.slip_length;
            sum.damage += part.damage * w;
            sum.bond_lengths = sum.bond_lengths.plus(&part.bond_lengths);
            sum.regularisation_error = sum.regularisation_error.max(part.regularisation_error);
            sum.pressure_moment = [0, 1].map(|i| sum.pressure_moment[i] + part.pressure_moment[i]);
            sum.closed = match (sum.closed, part.closed) {
                (Some([first, _]), Some([_, last])) => Some([first, last]),
                (closed, None) | (None, closed) => closed,
            };
        }
        let length = sum.length.max(f64::MIN_POSITIVE);
        for mean in [&mut sum.pressure, &mut sum.normal_displacement, &mut sum.tangential_traction, &mut sum.slip] {
            *mean /= length;
        }
        sum.uplift /= length;
        sum.damage /= length;
        sum
    }

    /// On a bonded joint, the state of most of the face: 0 bonded, 1 softening, 2 broken.
    pub fn bond_state(&self) -> f64 {
        let BondLengths { bonded, process_zone, broken } = self.bond_lengths;
        if broken > bonded.max(process_zone) {
            2.0
        } else if process_zone > bonded {
            1.0
        } else {
            0.0
        }
    }

    /// 0 open, 1 closed (stick, with friction), 2 slip (more of the face slips than sticks).
    pub fn status(&self) -> f64 {
        if self.contact_length == 0.0 {
            0.0
        } else if self.slip_length > self.stick_length {
            2.0
        } else {
            1.0
        }
    }
}

impl<'a> ContactProblem<'a> {
    /// Assembles the bulk terms once; the faces are those of `joint`.
    pub fn new(problem: &'a Problem, disc: &'a Discretisation, joint: &ContactJoint, smoothing: Smoothing) -> Self {
        let nitsche = joint.faces(problem, disc);
        let coupled = (!joint.masters.is_empty()).then(|| {
            let mesh = &problem.mesh;
            let pairs: Vec<Vec<usize>> = (nitsche.faces.iter())
                .filter_map(|f| f.opposite.as_ref().map(|o| [mesh.cell(f.cell), mesh.cell(o.cell)].concat()))
                .collect();
            SparsePattern::with_couplings(mesh, &disc.dofs, &pairs)
        });
        let bulk = problem.assemble_on(disc, coupled.as_ref().unwrap_or(&disc.pattern));
        ContactProblem { problem, disc, nitsche, smoothing, coupled, bulk, staged: None, schur: OnceLock::new() }
    }

    /// Makes the friction law act on the slip from the state of free unknowns `origin` (None:
    /// from rest), u^t − u^t_0 instead of u^t (docs/method.md §1.11).
    pub fn set_slip_origin(&mut self, origin: Option<&[f64]>) {
        let u0 = origin.map(|x| self.disc.dofs.expand(x));
        self.nitsche.set_slip_origin(&self.problem.mesh, u0);
    }

    /// Makes the loads those of the load path at λ = 1, b_w assembled from the self-weight
    /// `weight` per unit mass alone (with the Dirichlet data).
    pub fn stage_loads(&mut self, weight: Vector) {
        let alone =
            Problem { neumann: Vec::new(), body_force: BodyForce::Acceleration(weight), ..self.problem.clone() };
        let weight = alone.assemble_on(self.disc, self.pattern()).rhs;
        let uplift = self.nitsche.uplift.iter().map(|up| [up.diagram.upstream, up.diagram.downstream]).collect();
        self.staged = Some(Staged { load_factor: 1.0, full: self.bulk.rhs.clone(), weight, uplift });
    }

    /// Sets the load factor λ of the load path: b(λ) = b_w + λ (b − b_w) and p_u(λ) = λ p_u
    /// (b and p_u themselves at λ = 1).
    pub fn set_load_factor(&mut self, lambda: f64) {
        let Some(staged) = self.staged.as_mut() else { return };
        staged.load_factor = lambda;
        for ((b, full), weight) in self.bulk.rhs.iter_mut().zip(&staged.full).zip(&staged.weight) {
            *b = if lambda == 1.0 { *full } else { weight + lambda * (full - weight) };
        }
        for (up, [upstream, downstream]) in self.nitsche.uplift.iter_mut().zip(&staged.uplift) {
            up.diagram.upstream = lambda * upstream;
            up.diagram.downstream = lambda * downstream;
        }
    }

    /// The crack of each uplift diagram set to that of `cracks` (in order; None or missing:
    /// kept).
    pub fn set_cracks(&mut self, cracks: &Cracks) {
        for (up, crack) in self.nitsche.uplift.iter_mut().zip(cracks) {
            up.diagram.crack = crack.map_or(up.diagram.crack, |c| c.length);
        }
    }

    /// Whether the loads are those of λ = 1 (the problem's own).
    fn at_full_load(&self) -> bool {
        self.staged.as_ref().is_none_or(|s| s.load_factor == 1.0)
    }

    /// [`ContactError::LiftOff`] at `load_factor` for the state `x` ([`lifts_off`]).
    pub fn lift_off(&self, x: &[f64], load_factor: f64) -> Result<(), ContactError> {
        lifts_off(self.problem, &self.nitsche, &self.face_states(x), load_factor)
    }

    /// Sets the regularisation δ of the projection.
    pub fn set_delta(&mut self, delta: f64) {
        self.smoothing = Smoothing { delta };
    }

    /// The free dofs of the cells that own a contact face (and, on a joint between two
    /// bodies, of the master cells they face), sorted: the face terms touch no others.
    pub fn layer(&self) -> Vec<usize> {
        let (free, mut dofs) = (&self.disc.dofs.free, Vec::new());
        let mut layer: Vec<usize> = (0..self.nitsche.faces.len())
            .flat_map(|k| {
                self.nitsche.face_dofs(&self.problem.mesh, k, &mut dofs);
                dofs.iter().map(|&g| free[g]).filter(|&f| f != FIXED).collect::<Vec<_>>()
            })
            .collect();
        layer.sort_unstable();
        layer.dedup();
        layer
    }

    /// The free dofs of the layer on which the face terms have rows. For θ = 0 the test
    /// function of R_F is −γ v^n (and −γ v^t with friction; v^n of the jump \[v\] on a joint
    /// between two bodies), which vanishes at the nodes off Γ_C: the dofs of the nodes of the
    /// contact faces (and of the master facets they face). Otherwise θ σ^n(v) reaches every
    /// dof of the cell: the whole layer.
    pub fn layer_rows(&self) -> Vec<usize> {
        if (0..self.nitsche.faces.len()).any(|k| self.nitsche.theta(k) != 0.0) {
            return self.layer();
        }
        let mesh = &self.problem.mesh;
        let facets = self
            .nitsche
            .faces
            .iter()
            .flat_map(|f| std::iter::once(f.facet).chain(f.opposite.as_ref().map(|o| o.facet)));
        let mut rows: Vec<usize> = facets
            .flat_map(|f| mesh.facet(f).iter().flat_map(|&n| [2 * n, 2 * n + 1]))
            .map(|g| self.disc.dofs.free[g])
            .filter(|&f| f != FIXED)
            .collect();
        rows.sort_unstable();
        rows.dedup();
        rows
    }

    /// The fully active state: the solution with every point of Γ_C held closed, \[P_γ\]
    /// replaced by P_γ, and on a frictional joint sticking, Π_S(P^t_γ) replaced by P^t_γ (a
    /// linear problem, the bonded interface in Nitsche's form; one Newton step from u = 0).
    pub fn fully_active_start(&mut self) -> Result<Vec<f64>, NewtonError> {
        let smoothing = std::mem::replace(&mut self.smoothing, Smoothing::CLOSED);
        let x0 = vec![0.0; self.disc.dofs.n_free];
        let report = newton_until(self, x0, &NewtonOptions { max_iter: 1, ..Default::default() }, |it| !it.probe);
        self.smoothing = smoothing;
        Ok(report?.x)
    }

    /// F(x) and, when asked, its Jacobian (with the cohesion's indicator held fixed if
    /// `frozen`): the bulk K x − b and K, and the terms of each contact face.
    fn assemble(&self, x: &[f64], residual: &mut [f64], mut jacobian: Option<&mut [f64]>, frozen: bool) {
        // bulk: F = K x − b, J = K
        let pattern = self.pattern();
        pattern.multiply(&self.bulk.values, x, residual);
        for (r, b) in residual.iter_mut().zip(&self.bulk.rhs) {
            *r -= b;
        }
        if let Some(j) = jacobian.as_deref_mut() {
            j.copy_from_slice(&self.bulk.values);
        }
        let u_full = self.disc.dofs.expand(x);
        let n = self.nitsche.n_local();
        let (mut r_local, mut j_local, mut dofs) = (vec![0.0; n], vec![0.0; n * n], Vec::new());
        let free = &self.disc.dofs.free;
        for k in 0..self.nitsche.faces.len() {
            let u = local_displacement(&self.problem.mesh, &self.nitsche, k, &u_full, &mut dofs);
            let want_j = jacobian.is_some();
            let j = want_j.then_some(&mut j_local[..]);
            self.nitsche.face_terms(k, &u, self.smoothing, frozen, &mut r_local, j);
            for (i, &gi) in dofs.iter().enumerate() {
                let row = free[gi];
                if row == FIXED {
                    continue;
                }
                residual[row] += r_local[i];
                if let Some(j) = jacobian.as_deref_mut() {
                    for (c, &gc) in dofs.iter().enumerate() {
                        if free[gc] != FIXED {
                            j[pattern.position(row, free[gc])] += j_local[i * n + c];
                        }
                    }
                }
            }
        }
    }

    /// Contact state of every face for the free unknowns `x`.
    pub fn face_states(&self, x: &[f64]) -> Vec<FaceState> {
        let u_full = self.disc.dofs.expand(x);
        let mut dofs = Vec::new();
        (0..self.nitsche.faces.len())
            .map(|k| {
                let u = local_displacement(&self.problem.mesh, &self.nitsche, k, &u_full, &mut dofs);
                face_state(&self.nitsche, self.smoothing, k, &u)
            })
            .collect()
    }

    /// max |P_γ(u_h)| over the quadrature points of every contact face (those of the
    /// residual, split at the kinks of the projection) for the free unknowns `x`; 0 without
    /// contact faces.
    pub fn max_abs_p_gamma(&self, x: &[f64]) -> f64 {
        let u_full = self.disc.dofs.expand(x);
        let mut dofs = Vec::new();
        (0..self.nitsche.faces.len())
            .flat_map(|k| {
                let u = local_displacement(&self.problem.mesh, &self.nitsche, k, &u_full, &mut dofs);
                let points = self.nitsche.quadrature(k, &u, self.smoothing);
                points.into_iter().map(move |(s, _)| self.nitsche.p_gamma(k, &self.nitsche.point(k, s), &u).abs())
            })
            .fold(0.0, f64::max)
    }

    /// The solution `x` reached by `stages`, with the state of every face and the crack of
    /// each uplift diagram (`cracks`, in the order of `nitsche.uplift`; empty: none iterated).
    /// The refinement lo of the last stage's report is kept if that report ends at `x`. The
    /// system stays, so that Newton may go on from `x`.
    pub fn solution(&self, x: Vec<f64>, stages: Vec<Stage>, cracks: Cracks) -> ContactSolution {
        let faces = self.face_states(&x);
        let x_prev = stages.last().map_or_else(|| x.clone(), |s| s.report.x_prev.clone());
        let lo = stages.last().filter(|s| s.report.x == x).and_then(|s| s.report.lo.clone());
        let (smoothing, nitsche) = (self.smoothing, self.nitsche.clone());
        let path = Vec::new();
        let (coarse, discarded_steps) = (Vec::new(), 0);
        ContactSolution { x, lo, x_prev, smoothing, stages, faces, nitsche, cracks, coarse, path, discarded_steps }
    }

    /// The length open at the heel of each uplift diagram for `x`, over the faces of its curves
    /// ([`open_from_heel`]).
    pub fn crack_lengths(&self, x: &[f64]) -> Vec<f64> {
        let states = self.face_states(x);
        (self.nitsche.uplift.iter().enumerate())
            .map(|(d, up)| {
                let on = |k: &usize| self.nitsche.uplift_index(*k) == Some(d);
                let faces: Vec<FaceState> = (0..states.len()).filter(on).map(|k| states[k]).collect();
                open_from_heel(&faces, &up.diagram.line)
            })
            .collect()
    }

    /// The length of the contact face of diagram `d` at the distance `s` from its heel (its
    /// longest face if none holds it).
    pub(super) fn face_length_at(&self, d: usize, s: f64) -> f64 {
        let line = &self.nitsche.uplift[d].diagram.line;
        let span = |f: &ContactFace| f.ends.map(|e| line.distance(f.map.to_physical(e)));
        let holds = |f: &&ContactFace| {
            let [a, b] = span(f);
            a.min(b) <= s && s <= a.max(b)
        };
        let faces =
            || (self.nitsche.faces.iter().enumerate()).filter(|&(k, _)| self.nitsche.uplift_index(k) == Some(d));
        let mut own = faces().map(|(_, f)| f);
        own.find(holds).map_or_else(|| faces().map(|(_, f)| f.length).fold(0.0, f64::max), |f| f.length)
    }
}

/// The length of the joint open at the heel: the distance from the heel of the nearest closed
/// point (the whole joint if none is closed).
pub fn open_from_heel(faces: &[FaceState], line: &JointLine) -> f64 {
    let nearest = |[a, b]: [Point; 2]| line.distance(a).min(line.distance(b));
    faces.iter().filter_map(|f| f.closed.map(nearest)).fold(line.length, f64::min).max(0.0)
}

/// [`ContactError::LiftOff`] at `load_factor` if the joint of `nitsche` alone holds a body and
/// its faces' states `faces` keep less than [`path::LIFT_OFF`] of it in contact: what the
/// smoothing carries across the open joint is no equilibrium.
pub fn lifts_off(
    problem: &Problem,
    nitsche: &Nitsche,
    faces: &[FaceState],
    load_factor: f64,
) -> Result<(), ContactError> {
    let joint_length: f64 = nitsche.faces.iter().map(|f| f.length).sum();
    let contact_length: f64 = faces.iter().map(|f| f.contact_length).sum();
    match contact_length < path::LIFT_OFF * joint_length && joint_holds_body(problem, nitsche) {
        true => Err(ContactError::LiftOff { load_factor, contact_length, joint_length }),
        false => Ok(()),
    }
}

/// Whether only the joint holds a body of its faces against a rigid motion: that body's
/// Dirichlet conditions alone leave one free.
fn joint_holds_body(problem: &Problem, nitsche: &Nitsche) -> bool {
    let mesh = &problem.mesh;
    let body = mesh.bodies();
    let on_joint: std::collections::BTreeSet<usize> = nitsche.faces.iter().map(|f| body[f.cell]).collect();
    on_joint.into_iter().any(|b| {
        let mut nodes = vec![false; mesh.n_points()];
        for c in (0..mesh.n_cells()).filter(|&c| body[c] == b) {
            mesh.cell(c).iter().for_each(|&n| nodes[n] = true);
        }
        problem.free_rigid_motion_of(&nodes, &[]).is_some()
    })
}

/// The dofs of face k ([`Nitsche::face_dofs`]) and the displacement there.
pub(crate) fn local_displacement(
    mesh: &Mesh,
    nitsche: &Nitsche,
    k: usize,
    u_full: &[f64],
    dofs: &mut Vec<usize>,
) -> FaceDisplacement {
    nitsche.local(k, &values(mesh, nitsche, k, u_full, dofs), None)
}

/// The values of `u_full` at the dofs of face k ([`Nitsche::face_dofs`]).
fn values(mesh: &Mesh, nitsche: &Nitsche, k: usize, u_full: &[f64], dofs: &mut Vec<usize>) -> Vec<f64> {
    nitsche.face_dofs(mesh, k, dofs);
    dofs.iter().map(|&g| u_full[g]).collect()
}

/// The state of face k for the local displacement `u` of its cell, integrated on pieces
/// split at the kinks of the smoothing and of the plain projection.
fn face_state(nitsche: &Nitsche, smoothing: Smoothing, k: usize, u: &FaceDisplacement) -> FaceState {
    let length = nitsche.faces[k].length;
    let mut state = FaceState { length, ..Default::default() };
    let (law, mut cuts) = (nitsche.normal_law(k), nitsche.kinks(k, u, smoothing));
    // the joint is closed (in contact, or its bond not broken) where P_γ is below the P at
    // which it carries nothing
    let closes = law.carries_below();
    cuts.extend(nitsche.kinks(k, u, Smoothing::NONE));
    cuts.sort_by(f64::total_cmp);
    for (s, w) in nitsche.split_rule(k, &cuts) {
        let pt = nitsche.point(k, s);
        let p = nitsche.p_gamma(k, &pt, u);
        let mean = w / length;
        // the solved normal traction N(P_γ): p_c = −N(P_γ)
        let t_n = law.value(p, smoothing);
        state.pressure -= t_n * mean;
        for (m, x) in state.pressure_moment.iter_mut().zip(pt.x) {
            *m -= x * t_n * w;
        }
        state.cohesive_length += law.intact(p, smoothing).0 * w;
        let [normal, tangential] = nitsche.displacement_at(k, &pt, u);
        state.normal_displacement += normal * mean;
        state.contact_length += if p < closes { w } else { 0.0 };
        if let Some(bond) = law.state(p) {
            state.damage += law.damage(p) * mean;
            state.bond_lengths.add(bond, w);
        }
        let error = (t_n - law.value(p, Smoothing::NONE)).abs();
        state.regularisation_error = state.regularisation_error.max(error);
        state.uplift += nitsche.uplift_at(k, pt.x) * mean;
        if nitsche.law(k).has_friction() {
            state.tangential_traction += nitsche.tangential(k, &pt, u, smoothing).value * mean;
            state.slip += tangential * mean;
            let plain = nitsche.tangential(k, &pt, u, Smoothing::NONE);
            let sticks = nitsche.p_tangential(k, &pt, u).abs() < plain.threshold;
            if p < closes {
                *(if sticks { &mut state.stick_length } else { &mut state.slip_length }) += w;
            }
        }
    }
    // the pieces between the cuts are wholly open or closed
    let closed: Vec<&[f64]> = cuts
        .windows(2)
        .filter(|w| w[1] > w[0] && nitsche.p_gamma(k, &nitsche.point(k, 0.5 * (w[0] + w[1])), u) < closes)
        .collect();
    if let (Some(first), Some(last)) = (closed.first(), closed.last()) {
        state.closed = Some([nitsche.position(k, first[0]), nitsche.position(k, last[1])]);
    }
    state
}

impl NonlinearSystem for ContactProblem<'_> {
    fn pattern(&self) -> &SparsePattern {
        self.coupled.as_ref().unwrap_or(&self.disc.pattern)
    }

    /// Friction couples the normal traction into the tangential rows (docs/solver.md §2).
    fn monotone(&self) -> bool {
        self.nitsche.has_friction()
    }

    fn evaluate(&self, x: &[f64], residual: &mut [f64], jacobian: Option<&mut [f64]>) {
        self.assemble(x, residual, jacobian, false)
    }

    /// The Jacobian with the cohesion's closed indicator held at its value at x
    /// ([`Nitsche::face_terms`] with `frozen`), where some joint's threshold softens.
    fn frozen_jacobian(&self, x: &[f64], jacobian: &mut [f64]) -> bool {
        let softens = self.nitsche.softens();
        if softens {
            self.assemble(x, &mut vec![0.0; x.len()], Some(jacobian), true);
        }
        softens
    }

    /// The bulk K(x + lo) − b in difference form ([`Problem::residual`]) and each face's
    /// [`Nitsche::linearised_face_terms`]: P_γ(u_prev) and the increment u − u_prev, with
    /// u_h·ν − g from the compensated jump (docs/method.md §5.2).
    /// None below λ = 1 on a load path: the problem's loads are those of λ = 1.
    fn linearised_residual(&self, x: &[f64], lo: &[f64], x_prev: &[f64]) -> Option<Vec<f64>> {
        if !self.at_full_load() {
            return None;
        }
        let (problem, disc) = (self.problem, self.disc);
        let u = Refined { x: x.to_vec(), lo: lo.to_vec() }.displacement(problem, disc);
        let lo_nodes = u.lo.as_ref().expect("a refined displacement has lo");
        let prev = problem.displacement(disc, x_prev);
        let mut residual: Vec<f64> = problem.residual(disc, &u).iter().map(|r| -r).collect();
        let (mut r_local, mut dofs) = (vec![0.0; self.nitsche.n_local()], Vec::new());
        let at = |nodes: &[Vector], dofs: &[usize]| dofs.iter().map(|&g| nodes[g / 2][g % 2]).collect::<Vec<f64>>();
        for k in 0..self.nitsche.faces.len() {
            self.nitsche.face_dofs(&problem.mesh, k, &mut dofs);
            let (hi, lo, hi_prev) = (at(&u.hi, &dofs), at(lo_nodes, &dofs), at(&prev, &dofs));
            let nitsche = &self.nitsche;
            let (u_k, u_prev) = (nitsche.local(k, &hi, Some(&lo)), nitsche.local(k, &hi_prev, None));
            let step = nitsche.increment(k, &hi, Some(&lo), &hi_prev);
            nitsche.linearised_face_terms(k, &u_prev, &u_k, &step, self.smoothing, &mut r_local);
            for (&g, r) in dofs.iter().zip(&r_local) {
                if disc.dofs.free[g] != FIXED {
                    residual[disc.dofs.free[g]] += r;
                }
            }
        }
        Some(residual)
    }

    fn schur(&self) -> Option<&LayerSchur> {
        let build = || LayerSchur::new(self.pattern(), &self.bulk.values, &self.layer(), &self.layer_rows());
        self.schur.get_or_init(build).as_ref()
    }

    fn scale(&self) -> f64 {
        self.bulk.rhs.iter().map(|b| b * b).sum::<f64>().sqrt()
    }
}

/// A Newton iterate u^k on Γ_C as the estimator sees it: the faces, the smoothing of its
/// step and the previous iterate u^{k−1}, at which the Newton equation that u^k solves was
/// linearised.
pub struct Linearisation<'a> {
    pub nitsche: &'a Nitsche,
    pub smoothing: Smoothing,
    /// u^{k−1} at the nodes.
    pub u_prev: Vec<Vector>,
}

impl<'a> Linearisation<'a> {
    /// The state of an iterate whose previous iterate has the free unknowns `x_prev`.
    pub fn new(
        problem: &Problem,
        disc: &Discretisation,
        nitsche: &'a Nitsche,
        smoothing: Smoothing,
        x_prev: &[f64],
    ) -> Self {
        Linearisation { nitsche, smoothing, u_prev: problem.displacement(disc, x_prev) }
    }
}
