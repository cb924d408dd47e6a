//! Unilateral contact on Γ_C with a rigid foundation, or across a joint between two meshed
//! bodies (docs/method.md §1.10), by Nitsche's method.
//!
//! A [`ContactJoint`] is the one description of a contact boundary, built by the scene: where
//! (the physical tags of Γ_C), for each of its curves which law and which Nitsche parameters
//! ([`CurveLaw`]), and the uplift diagrams with the curves each acts on ([`CurveUplift`]). On a
//! mesh it becomes the faces of [`Nitsche`], each reading the law and the uplift of its curve.
//! [`ContactProblem`] is the nonlinear system F(x) = 0 over the free displacement dofs,
//!
//!   F(u; v) = (σ(u), ε(v)) − (f, v) − (g_N, v)_{Γ_N} + Σ_F R_F(u; v),
//!
//! with the face terms R_F of [`nitsche`] and the [`Smoothing`] of the projection at δ. The
//! bulk stiffness K and load b are assembled once; each evaluation adds the face terms of the
//! cells that own a contact face. A solve returns a [`ContactSolution`]: the iterate, the
//! linearisation point and smoothing it was computed with, and the state of every face.

pub mod law;
pub mod nitsche;
pub mod path;
pub mod projection;
pub mod resultant;
pub mod strength;
pub mod uplift;

use crate::elasticity::{nodal, BodyForce, Discretisation, Displacement, Problem, Refined};
use crate::fem::dofs::FIXED;
use crate::fem::sparse::{LinearSystem, SparsePattern};
use crate::mesh::Mesh;
use crate::solve::{newton, newton_until, LayerSchur, NewtonError, NewtonOptions, NewtonReport, NonlinearSystem};
pub use law::JointLaw;
use nitsche::{ContactFace, FaceDisplacement, Nitsche, NitscheParameters};
pub use path::{LoadPath, NoEquilibrium, PathPoint};
use projection::{negative_part, Smoothing};
pub use resultant::{JointLine, Resultant};
use std::sync::OnceLock;
use std::time::Instant;
pub use strength::{reduce_strength, strength_reduction, StrengthError, StrengthReduction, STRENGTH_TOLERANCE};
pub use uplift::{CrackRule, Uplift};

/// The joint law and the Nitsche parameters of one curve of Γ_C.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveLaw {
    pub law: JointLaw,
    pub parameters: NitscheParameters,
}

impl CurveLaw {
    /// This curve with its strength divided by k ([`JointLaw::reduced`]).
    pub fn reduced(&self, k: f64) -> CurveLaw {
        CurveLaw { law: self.law.reduced(k), ..*self }
    }
}

/// An uplift diagram and the curves of Γ_C it acts on (indices into [`ContactJoint::tags`]):
/// one diagram along several curves on one straight line, or a curve's own.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveUplift {
    pub curves: Vec<usize>,
    pub diagram: Uplift,
}

/// A contact boundary: the curves of Γ_C, and the joint law and Nitsche parameters of each.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactJoint {
    /// Physical tags of the curves of Γ_C (on a joint between two bodies, the slave sides).
    pub tags: Vec<i32>,
    /// On joints between two bodies, the physical tag of the master side's curve facing each
    /// curve of `tags`; empty: a rigid foundation.
    pub masters: Vec<i32>,
    /// The law and Nitsche parameters of each curve of `tags`, in the same order.
    pub laws: Vec<CurveLaw>,
    /// The pore-water pressure diagrams in the joint, each on its curves (a curve on at most
    /// one); empty: no uplift.
    pub uplift: Vec<CurveUplift>,
    /// The nodal displacements (dof 2i + a) of the state that the friction law measures slip
    /// from (None: rest); of a joint as solved on a load path, the state before the last.
    pub slip_origin: Option<Vec<f64>>,
}

impl ContactJoint {
    /// A joint on the curves `tags` (facing the curves `masters` on two bodies, or none: a rigid
    /// foundation), every curve with `law` and `parameters`.
    pub fn uniform(tags: Vec<i32>, masters: Vec<i32>, law: JointLaw, parameters: NitscheParameters) -> Self {
        let laws = vec![CurveLaw { law, parameters }; tags.len()];
        ContactJoint { tags, masters, laws, uplift: Vec::new(), slip_origin: None }
    }

    /// This joint with the uplift `diagram` along all of its curves.
    pub fn with_uplift(self, diagram: Uplift) -> Self {
        let curves = (0..self.tags.len()).collect();
        ContactJoint { uplift: vec![CurveUplift { curves, diagram }], ..self }
    }

    /// A frictionless joint on the curves `tags`.
    pub fn frictionless(tags: Vec<i32>, parameters: NitscheParameters) -> Self {
        ContactJoint::uniform(tags, Vec::new(), JointLaw::Frictionless, parameters)
    }

    /// Whether some curve has a tangential traction.
    pub fn has_friction(&self) -> bool {
        self.laws.iter().any(|c| c.law.has_friction())
    }

    /// Whether some curve i with `plane[i]` has a tangential traction (the sliding plane of
    /// [`ContactJoint::reduced`] has a strength to divide).
    pub fn has_friction_on(&self, plane: &[bool]) -> bool {
        self.laws.iter().zip(plane).any(|(c, &on)| on && c.law.has_friction())
    }

    /// The joint with the strength of the curves i with `plane[i]` divided by k (strength
    /// reduction on a sliding plane; the other curves keep theirs).
    pub fn reduced(&self, k: f64, plane: &[bool]) -> ContactJoint {
        let laws = self.laws.iter().zip(plane).map(|(c, &on)| if on { c.reduced(k) } else { *c }).collect();
        ContactJoint { laws, ..self.clone() }
    }

