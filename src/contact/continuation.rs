//! How a solve reaches its answer: the continuation path in δ, the load path or the crack
//! fixed point after it, and nested iteration from coarser levels.

use super::projection::Smoothing;
use super::{path, settle_crack, CoarseSolve, CoarseTimings, ContactError, ContactJoint, ContactProblem};
use super::{ContactSolution, Cracks, LoadPath};
use crate::elasticity::{nodal, Discretisation, Problem};
use crate::geometry::Vector;
use crate::mesh::Mesh;
use crate::solve::{newton, NewtonError, NewtonOptions, NewtonReport};
use std::time::Instant;

/// Newton at one regularisation δ of a continuation path.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Stage {
    pub delta: f64,
    pub report: NewtonReport,
}

/// The Newton steps of `stages`.
pub fn newton_steps(stages: &[Stage]) -> usize {
    stages.iter().map(|s| s.report.iterations.len()).sum()
}

/// Newton along the path δ_k = max(delta, delta_start / 10^k), each stage starting from the
/// previous solution; for delta = 0 the path jumps to 0 after eight decades. A direct solve
/// at a tiny δ from a poor initial guess moves the active set one face per step; the path
/// reaches it in a few steps per stage. `delta_start ≤ delta` is one stage. A path from rest
/// (x0 = 0) whose first stage fails starts that stage again from the closed (and sticking)
/// state ([`ContactProblem::fully_active_start`]): from u = 0 Newton can slide a body that a
/// frictional joint alone holds far into slip, where it stalls (docs/solver.md §4), and
/// without friction the first step on a body that only its contact holds is set by round-off.
pub fn continuation(
    contact: &mut ContactProblem,
    delta: f64,
    delta_start: f64,
    x0: Vec<f64>,
    options: &NewtonOptions,
) -> Result<(Vec<f64>, Vec<Stage>), NewtonError> {
    continuation_counted(contact, (delta, delta_start), x0, options, &mut 0)
}

/// [`continuation`], the Newton steps of a first stage from rest that failed added to
/// `discarded`.
pub fn continuation_counted(
    contact: &mut ContactProblem,
    (delta, delta_start): (f64, f64),
    x0: Vec<f64>,
    options: &NewtonOptions,
    discarded: &mut usize,
) -> Result<(Vec<f64>, Vec<Stage>), NewtonError> {
    let mut stages: Vec<Stage> = Vec::new();
    let from_rest = x0.iter().all(|&v| v == 0.0);
    let mut x = x0;
    let mut current = delta_start.max(delta);
    loop {
        contact.set_delta(current);
        let report = match newton(contact, x, options) {
            Err(failed) if from_rest && stages.is_empty() => {
                *discarded += failed.steps();
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

/// A coarser level of nested iteration: its problem (on a coarser mesh of the geometry, or at
/// degree 1 on the given mesh's triangles), its joint, and the wall time taken to make them
/// \[s\].
pub struct CoarseLevel {
    pub problem: Problem,
    pub joint: ContactJoint,
    pub seconds: f64,
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
        return Ok(ContactSolution { path: followed.path, discarded_steps: followed.discarded_steps, ..solution });
    }
    let (deltas, mut discarded_steps) = ((settings.delta, settings.delta_start), 0);
    let (x, mut stages) = continuation_counted(&mut contact, deltas, x0, &settings.newton, &mut discarded_steps)?;
    let (x, cracks) = match joint.uplift.iter().any(|up| up.diagram.rule.follows_crack()) {
        true => settle_crack(&mut contact, x, &settings.newton, &mut stages)?,
        false => (x, Vec::new()),
    };
    contact.lift_off(&x, 1.0)?;
    Ok(ContactSolution { discarded_steps, ..contact.solution(x, stages, cracks) })
}

/// Nested iteration (docs/solver.md §4): Newton on each level of `coarse` (coarser meshes
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
        let (x, stages, discarded) = match (settings.path, &previous) {
            (Some(path), None) => {
                contact.stage_loads(path.weight);
                let deltas = (settings.delta, delta_start);
                let followed = path::follow(&mut contact, deltas, x0, &settings.newton, path.trace, &[])?;
                cracks = followed.cracks;
                (followed.x, followed.stages, followed.discarded_steps)
            }
            _ => {
                contact.set_cracks(&cracks);
                let mut discarded = 0;
                let deltas = (settings.delta, delta_start);
                let (x, stages) = continuation_counted(&mut contact, deltas, x0, &settings.newton, &mut discarded)?;
                (x, stages, discarded)
            }
        };
        let newton = clock.elapsed().as_secs_f64();
        let newton_steps = newton_steps(&stages) + discarded;
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
    pub u: Vec<Vector>,
    pub slip_origin: Option<Vec<Vector>>,
}

impl CarriedState {
    /// The free unknowns of both interpolated at the nodes of `problem`.
    pub fn onto(&self, problem: &Problem, disc: &Discretisation) -> (Vec<f64>, Option<Vec<f64>>) {
        let at = |u: &[Vector]| problem.interpolated(disc, &self.mesh, u);
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
