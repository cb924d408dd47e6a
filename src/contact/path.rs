//! The load path (docs/method.md §1.11; its steps, docs/solver.md §5): the dam is built, its
//! weight on the closed joint, and then the other loads come on with a load factor λ from 0
//! to 1,
//!
//!   b(λ) = b_w + λ (b − b_w),   p_u(λ) = λ p_u,
//!
//! b_w the load vector of the self-weight alone (with the Dirichlet data) and b that of every
//! load. λ = 0 is solved by Newton at δ from the joint held closed and sticking (the bonded
//! solution, which the weight alone barely leaves; from rest along the δ path where that
//! fails). Then λ grows by Δλ, from 1 (every load at once), each state from the secant
//! predictor of the last two (the last one alone after λ = 0), Newton to 10⁻⁶ ‖b‖ below
//! λ = 1, the crack that the reservoir fills settled at every λ (it grows with the loads), the
//! friction law acting on the slip from the last converged state.
//! A Newton run of a load step longer than [`CONTROLLED_STEP`] whose ‖F‖ has not halved in
//! [`PATIENCE`] steps fails.
//! Δλ doubles after a step of few Newton steps and halves after a failed one, down to
//! [`MIN_STEP`]; once a step has failed, a step to that λ or beyond fails at once where its
//! first solve opens the filled crack by more than [`CRACK_STEP`] of the joint. A path that
//! cannot pass λ* < 1 with that step ends there (at once where the state at λ* has used up the
//! joint's strength, FS_LE ≤ 1 + [`SLIDING_MARGIN`]),
//! and the state at λ* says why ([`Limit`]): the joint slides, opens over its length, or the
//! crack runs on. A state that the joint alone holds with less than [`LIFT_OFF`] of it in
//! contact is no equilibrium ([`ContactProblem::lift_off`]): the step fails. A limit with
//! none of these is a numerical failure, not a verdict.

use super::{continuation_counted, newton_steps, settle_crack_to, ContactError, ContactProblem, Crack, Cracks, Stage};
use crate::geometry::Vector;
use crate::solve::NewtonOptions;
use serde::Serialize;

/// The first load step Δλ: every load at once from the built state, halved where that fails
/// (on the battery of `damfem::verify::battery`, 200 cases of seed 1, the steps of failed
/// attempts counted: a median of 12 Newton steps per mesh from Δλ = 1, 13 from 1/2).
pub const FIRST_STEP: f64 = 1.0;
/// The relative residual tolerance of Newton below λ = 1 (at λ = 1, that of the options):
/// those states only carry the path.
const PATH_RTOL: f64 = 1e-6;
/// The smallest load step: a path that cannot pass λ* with it ends at λ*.
pub const MIN_STEP: f64 = 1.0 / 512.0;
/// Below λ = 1 the crack settles to this share of the joint's length (at λ = 1, to
/// [`Crack::TOLERANCE`]): it only carries the path to the next load step.
const CRACK_TOLERANCE: f64 = 1e-3;
/// A step whose first Newton solve takes at most this many steps doubles Δλ.
const EASY_STEPS: usize = 8;
/// Newton steps per solve on the path: a step that needs more is halved.
const STEP_ITERATIONS: usize = 60;
/// A Newton solve of a load step longer than [`CONTROLLED_STEP`] whose ‖F‖ has not halved in
/// this many steps fails: the path halves its load step rather than wait for it (the shorter
/// steps near a limit may need their 60).
pub const PATIENCE: usize = 10;
/// A load step whose first solve opens the crack that the reservoir fills by more than this
/// share of its joint fails at once, unless it is at most [`CONTROLLED_STEP`]: the crack's
/// solves converge only from nearby cracks, and beyond λ* they run on for hundreds of Newton
/// steps before a solve fails.
pub const CRACK_STEP: f64 = 0.1;
/// Load steps up to this size are not held to [`CRACK_STEP`] (a crack may jump at a fixed λ).
pub const CONTROLLED_STEP: f64 = 1.0 / 64.0;
/// At the limit, FS_LE of the joint below 1 + this means that it slides.
pub const SLIDING_MARGIN: f64 = 0.02;
/// At the limit, a contact length below this share of the joint means that it has lifted off.
pub const LIFT_OFF: f64 = 0.02;