    /// Every curve: the whole joint as the sliding plane of [`ContactJoint::reduced`].
    pub fn every_curve(&self) -> Vec<bool> {
        vec![true; self.laws.len()]
    }

    /// The contact faces of the joint on the mesh of `problem`.
    pub fn faces(&self, problem: &Problem, disc: &Discretisation) -> Nitsche {
        Nitsche::new(&problem.mesh, &disc.topology, &problem.materials, self)
    }

    /// This joint with the uplift that `solution` was found with (its crack included).
    pub fn as_solved(&self, solution: &ContactSolution) -> ContactJoint {
        let (uplift, slip_origin) =
            (solution.nitsche.uplift.clone(), solution.nitsche.slip_origin().map(<[f64]>::to_vec));
        ContactJoint { uplift, slip_origin, ..self.clone() }
    }
}

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
    /// Length of the part of F where P_γ(u_h) < 0.
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
    /// ∫_F q'(P_γ(u_h)) ds, the length over which the solved equations apply a cohesion: the
    /// smoothed closed indicator of docs/method.md §1.7 (the closed length at δ = 0).
    pub cohesive_length: f64,
    /// The ends of the closed part of F (from its first closed point to its last), if any.
    pub closed: Option<[[f64; 2]; 2]>,
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
        sum
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
    pub fn stage_loads(&mut self, weight: [f64; 2]) {
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
            let u = local(&self.problem.mesh, &self.nitsche, k, &u_full, &mut dofs);
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
                let u = local(&self.problem.mesh, &self.nitsche, k, &u_full, &mut dofs);
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
                let u = local(&self.problem.mesh, &self.nitsche, k, &u_full, &mut dofs);
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
        ContactSolution { x, lo, x_prev, smoothing, stages, faces, nitsche, cracks, coarse: Vec::new(), path }
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
    fn face_length_at(&self, d: usize, s: f64) -> f64 {
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
    let nearest = |[a, b]: [[f64; 2]; 2]| line.distance(a).min(line.distance(b));
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
fn local(mesh: &Mesh, nitsche: &Nitsche, k: usize, u_full: &[f64], dofs: &mut Vec<usize>) -> FaceDisplacement {
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
    let mut cuts = nitsche.kinks(k, u, smoothing);
    cuts.extend(nitsche.kinks(k, u, Smoothing::NONE));
    cuts.sort_by(f64::total_cmp);
    for (s, w) in nitsche.split_rule(k, &cuts) {
        let pt = nitsche.point(k, s);
        let p = nitsche.p_gamma(k, &pt, u);
        let mean = w / length;
        // the solved normal traction q(P_γ): p_c = −q(P_γ)
        let t_n = smoothing.value(p);
        state.pressure -= t_n * mean;
        for (m, x) in state.pressure_moment.iter_mut().zip(pt.x) {
            *m -= x * t_n * w;
        }
        state.cohesive_length += smoothing.derivative(p) * w;
        let [normal, tangential] = nitsche.displacement_at(k, &pt, u);
        state.normal_displacement += normal * mean;
        state.contact_length += if p < 0.0 { w } else { 0.0 };
        let error = (smoothing.value(p) - negative_part(p)).abs();
        state.regularisation_error = state.regularisation_error.max(error);
        state.uplift += nitsche.uplift_at(k, pt.x) * mean;
        if nitsche.law(k).has_friction() {
            state.tangential_traction += nitsche.tangential(k, &pt, u, smoothing).value * mean;
            state.slip += tangential * mean;
            let plain = nitsche.tangential(k, &pt, u, Smoothing::NONE);
            let sticks = nitsche.p_tangential(k, &pt, u).abs() < plain.threshold;
            if p < 0.0 {
                *(if sticks { &mut state.stick_length } else { &mut state.slip_length }) += w;
            }
        }
    }
    // the pieces between the cuts are wholly open or closed
    let closed: Vec<&[f64]> = cuts
        .windows(2)
        .filter(|w| w[1] > w[0] && nitsche.p_gamma(k, &nitsche.point(k, 0.5 * (w[0] + w[1])), u) < 0.0)
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

    /// Friction couples the normal traction into the tangential rows (docs/method.md §1.5).
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
        let at = |nodes: &[[f64; 2]], dofs: &[usize]| dofs.iter().map(|&g| nodes[g / 2][g % 2]).collect::<Vec<f64>>();
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

/// Newton at one regularisation δ of a continuation path.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Stage {
    pub delta: f64,
    pub report: NewtonReport,
}

/// Newton along the path δ_k = max(delta, delta_start / 10^k), each stage starting from the
/// previous solution; for delta = 0 the path jumps to 0 after eight decades. A direct solve
/// at a tiny δ from a poor initial guess moves the active set one face per step; the path
/// reaches it in a few steps per stage. `delta_start ≤ delta` is one stage. A path from rest
/// (x0 = 0) whose first stage fails starts that stage again from the closed (and sticking)
/// state ([`ContactProblem::fully_active_start`]): from u = 0 Newton can slide a body that a
/// frictional joint alone holds far into slip, where it stalls (docs/method.md §1.10), and
/// without friction the first step on a body that only its contact holds is set by round-off.
pub fn continuation(
    contact: &mut ContactProblem,
    delta: f64,
    delta_start: f64,
    x0: Vec<f64>,
    options: &NewtonOptions,
) -> Result<(Vec<f64>, Vec<Stage>), NewtonError> {
    let mut stages: Vec<Stage> = Vec::new();
    let from_rest = x0.iter().all(|&v| v == 0.0);
    let mut x = x0;
    let mut current = delta_start.max(delta);
    loop {
        contact.set_delta(current);
        let report = match newton(contact, x, options) {
            Err(_) if from_rest && stages.is_empty() => {
                let closed = contact.fully_active_start()?;
                newton(contact, closed, options)?
            }
            attempt => attempt?,
        };
        x = report.x.clone();
        stages.push(Stage { delta: current, report });
        if current <= delta * (1.0 + 1e-9) {
            return Ok((x, stages));
        }
        let next = current / 10.0;
        current = if next < 1e-8 * delta_start { delta } else { next.max(delta) };
    }
}

/// How `damfem solve` reaches the regularisation δ: a continuation path from `delta_start`.
#[derive(Debug, Clone, Copy)]
pub struct Continuation {
    /// Target regularisation δ \[Pa\] (0: the plain projection with its semismooth derivative).
    pub delta: f64,
    /// First δ of the path (≤ delta: a single Newton solve at delta).
    pub delta_start: f64,
    pub newton: NewtonOptions,
    /// From rest, the load path ([`path::follow`]) rather than every load at once (None).
    pub path: Option<LoadPath>,
}

/// A contact iterate and what it was computed with.
#[derive(Clone)]
pub struct ContactSolution {
    /// Free unknowns.
    pub x: Vec<f64>,
    /// The refinement of x by its last Newton step's factors: the iterate is the pair x + lo
    /// (docs/method.md §5.2); None: x.
    pub lo: Option<Vec<f64>>,
    /// The iterate before the last Newton step: the linearisation point of x.
    pub x_prev: Vec<f64>,
    /// The smoothing of the last Newton step.
    pub smoothing: Smoothing,
    pub stages: Vec<Stage>,
    /// State of every contact face.
    pub faces: Vec<FaceState>,
    /// The contact faces and parameters.
    pub nitsche: Nitsche,
    /// With uplift in an open crack, the fixed point that found it, for each diagram of
    /// `nitsche.uplift` in order (None: its crack is not filled; empty: not iterated). The
    /// crack itself is in the diagram.
    pub cracks: Cracks,
    /// The solves on coarser meshes whose solution started Newton ([`nested_start`]), coarsest
    /// first; empty for a start from u = 0.
    pub coarse: Vec<CoarseSolve>,
    /// The converged states of the load path that led to it (empty: none followed).
    pub path: Vec<PathPoint>,
}

/// A solve of nested iteration on a coarser level: its element degree, unknowns, Newton steps
/// and times.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CoarseSolve {
    /// 1 on the degree-1 problem of the given mesh's triangles (docs/method.md §1.5).
    pub order: usize,
    pub unknowns: usize,
    pub newton_steps: usize,
    pub seconds: CoarseTimings,
}

/// Wall times of a level of nested iteration, in seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct CoarseTimings {
    /// The level's mesh and problem: gmsh's mesh, or the vertices of the given mesh
    /// ([`CoarseLevel::seconds`]).
    pub mesh: f64,
    /// Dofs, pattern and the bulk stiffness and load.
    pub assemble: f64,
    /// The solution of the level below interpolated at this level's nodes.
    pub start: f64,
    /// Newton, the once-per-mesh factorisation of the stiffness included.
    pub newton: f64,
}

