//! A solve's result: the contact iterate with the state of its faces and what the joint
//! carries, the coarse solves that started it, and the solution of a problem with or without Γ_C.

use super::nitsche::Nitsche;
use super::projection::Smoothing;
use super::{open_from_heel, Cracks, FaceState, JointLine, Linearisation, PathPoint, Stage};
use crate::elasticity::{Discretisation, Displacement, Problem, Refined};

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
    /// The solves on coarser meshes whose solution started Newton
    /// ([`nested_start`](super::nested_start)), coarsest first; empty for a start from u = 0.
    pub coarse: Vec<CoarseSolve>,
    /// The converged states of the load path that led to it (empty: none followed).
    pub path: Vec<PathPoint>,
    /// The Newton steps of the attempts that failed on the way (load steps of the path that
    /// were halved), which `stages` do not hold.
    pub discarded_steps: usize,
}

/// A solve of nested iteration on a coarser level: its element degree, unknowns, Newton steps
/// and times.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CoarseSolve {
    /// 1 on the degree-1 problem of the given mesh's triangles (docs/solver.md §4).
    pub order: usize,
    pub unknowns: usize,
    pub newton_steps: usize,
    pub seconds: CoarseTimings,
}

/// Wall times of a level of nested iteration, in seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct CoarseTimings {
    /// The level's mesh and problem: gmsh's mesh, or the vertices of the given mesh
    /// ([`CoarseLevel::seconds`](super::CoarseLevel::seconds)).
    pub mesh: f64,
    /// Dofs, pattern and the bulk stiffness and load.
    pub assemble: f64,
    /// The solution of the level below interpolated at this level's nodes.
    pub start: f64,
    /// Newton, the once-per-mesh factorisation of the stiffness included.
    pub newton: f64,
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

    /// The Newton steps of the solve on this mesh: over all stages, and those of the attempts
    /// that failed.
    pub fn newton_steps(&self) -> usize {
        super::newton_steps(&self.stages) + self.discarded_steps
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
    /// §1.9): N = ∫ p_c ds, T = ∫ t^t ds, the contact length and FS_LE = ∫ (c b(P_γ) + F p_c)
    /// ds / |T| (s b(P_γ) for Tresca; b the smoothed closed indicator q', 1_closed at δ = 0, or
    /// a bond's intact fraction), None without friction or shear there.
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
    /// [`ContactJoint::reduced`](super::ContactJoint::reduced).
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
    pub fn faces_on(&self, line: &JointLine) -> Vec<FaceState> {
        (self.faces.iter().enumerate()).filter(|&(k, _)| self.on_line(k, line)).map(|(_, f)| *f).collect()
    }

    /// The length of `line` open at the heel ([`open_from_heel`]).
    pub fn crack_from_heel(&self, line: &JointLine) -> f64 {
        open_from_heel(&self.faces_on(line), line)
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