/// How the loads come on: the self-weight alone, then the rest by λ ([`follow`]).
#[derive(Debug, Clone, Copy)]
pub struct LoadPath {
    /// The body force per unit mass of the self-weight, (0, −g) \[m/s²\].
    pub weight: Vector,
    /// Called with every converged state (progress).
    pub trace: Option<fn(&PathPoint)>,
}

/// A converged state of the load path.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PathPoint {
    pub load_factor: f64,
    /// The crack of the first uplift diagram whose crack is filled \[m\] (None: none).
    pub crack: Option<f64>,
    /// N = ∫ p_c, T = ∫ t^t over the joint \[N/m\], and its contact length \[m\].
    pub normal_force: f64,
    pub tangential_force: f64,
    pub contact_length: f64,
    /// FS_LE of the whole joint (None without friction or shear).
    pub sliding_safety_factor: Option<f64>,
    /// Newton steps of this load step, its crack solves and the failed attempts at the steps
    /// before it (since the last state) included.
    pub newton_steps: usize,
    /// On a bonded joint, the largest fall of a face's mean damage since the state before
    /// (0 without a bond): where the holonomic bond healed, which the irreversible law would
    /// not (docs/method.md §1.13).
    pub healing: f64,
}

/// Why the path ended at λ* < 1: what the state at λ* shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Limit {
    /// FS_LE ≤ 1 + [`SLIDING_MARGIN`]: the joint's strength is used up.
    Sliding,
    /// The contact length is below [`LIFT_OFF`] of the joint: it overturns or floats.
    LiftOff,
    /// The crack that the reservoir fills did not settle at λ* + Δλ: it runs on.
    CrackRuns,
}

/// The load path could not pass λ* < 1, and the state there shows that the joint does not
/// hold: a result, not a failure of the solver.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{}", describe(self))]
pub struct NoEquilibrium {
    pub load_factor: f64,
    pub limit: Limit,
    /// The joint's length \[m\] and, at λ*, its state.
    pub joint_length: f64,
    pub at_limit: PathPoint,
    pub path: Vec<PathPoint>,
}

fn describe(v: &NoEquilibrium) -> String {
    let at = &v.at_limit;
    let why = match v.limit {
        Limit::Sliding => format!(
            "the joint slides: FS_LE = {:.3} at λ* with N = {:.4e} N/m, T = {:.4e} N/m",
            at.sliding_safety_factor.unwrap_or(f64::NAN),
            at.normal_force,
            at.tangential_force
        ),
        Limit::LiftOff => format!(
            "the joint lifts off (the body overturns or floats): {:.3} m of {:.3} m in contact at λ*, less than {} % \
             beyond it",
            at.contact_length,
            v.joint_length,
            100.0 * LIFT_OFF
        ),
        Limit::CrackRuns => format!(
            "the crack at the heel reaches {:.3} m of {:.3} m at λ* and, with the uplift its rule gives it, runs on \
             beyond it",
            at.crack.unwrap_or(0.0),
            v.joint_length
        ),
    };
    format!("no equilibrium beyond λ* = {:.3} of the loads that follow the self-weight: {why}", v.load_factor)
}

/// The states of a path and the solve that ends it.
pub struct Followed {
    pub x: Vec<f64>,
    pub stages: Vec<Stage>,
    pub cracks: Cracks,
    pub path: Vec<PathPoint>,
    /// The Newton steps of the failed attempts, which `stages` do not hold.
    pub discarded_steps: usize,
}