/// A coarser level of nested iteration: its problem (on a coarser mesh of the geometry, or at
/// degree 1 on the given mesh's triangles), its joint, and the wall time taken to make them
/// \[s\].
pub struct CoarseLevel {
    pub problem: Problem,
    pub joint: ContactJoint,
    pub seconds: f64,
}

impl ContactSolution {
    /// The state of every boundary facet that carries a contact face, by facet index: the
    /// pieces of a slave facet merged ([`FaceState::merged`]) and, on a joint between two
    /// bodies, each master facet with the pieces that face it (the same jump and pressure).
    pub fn facet_states(&self) -> std::collections::BTreeMap<usize, FaceState> {
        let mut parts: std::collections::BTreeMap<usize, Vec<&FaceState>> = Default::default();
        for (face, state) in self.nitsche.faces.iter().zip(&self.faces) {
            parts.entry(face.facet).or_default().push(state);
            if let Some(opposite) = &face.opposite {
                parts.entry(opposite.facet).or_default().push(state);
            }
        }
        parts.into_iter().map(|(facet, states)| (facet, FaceState::merged(states))).collect()
    }

    /// Total number of Newton steps over all stages.
    pub fn newton_steps(&self) -> usize {
        self.stages.iter().map(|s| s.report.iterations.len()).sum()
    }

    /// Total length of the contact zone {P_γ(u_h) < 0}.
    pub fn contact_length(&self) -> f64 {
        self.faces.iter().map(|f| f.contact_length).sum()
    }

    /// The normal force the joint carries, N = ∫_{Γ_C} p_c ds \[N/m\] (compression positive).
    pub fn normal_force(&self) -> f64 {
        self.forces(|_| true).normal_force
    }

    /// The tangential force T = ∫_{Γ_C} t^t ds \[N/m\] along τ = (−ν_y, ν_x).
    pub fn tangential_force(&self) -> f64 {
        self.forces(|_| true).tangential_force
    }

    /// FS_LE of the whole of Γ_C ([`JointForces::sliding_safety_factor`]).
    pub fn sliding_safety_factor(&self) -> Option<f64> {
        self.forces(|_| true).sliding_safety_factor
    }

    /// The forces on the faces k with `on(k)`, each face with its curve's law (docs/method.md
    /// §1.9): N = ∫ p_c ds, T = ∫ t^t ds, the contact length and FS_LE = ∫ (c q'(P_γ) + F p_c)
    /// ds / |T| (s q'(P_γ) for Tresca, q' the smoothed closed indicator; 1_closed at δ = 0), None without friction or
    /// shear there.
    pub fn forces(&self, on: impl Fn(usize) -> bool) -> JointForces {
        let (mut n, mut t, mut contact_length, mut capacity, mut friction) = (0.0, 0.0, 0.0, 0.0, false);
        for (k, f) in self.faces.iter().enumerate().filter(|&(k, _)| on(k)) {
            let law = self.nitsche.law(k);
            n += f.pressure * f.length;
            t += f.tangential_traction * f.length;
            contact_length += f.contact_length;
            capacity += law.capacity(f.pressure * f.length, f.cohesive_length);
            friction |= law.has_friction();
        }
        let sliding_safety_factor = (friction && t != 0.0).then(|| capacity / t.abs());
        JointForces { contact_length, normal_force: n, tangential_force: t, sliding_safety_factor }
    }

    /// The uplift force U = ∫_{Γ_C} p_u ds \[N/m\].
    pub fn uplift_force(&self) -> f64 {
        self.uplift_force_of(|_| true)
    }

    /// The uplift force ∫ p_u ds \[N/m\] on the faces k with `on(k)`.
    pub fn uplift_force_of(&self, on: impl Fn(usize) -> bool) -> f64 {
        (self.faces.iter().enumerate()).filter(|&(k, _)| on(k)).map(|(_, f)| f.uplift * f.length).sum()
    }

    /// The curves with a face on `line`, per curve of the joint: the sliding plane of
    /// [`ContactJoint::reduced`].
    pub fn curves_on(&self, line: &JointLine) -> Vec<bool> {
        let mut plane = vec![false; self.nitsche.laws.len()];
        for (k, face) in self.nitsche.faces.iter().enumerate() {
            plane[face.curve] |= self.on_line(k, line);
        }
        plane
    }

    /// Whether every face lies on one straight line, that of the first face (one sliding
    /// plane, not a lift joint above a base).
    pub fn on_one_line(&self) -> bool {
        if self.nitsche.faces.is_empty() {
            return true;
        }
        let line = JointLine::new(self.nitsche.position(0, 0.0), self.nitsche.position(0, 1.0));
        (0..self.faces.len()).all(|k| self.on_line(k, &line))
    }

    /// Whether face k lies on `line` (a sliding plane among other joints).
    pub fn on_line(&self, k: usize, line: &JointLine) -> bool {
        [0.0, 1.0].iter().all(|&s| line.holds(self.nitsche.position(k, s)))
    }

    /// The states of the faces on `line`.
    fn faces_on(&self, line: &JointLine) -> Vec<FaceState> {
        (self.faces.iter().enumerate()).filter(|&(k, _)| self.on_line(k, line)).map(|(_, f)| *f).collect()
    }

    /// The forces on the faces on `line` ([`ContactSolution::forces`]).
    pub fn forces_on(&self, line: &JointLine) -> JointForces {
        self.forces(|k| self.on_line(k, line))
    }

    /// The resultant of the traction of the faces on the straight joint `line` (docs/method.md
    /// §1.9); None when nothing presses on the joint.
    pub fn resultant(&self, line: &JointLine) -> Option<Resultant> {
        let faces = self.faces_on(line);
        let moment = faces.iter().fold([0.0; 2], |m, f| [m[0] + f.pressure_moment[0], m[1] + f.pressure_moment[1]]);
        let JointForces { normal_force, tangential_force, .. } = self.forces_on(line);
        let uplift = faces.iter().map(|f| f.uplift * f.length).sum();
        Resultant::new(line, [normal_force, tangential_force, uplift], moment)
    }

    /// The length of `line` open at the heel ([`open_from_heel`]).
    pub fn crack_from_heel(&self, line: &JointLine) -> f64 {
        open_from_heel(&self.faces_on(line), line)
    }

    /// The mean effective normal stress σ'^n = q(P_γ) = −p_c \[Pa\] (tension positive) of the
    /// solved equations over the part of `line` at the distances `window` = \[s₀, s₁\] from the
    /// heel, integrated exactly on pieces split at the kinks of p_c and at s₀, s₁.
    pub fn mean_normal_stress(
        &self,
        problem: &Problem,
        disc: &Discretisation,
        line: &JointLine,
        window: [f64; 2],
    ) -> f64 {
        let u_full = disc.dofs.expand(&self.x);
        let mut dofs = Vec::new();
        let mut integral = 0.0;
        for k in (0..self.nitsche.faces.len()).filter(|&k| self.on_line(k, line)) {
            let [d0, d1] = [0.0, 1.0].map(|t| line.distance(self.nitsche.position(k, t)));
            // the window's ends in the face parameter t: s(t) = d0 + t (d1 − d0)
            let [a, b] = window.map(|s| (s - d0) / (d1 - d0));
            let (lo, hi) = (a.min(b).max(0.0), a.max(b).min(1.0));
            if lo >= hi {
                continue;
            }
            let u = local(&problem.mesh, &self.nitsche, k, &u_full, &mut dofs);
            let mut cuts = self.nitsche.kinks(k, &u, self.smoothing);
            cuts.extend([lo, hi]);
            cuts.sort_by(f64::total_cmp);
            integral += self
                .nitsche
                .split_rule(k, &cuts)
                .into_iter()
                .filter(|&(t, _)| t > lo && t < hi)
                .map(|(t, w)| self.smoothing.value(self.nitsche.p_gamma(k, &self.nitsche.point(k, t), &u)) * w)
                .sum::<f64>();
        }
        integral / (window[1] - window[0])
    }

    /// With friction, the total length of the closed part that sticks.
    pub fn stick_length(&self) -> f64 {
        self.faces.iter().map(|f| f.stick_length).sum()
    }

    /// With friction, the total length of the closed part that slips.
    pub fn slip_length(&self) -> f64 {
        self.faces.iter().map(|f| f.slip_length).sum()
    }