/// The load path on `contact` from `x0` (usually rest) along the δ path from `delta_start` to
/// `delta` at λ = 0, then at δ, each converged state shown to `trace`. The load factors of
/// `schedule` (ascending; those a coarser mesh reached) are tried first, in order, and the
/// step rule takes over after them or at the first that fails. Ends at λ = 1 with the state
/// there, or with [`ContactError::NoEquilibrium`] or [`ContactError::PathStalled`] at λ*.
pub fn follow(
    contact: &mut ContactProblem,
    (delta, delta_start): (f64, f64),
    x0: Vec<f64>,
    options: &NewtonOptions,
    trace: Option<fn(&PathPoint)>,
    schedule: &[f64],
) -> Result<Followed, ContactError> {
    let joint_length = contact.nitsche.faces.iter().map(|f| f.length).sum();
    contact.set_load_factor(0.0);
    contact.set_slip_origin(None);
    // the Newton steps of the failed attempts since the last state, and in all
    let (mut wasted, mut discarded_steps) = (0, 0);
    let (mut x, mut stages) = built(contact, (delta, delta_start), x0, options, &mut wasted)?;
    discarded_steps += wasted;
    let (mut path, mut damage) = (Vec::new(), Vec::new());
    let first = point(contact, &x, 0.0, std::mem::take(&mut wasted) + newton_steps(&stages), &mut damage);
    reached(&mut path, first, trace);
    let max_iter = options.max_iter.min(STEP_ITERATIONS);
    let on_path = NewtonOptions { max_iter, rtol: options.rtol.max(PATH_RTOL), ..*options };
    let at_end = NewtonOptions { max_iter, ..*options };
    let (mut lambda, mut step, mut cracks) = (0.0, FIRST_STEP, Vec::new());
    let mut previous: Option<(Vec<f64>, f64)> = None;
    let (mut schedule, mut failed) = (schedule, f64::INFINITY);
    while lambda < 1.0 {
        while schedule.first().is_some_and(|&l| l <= lambda) {
            schedule = &schedule[1..];
        }
        let planned = schedule.first().copied().filter(|&l| l < 1.0);
        let trial = planned.unwrap_or((lambda + step).min(1.0));
        let increment = trial - lambda;
        let kept: Vec<f64> = contact.nitsche.uplift.iter().map(|up| up.diagram.crack).collect();
        contact.set_load_factor(trial);
        contact.set_slip_origin(Some(&x));
        let guess = predicted(&x, previous.as_ref(), lambda, trial);
        let growth = (increment > CONTROLLED_STEP && trial >= failed).then_some(CRACK_STEP);
        let mut more = Vec::new();
        let patience = (increment > CONTROLLED_STEP).then_some(PATIENCE);
        let attempt = match trial == 1.0 {
            true => {
                solve_at(contact, guess, &NewtonOptions { patience, ..at_end }, (Crack::TOLERANCE, growth), &mut more)
            }
            false => {
                let on_path = NewtonOptions { patience, ..on_path };
                solve_at(contact, guess, &on_path, (CRACK_TOLERANCE, growth), &mut more)
            }
        };
        let attempt = attempt.and_then(|solved| contact.lift_off(&solved.0, trial).map(|_| solved));
        match attempt {
            Ok((y, found)) => {
                let steps = std::mem::take(&mut wasted) + newton_steps(&more);
                let first = more[0].report.iterations.len();
                previous = Some((std::mem::replace(&mut x, y), lambda));
                (lambda, cracks) = (trial, found);
                stages.extend(more);
                reached(&mut path, point(contact, &x, lambda, steps, &mut damage), trace);
                if planned.is_some() {
                    step = increment;
                } else if first <= EASY_STEPS {
                    step = (2.0 * step).min(FIRST_STEP);
                }
            }
            Err(failure) => {
                let spent = newton_steps(&more) + failure.newton_steps();
                (wasted, discarded_steps) = (wasted + spent, discarded_steps + spent);
                let restore = |contact: &mut ContactProblem| {
                    for (up, &crack) in contact.nitsche.uplift.iter_mut().zip(&kept) {
                        up.diagram.crack = crack;
                    }
                };
                restore(contact);
                failed = failed.min(trial);
                // half the step that failed (that to λ = 1 may have been shorter than Δλ); the
                // schedule no longer holds
                step = 0.5 * increment;
                schedule = &[];
                if slides(&path) {
                    // its strength used up, the joint cannot take more load: λ* is here
                    return Err(limit(path, failure, joint_length));
                }
                if step < MIN_STEP {
                    // the crack may jump past a drain line at a fixed λ, which no step resolves:
                    // the loads of λ = 1 at once from the last converged state, before a verdict
                    contact.set_load_factor(1.0);
                    let mut more = Vec::new();
                    let at_once = solve_at(contact, x.clone(), options, (Crack::TOLERANCE, None), &mut more);
                    if let Ok((y, found)) = at_once.and_then(|s| contact.lift_off(&s.0, 1.0).map(|_| s)) {
                        let last = point(contact, &y, 1.0, wasted + newton_steps(&more), &mut damage);
                        reached(&mut path, last, trace);
                        stages.extend(more);
                        return Ok(Followed { x: y, stages, cracks: found, path, discarded_steps });
                    }
                    restore(contact);
                    contact.set_load_factor(lambda);
                    return Err(limit(path, failure, joint_length));
                }
            }
        }
    }
    Ok(Followed { x, stages, cracks, path, discarded_steps })
}