    /// The nodal displacements: the pair x + lo, or x without a refinement.
    pub fn displacement(&self, problem: &Problem, disc: &Discretisation) -> Displacement {
        match &self.lo {
            Some(lo) => Refined { x: self.x.clone(), lo: lo.clone() }.displacement(problem, disc),
            None => problem.displacement(disc, &self.x).into(),
        }
    }

    /// What the estimator needs of this iterate.
    pub fn linearisation(&self, problem: &Problem, disc: &Discretisation) -> Linearisation<'_> {
        Linearisation::new(problem, disc, &self.nitsche, self.smoothing, &self.x_prev)
    }
}

/// What a part of Γ_C carries: its contact length \[m\], N = ∫ p_c ds and T = ∫ t^t ds \[N/m\], and
/// FS_LE by limit equilibrium along it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct JointForces {
    pub contact_length: f64,
    pub normal_force: f64,
    pub tangential_force: f64,
    pub sliding_safety_factor: Option<f64>,
}

/// A Newton iterate u^k on Γ_C as the estimator sees it: the faces, the smoothing of its
/// step and the previous iterate u^{k−1}, at which the Newton equation that u^k solves was
/// linearised.
pub struct Linearisation<'a> {
    pub nitsche: &'a Nitsche,
    pub smoothing: Smoothing,
    /// u^{k−1} at the nodes.
    pub u_prev: Vec<[f64; 2]>,
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

/// The crack open at the heel that the uplift fills, found by a fixed point ([`settle_crack`]):
/// solve with the crack s_c, measure the open length at the heel, and solve again until it
/// moves by at most [`Crack::TOLERANCE`] of the joint length, or a bisection brackets it that
/// closely.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Crack {
    /// s_c \[m\].
    pub length: f64,
    /// Solves of the iteration, the first included.
    pub iterations: usize,
    /// |s_c − the open length of the last solve| \[m\].
    pub change: f64,
    /// The last cracks below and above the fixed point (the open length was larger, and
    /// smaller, than the crack solved with), once both were seen \[m\].
    pub bracket: Option<[f64; 2]>,
    /// Whether the crack stops at the drain line, where the diagram jumps: with the drains
    /// counted the joint opens past them, without them it closes short of them, so no crack
    /// is a fixed point. The drains are then taken as reached (EM 1110-2-2100's T ≥ X: s_c =
    /// X, the larger uplift), and `change` is X − the open length without them.
    pub at_drains: bool,
}

/// The crack of each uplift diagram of a joint, in order (None where the crack is not filled).
pub type Cracks = Vec<Option<Crack>>;

impl Crack {
    pub const TOLERANCE: f64 = 1e-6;
    pub const MAX_ITERATIONS: usize = 40;
}

/// Why a contact solve stopped without an answer.
#[derive(Debug, thiserror::Error)]
pub enum ContactError {
    #[error(transparent)]
    Newton(#[from] NewtonError),
    #[error(
        "the crack–uplift iteration did not settle in {iterations} solves: the crack at the heel (now {length:.4} m) \
         still moved by {change:.3e} m; set crack = \"ignore\" in its uplift table to solve without the crack's \
         pressure"
    )]
    Crack { iterations: usize, length: f64, change: f64 },
    #[error(
        "the crack–uplift iteration closed on a crack of {length:.4} m whose opening jumps by {change:.3e} m, more \
         than the face there ({face:.3e} m); refine the mesh along the joint, or set crack = \"ignore\" in its uplift \
         table"
    )]
    CrackJump { length: f64, change: f64, face: f64 },
    #[error(transparent)]
    NoEquilibrium(#[from] NoEquilibrium),
    #[error(
        "no equilibrium at λ = {load_factor:.4} of the loads that follow the self-weight: only the joint holds the \
         body, and {contact_length:.3} m of its {joint_length:.3} m remain in contact (less than {share} %): the body \
         lifts off (overturns or floats)",
        share = 100.0 * path::LIFT_OFF
    )]
    LiftOff { load_factor: f64, contact_length: f64, joint_length: f64 },
    #[error(
        "the load path stopped at λ = {load_factor:.4} of the loads that follow the self-weight, where the joint \
         neither slides, lifts off nor cracks through (crack {crack}, contact length {contact:.3} m, FS_LE {fs}): no \
         converged state beyond it with load steps down to {min_step:.1e}; the last step's solve: {source}",
        crack = state.crack.map_or("none".to_string(), |c| format!("{c:.3} m")),
        contact = state.contact_length,
        fs = state.sliding_safety_factor.map_or("none".to_string(), |f| format!("{f:.3}")),
        min_step = path::MIN_STEP,
    )]
    PathStalled { load_factor: f64, state: PathPoint, source: Box<ContactError> },
}

/// Solves the elasticity problem with contact on `joint` from a zero initial guess, along
/// the δ path of `settings`; with uplift in the crack, repeated until the crack settles.
pub fn solve_by_continuation(
    problem: &Problem,
    disc: &Discretisation,
    joint: &ContactJoint,
    settings: &Continuation,
) -> Result<ContactSolution, ContactError> {
    solve_from(problem, disc, joint, settings, vec![0.0; disc.dofs.n_free])
}

/// Solves the elasticity problem with contact on `joint` from the free unknowns `x0`, along
/// the δ path of `settings`; with uplift in the crack, repeated until the crack settles. A
/// state that the joint alone would hold with less than [`path::LIFT_OFF`] of it in contact is
/// [`ContactError::LiftOff`].
pub fn solve_from(
    problem: &Problem,
    disc: &Discretisation,
    joint: &ContactJoint,
    settings: &Continuation,
    x0: Vec<f64>,
) -> Result<ContactSolution, ContactError> {
    let contact = ContactProblem::new(problem, disc, joint, Smoothing { delta: settings.delta });
    solve_system_from(contact, joint, settings, x0)
}

/// [`solve_from`] on `contact`, the system of `joint` already assembled (its stiffness perhaps
/// already factorised).
pub fn solve_system_from(
    contact: ContactProblem,
    joint: &ContactJoint,
    settings: &Continuation,
    x0: Vec<f64>,
) -> Result<ContactSolution, ContactError> {
    solve_system_along(contact, joint, settings, x0, &[])
}

/// [`solve_system_from`] whose load path from rest tries the load factors of `schedule` first
/// ([`path::follow`]).
pub fn solve_system_along(
    mut contact: ContactProblem,
    joint: &ContactJoint,
    settings: &Continuation,
    x0: Vec<f64>,
    schedule: &[f64],
) -> Result<ContactSolution, ContactError> {
    if let Some(path) = settings.path.filter(|_| x0.iter().all(|&v| v == 0.0)) {
        contact.stage_loads(path.weight);
        let deltas = (settings.delta, settings.delta_start);
        let followed = path::follow(&mut contact, deltas, x0, &settings.newton, path.trace, schedule)?;
        let solution = contact.solution(followed.x, followed.stages, followed.cracks);
        return Ok(ContactSolution { path: followed.path, ..solution });
    }
    let (x, mut stages) = continuation(&mut contact, settings.delta, settings.delta_start, x0, &settings.newton)?;
    let (x, cracks) = match joint.uplift.iter().any(|up| up.diagram.rule.follows_crack()) {
        true => {
            let (x, more, cracks) = settle_crack(&mut contact, x, &settings.newton)?;
            stages.extend(more);
            (x, cracks)
        }
        false => (x, Vec::new()),
    };
    contact.lift_off(&x, 1.0)?;
    Ok(contact.solution(x, stages, cracks))
}

/// Nested iteration (docs/method.md §1.5): Newton on each level of `coarse` (coarser meshes
/// of the same geometry, or the degree-1 problem on the triangles of `problem`, coarsest
/// first, taken one at a time), from u = 0 along the δ path of `settings` on the first and at
/// δ from the previous solution interpolated on the others.
/// Returns the last solution interpolated at the nodes of `problem` (free unknowns of `disc`),
/// the start of Newton there, and the coarse solves; None without levels or if one of them is
/// None (it could not be made). The crack that uplift fills keeps the length of each coarse
/// joint: it is settled on `problem` only.
pub fn nested_start(
    problem: &Problem,
    disc: &Discretisation,
    coarse: impl IntoIterator<Item = Option<CoarseLevel>>,
    settings: &Continuation,
) -> Result<Option<NestedStart>, ContactError> {
    let mut previous: Option<CarriedState> = None;
    let (mut solves, mut cracks) = (Vec::new(), Vec::new());
    for level in coarse {
        let Some(CoarseLevel { problem: level, joint, seconds: mesh }) = level else { return Ok(None) };
        let clock = Instant::now();
        let level_disc = level.discretise();
        let mut contact = ContactProblem::new(&level, &level_disc, &joint, Smoothing { delta: settings.delta });
        let assemble = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let (x0, delta_start) = match &previous {
            None => (vec![0.0; level_disc.dofs.n_free], settings.delta_start),
            Some(below) => {
                let (x0, origin) = below.onto(&level, &level_disc);
                contact.set_slip_origin(origin.as_deref());
                (x0, settings.delta)
            }
        };
        let start = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let (x, stages) = match (settings.path, &previous) {
            (Some(path), None) => {
                contact.stage_loads(path.weight);
                let deltas = (settings.delta, delta_start);
                let followed = path::follow(&mut contact, deltas, x0, &settings.newton, path.trace, &[])?;
                cracks = followed.cracks;
                (followed.x, followed.stages)
            }
            _ => {
                contact.set_cracks(&cracks);
                continuation(&mut contact, settings.delta, delta_start, x0, &settings.newton)?
            }
        };
        let newton = clock.elapsed().as_secs_f64();
        let newton_steps = stages.iter().map(|s| s.report.iterations.len()).sum();
        let seconds = CoarseTimings { mesh, assemble, start, newton };
        solves.push(CoarseSolve { order: level.mesh.order, unknowns: level_disc.dofs.n_free, newton_steps, seconds });
        let u = level.displacement(&level_disc, &x);
        let slip_origin = contact.nitsche.slip_origin().map(nodal);
        drop(contact);
        previous = Some(CarriedState { mesh: level.mesh, u, slip_origin });
    }
    Ok(previous.map(|below| {
        let (x0, slip_origin) = below.onto(problem, disc);
        NestedStart { x0, slip_origin, solves, cracks }
    }))
}

/// A solution's nodal displacements on its mesh and those of the state its friction law
/// measures slip from (None: rest), as carried to another mesh.
pub struct CarriedState {
    pub mesh: Mesh,
    pub u: Vec<[f64; 2]>,
    pub slip_origin: Option<Vec<[f64; 2]>>,
}

impl CarriedState {
    /// The free unknowns of both interpolated at the nodes of `problem`.
    pub fn onto(&self, problem: &Problem, disc: &Discretisation) -> (Vec<f64>, Option<Vec<f64>>) {
        let at = |u: &[[f64; 2]]| problem.interpolated(disc, &self.mesh, u);
        (at(&self.u), self.slip_origin.as_deref().map(at))
    }
}