/// λ = 0, the self-weight on the joint, from `x0` (rest): Newton at δ from the joint held
/// closed and sticking (the bonded solution, which the weight alone barely leaves), else
/// along the δ path from `delta_start`; the steps of the runs that failed added to
/// `discarded`.
fn built(
    contact: &mut ContactProblem,
    (delta, delta_start): (f64, f64),
    x0: Vec<f64>,
    options: &NewtonOptions,
    discarded: &mut usize,
) -> Result<(Vec<f64>, Vec<Stage>), ContactError> {
    contact.set_delta(delta);
    let closed = contact.fully_active_start()?;
    match crate::solve::newton(contact, closed, options) {
        Ok(report) => Ok((report.x.clone(), vec![Stage { delta, report }])),
        Err(failed) => {
            *discarded += failed.steps();
            Ok(continuation_counted(contact, (delta, delta_start), x0, options, discarded)?)
        }
    }
}

/// The secant predictor of the state at λ = `trial` from the states `x` at `lambda` and
/// `previous` before it: x + (trial − λ)/(λ − λ_prev) (x − x_prev); x without one.
fn predicted(x: &[f64], previous: Option<&(Vec<f64>, f64)>, lambda: f64, trial: f64) -> Vec<f64> {
    match previous {
        Some((x_prev, lambda_prev)) => {
            let ratio = (trial - lambda) / (lambda - lambda_prev);
            x.iter().zip(x_prev).map(|(a, b)| a + ratio * (a - b)).collect()
        }
        None => x.to_vec(),
    }
}

/// The state `point` reported to `trace`, and kept.
fn reached(path: &mut Vec<PathPoint>, point: PathPoint, trace: Option<fn(&PathPoint)>) {
    if let Some(trace) = trace {
        trace(&point);
    }
    path.push(point);
}