/// The start that nested iteration gives a mesh, the coarse solves that led to it, and the
/// cracks that the load path settled on the coarsest level (empty: none followed).
pub struct NestedStart {
    pub x0: Vec<f64>,
    /// The slip origin of the friction law at x0 ([`ContactProblem::set_slip_origin`]).
    pub slip_origin: Option<Vec<f64>>,
    pub solves: Vec<CoarseSolve>,
    pub cracks: Cracks,
}

/// The crack–uplift fixed point at the δ of `contact` (docs/method.md §1.8), from the solution
/// `x` with its current cracks, one s_c per uplift diagram whose crack is filled, settled
/// together. With g(s_c) = open − s_c, the open length at the diagram's heel of the solution
/// less the crack it was solved with: s_c ← open at first, then the secant step
/// s_c − g (s_c − s_prev)/(g − g_prev) while g keeps its sign (the plain update creeps when
/// the open length follows the crack closely), and once g has taken both signs, false
/// position inside the bracket of the last crack of each sign, or its midpoint where the
/// bracket has not halved since the last such step (safeguarded bisection: the open length may
/// jump across the fixed point). Every diagram not yet settled is updated so, then Newton
/// solves again from the last solution, until each has |g| ≤ [`Crack::TOLERANCE`] L or its
/// bracket that narrow. A crack that moves clears the brackets of the others: their g changes
/// with it.
/// Returns the solution, the Newton stages of the new solves (none if `x` already settles
/// them), and the crack of each diagram (None where it is not filled).
pub fn settle_crack(
    contact: &mut ContactProblem,
    x: Vec<f64>,
    options: &NewtonOptions,
) -> Result<(Vec<f64>, Vec<Stage>, Cracks), ContactError> {
    settle_crack_to(contact, x, options, Crack::TOLERANCE)
}

/// [`settle_crack`] to |g| ≤ `tolerance` L.
pub fn settle_crack_to(
    contact: &mut ContactProblem,
    mut x: Vec<f64>,
    options: &NewtonOptions,
    tolerance: f64,
) -> Result<(Vec<f64>, Vec<Stage>, Cracks), ContactError> {
    let mut stages: Vec<Stage> = Vec::new();
    let mut searches: Vec<CrackSearch> = (contact.nitsche.uplift.iter())
        .map(|up| CrackSearch { tolerance, drains: up.diagram.drains.map(|d| d.distance), ..Default::default() })
        .collect();
    for iterations in 1..=Crack::MAX_ITERATIONS {
        let open = contact.crack_lengths(&x);
        let mut cracks = vec![None; searches.len()];
        let mut next = vec![None; searches.len()];
        for (d, search) in searches.iter_mut().enumerate() {
            let up = &contact.nitsche.uplift[d].diagram;
            if !up.rule.follows_crack() {
                continue;
            }
            match search.record(up.crack, open[d], up.line.length) {
                Ok(bracket) => {
                    let (length, change) = (up.crack, (open[d] - up.crack).abs());
                    let at_drains = search.closes_on_drains() == Some(up.crack);
                    let face = contact.face_length_at(d, length);
                    if change > face && !at_drains {
                        return Err(ContactError::CrackJump { length, change, face });
                    }
                    cracks[d] = Some(Crack { length, iterations, change, bracket, at_drains });
                }
                Err(_) if iterations == Crack::MAX_ITERATIONS => {
                    return Err(ContactError::Crack { iterations, length: open[d], change: (open[d] - up.crack).abs() })
                }
                Err(s) => next[d] = Some(s),
            }
        }
        if next.iter().all(Option::is_none) {
            return Ok((x, stages, cracks));
        }
        // a crack that moves changes the open length of the others: the signs of g they
        // recorded before no longer bracket their fixed point
        let moved: Vec<bool> = (next.iter().zip(&contact.nitsche.uplift))
            .map(|(s, up)| s.is_some_and(|s| s != up.diagram.crack))
            .collect();
        for (d, search) in searches.iter_mut().enumerate() {
            if moved.iter().enumerate().any(|(other, &m)| m && other != d) {
                (search.below, search.above, search.width) = (None, None, None);
            }
        }
        for (up, s) in contact.nitsche.uplift.iter_mut().zip(next) {
            up.diagram.crack = s.unwrap_or(up.diagram.crack);
        }
        let report = newton(contact, x, options)?;
        x = report.x.clone();
        stages.push(Stage { delta: contact.smoothing.delta, report });
    }
    unreachable!("the loop returns by its last iteration")
}

/// The search of one diagram's crack in [`settle_crack_to`].
#[derive(Debug, Clone, Copy, Default)]
struct CrackSearch {
    /// The last crack with g > 0 and the last with g < 0, each with its g.
    below: Option<(f64, f64)>,
    above: Option<(f64, f64)>,
    /// The width of the bracket at the last false-position step (None: none yet).
    width: Option<f64>,
    /// The last crack updated and its g.
    previous: Option<(f64, f64)>,
    /// The search stops at |g| ≤ tolerance L.
    tolerance: f64,
    /// The drain line s_d, where the diagram jumps as the crack reaches it.
    drains: Option<f64>,
}