/// Newton at the current λ from `x`, and the crack settled there to `tolerance` L, its
/// stages pushed to `stages` (those of an attempt that fails too); with a `growth` share,
/// [`ContactError::CrackStep`] where the first solve opens a crack by more than that share of
/// its joint.
fn solve_at(
    contact: &mut ContactProblem,
    x: Vec<f64>,
    options: &NewtonOptions,
    (tolerance, growth): (f64, Option<f64>),
    stages: &mut Vec<Stage>,
) -> Result<(Vec<f64>, Cracks), ContactError> {
    let report = crate::solve::newton(contact, x, options)?;
    let x = report.x.clone();
    stages.push(Stage { delta: contact.smoothing.delta, report });
    if !contact.nitsche.uplift.iter().any(|up| up.diagram.rule.follows_crack()) {
        return Ok((x, Vec::new()));
    }
    if let Some(share) = growth {
        let open = contact.crack_lengths(&x);
        for (up, open) in contact.nitsche.uplift.iter().zip(open) {
            let (crack, limit) = (up.diagram.crack, share * up.diagram.line.length);
            if up.diagram.rule.follows_crack() && open - crack > limit {
                return Err(ContactError::CrackStep { from: crack, to: open, limit });
            }
        }
    }
    settle_crack_to(contact, x, options, tolerance, stages)
}

/// The state at λ of the free unknowns `x`, its healing against the faces' mean damage
/// `damage` of the state before (empty at the first), which it replaces.
fn point(
    contact: &ContactProblem,
    x: &[f64],
    load_factor: f64,
    newton_steps: usize,
    damage: &mut Vec<f64>,
) -> PathPoint {
    let solution = contact.solution(x.to_vec(), Vec::new(), Vec::new());
    let now: Vec<f64> = solution.faces.iter().map(|f| f.damage).collect();
    let healing = damage.iter().zip(&now).map(|(before, after)| before - after).fold(0.0, f64::max);
    *damage = now;
    let forces = solution.forces(|_| true);
    let filled = contact.nitsche.uplift.iter().find(|up| up.diagram.rule.follows_crack());
    PathPoint {
        load_factor,
        crack: filled.map(|up| solution.crack_from_heel(&up.diagram.line)),
        normal_force: forces.normal_force,
        tangential_force: forces.tangential_force,
        contact_length: forces.contact_length,
        sliding_safety_factor: forces.sliding_safety_factor,
        newton_steps,
        healing,
    }
}

/// The end of a path that could not pass λ* (the last point of `path`), judged by its state
/// there and by the `failure` of the step beyond it.
fn limit(path: Vec<PathPoint>, failure: ContactError, joint_length: f64) -> ContactError {
    let at = *path.last().expect("the path has its state at λ = 0");
    let limit = if at.contact_length < LIFT_OFF * joint_length || matches!(failure, ContactError::LiftOff { .. }) {
        Some(Limit::LiftOff)
    } else if slides(&path) {
        Some(Limit::Sliding)
    } else if matches!(failure, ContactError::Crack { .. } | ContactError::CrackJump { .. }) || crack_runs(&path) {
        Some(Limit::CrackRuns)
    } else {
        None
    };
    match limit {
        Some(limit) => ContactError::NoEquilibrium(Box::new(NoEquilibrium {
            load_factor: at.load_factor,
            limit,
            joint_length,
            at_limit: at,
            path,
        })),
        None => ContactError::PathStalled { load_factor: at.load_factor, state: at, last: Box::new(failure) },
    }
}

/// Whether the last state of `path` has used up the joint's strength: FS_LE ≤ 1 +
/// [`SLIDING_MARGIN`].
fn slides(path: &[PathPoint]) -> bool {
    path.last().and_then(|at| at.sliding_safety_factor).is_some_and(|f| f <= 1.0 + SLIDING_MARGIN)
}

/// Whether the crack grew over the last steps of the path faster than the loads: its last
/// increment, per unit of λ, more than ten times its mean rate from λ = 0.
fn crack_runs(path: &[PathPoint]) -> bool {
    let [.., a, b] = path else { return false };
    let (Some(ca), Some(cb)) = (a.crack, b.crack) else { return false };
    let rate = (cb - ca) / (b.load_factor - a.load_factor);
    rate > 0.0 && rate > 10.0 * cb / b.load_factor
}