impl CrackSearch {
    /// Records g = open − s_c for the crack s_c of a joint of length `length`. Ok(the bracket)
    /// once settled; Err(the next crack) otherwise. A bracket around the drain line is first
    /// cut there; one that closes on it from below is settled at s_c = s_d ([`Crack::at_drains`]).
    fn record(&mut self, crack: f64, open: f64, length: f64) -> Result<Option<[f64; 2]>, f64> {
        let (g, tolerance) = (open - crack, self.tolerance * length);
        *(if g > 0.0 { &mut self.below } else { &mut self.above }) = Some((crack, g));
        let bracket = self.below.zip(self.above).map(|((a, _), (b, _))| [a.min(b), a.max(b)]);
        if g.abs() <= tolerance {
            return Ok(bracket);
        }
        if bracket.is_some_and(|[a, b]| b - a <= tolerance) {
            return match self.closes_on_drains() {
                Some(s_d) if crack != s_d => Err(s_d),
                _ => Ok(bracket),
            };
        }
        if let Some(s_d) = self.drains.filter(|&s_d| bracket.is_some_and(|[a, b]| a < s_d && s_d < b)) {
            return Err(s_d);
        }
        // the secant step only where it moves s_c the way g points: where |g| grows with the
        // crack (the crack feeds itself) it points back, to cracks whose g has the same sign
        let secant = self
            .previous
            .filter(|&(_, g_prev)| g_prev != g)
            .map(|(s, g_prev)| crack - g * (crack - s) / (g - g_prev))
            .filter(|s| s.is_finite() && (s - crack) * g > 0.0);
        self.previous = Some((crack, g));
        Err(match bracket {
            Some(_) => self.within(),
            None => secant.unwrap_or(open).clamp(0.0, length),
        })
    }

    /// The next crack inside the bracket: false position
    /// s = a − g_a (b − a)/(g_b − g_a) on its ends a (g_a > 0) and b (g_b < 0) where the bracket
    /// has at least halved since the last such step, else its midpoint (the open length may jump
    /// across the fixed point, where false position creeps).
    fn within(&mut self) -> f64 {
        let ((a, g_a), (b, g_b)) = self.below.zip(self.above).expect("a bracket has both ends");
        let width = (b - a).abs();
        if self.width.is_none_or(|w| width <= 0.5 * w) {
            self.width = Some(width);
            return a - g_a * (b - a) / (g_b - g_a);
        }
        0.5 * (a + b)
    }

    /// The drain line s_d if the bracket closes on it from below: g > 0 short of it, g < 0 at it.
    fn closes_on_drains(&self) -> Option<f64> {
        let (below, above) = (self.below.map(|(s, _)| s), self.above.map(|(s, _)| s));
        self.drains.filter(|&s_d| above == Some(s_d) && below.is_some_and(|b| b < s_d))
    }
}

/// The free unknowns of a solve, with the contact state when the problem has Γ_C.
pub enum Solution {
    /// Without Γ_C: one linear solve, refined to the pair x + lo.
    Linear(Refined),
    Contact(Box<ContactSolution>),
}

impl Solution {
    /// The free unknowns.
    pub fn x(&self) -> &[f64] {
        match self {
            Solution::Linear(r) => &r.x,
            Solution::Contact(c) => &c.x,
        }
    }

    /// The nodal displacements: the refined pair of the linear solve, or of the last Newton
    /// step.
    pub fn displacement(&self, problem: &Problem, disc: &Discretisation) -> Displacement {
        match self {
            Solution::Linear(r) => r.displacement(problem, disc),
            Solution::Contact(c) => c.displacement(problem, disc),
        }
    }

    /// The contact state, if the problem has Γ_C.
    pub fn contact(&self) -> Option<&ContactSolution> {
        match self {
            Solution::Linear(_) => None,
            Solution::Contact(c) => Some(c),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::CrackSearch;

    // A crack that feeds itself. Source: the base of geo/dam_lifts_on_rock_uplift.toml under a
    // 55 m reservoir with its friction raised to 1.5 (docs/method.md §1.8), whose open lengths
    // were 5.67 m with s_c = 0 and 17.53 m with s_c = 5.67 m. Goal: g = open − s_c grows with
    // s_c, so the secant through the two points has its root behind both (at −5.2 m); the next
    // crack must move the way g points (past the last crack, here the plain update s_c ← open),
    // not back to 0 (clamped), where g > 0 is already known and the search would stay.
    // Parameters: a joint of 40 m.
    #[test]
    fn a_crack_that_feeds_itself_grows() {
        let mut search = CrackSearch { tolerance: super::Crack::TOLERANCE, ..Default::default() };
        assert_eq!(search.record(0.0, 5.67, 40.0), Err(5.67));
        let next = search.record(5.67, 17.53, 40.0).unwrap_err();
        assert_eq!(next, 17.53, "the secant's root lies behind both cracks");
        // g falling towards 0 keeps the secant step: through (5.67, 11.86) and (17.53, 2.0)
        let next = search.record(17.53, 19.53, 40.0).unwrap_err();
        let secant = 17.53 - 2.0 * (17.53 - 5.67) / (2.0 - 11.86);
        assert!((next - secant).abs() < 1e-12 && next > 19.53, "{next} against {secant}");
    }

    // A crack that jumps at the drain line. Source: battery case of seed 63
    // (`damfem::verify::battery`, drains 2.87 m from the heel), whose open length was 3.05 m
    // for every crack short of the drains and 2.26 m for every crack past them. Goal: no crack
    // has g = 0; the search must settle at s_c = s_d (the drains reached, the larger uplift)
    // whichever side its bisection ends on, not on the side of its last solve.
    // Parameters: a joint of 41.75 m.
    #[test]
    fn a_crack_that_jumps_at_the_drains_stops_there() {
        let s_d = 2.87;
        let open = |s: f64| if s < s_d { 3.05 } else { 2.26 };
        let mut search = CrackSearch { tolerance: super::Crack::TOLERANCE, drains: Some(s_d), ..Default::default() };
        let mut crack = 0.0;
        for _ in 0..super::Crack::MAX_ITERATIONS {
            match search.record(crack, open(crack), 41.75) {
                Ok(_) => {
                    assert_eq!((crack, search.closes_on_drains()), (s_d, Some(s_d)));
                    return;
                }
                Err(next) => crack = next,
            }
        }
        panic!("the search did not settle: last crack {crack}");
    }
}
