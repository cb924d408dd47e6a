//! The solve on one mesh of the adaptive loop: Newton stopped by the estimators (S_lin),
//! inside a loop on the regularisation δ stopped by (S_reg).

use super::{AdaptError, AdaptSettings};
use crate::contact::path::follow;
use crate::contact::projection::Smoothing;
use crate::contact::{
    newton_steps, settle_crack, ContactJoint, ContactProblem, Crack, Cracks, Linearisation, LoadPath, Solution, Stage,
};
use crate::elasticity::{Discretisation, Problem, Refined};
use crate::estimate::estimators::GlobalEstimators;
use crate::estimate::{estimate_displacement, Estimate};
use crate::solve::{newton_until, Iterate, NewtonError, NewtonOptions, NewtonReport};
use serde::Serialize;
use std::time::Instant;

/// The result of one mesh level.
pub struct Level<'a> {
    /// The final iterate, with its contact state.
    pub solution: Solution,
    pub estimate: Estimate,
    /// Number of δ reductions, of Newton steps and of estimates of the adaptive solve on this
    /// level (those of [`Level::finish`] are in `finish`).
    pub n_reg: usize,
    pub n_lin: usize,
    pub n_est: usize,
    /// Wall time of the solves (Newton or Cholesky) and of the estimator runs \[s\].
    pub solve_seconds: f64,
    pub estimate_seconds: f64,
    /// The linearisation trend of the last estimate (None without Γ_C).
    pub trend: Option<Trend>,
    /// How Newton was run to the residual tolerance, once it has been (the last mesh).
    pub finish: Option<Finish>,
    /// Whether a Newton run to the residual tolerance stalled on this level, which then ended
    /// where (S_lin) stopped Newton (docs/method.md §5.3).
    pub stalled_before_tolerance: bool,
    /// With Γ_C, until [`Level::finish`]: the contact system at the δ and cracks of the
    /// solution, its stiffness factorised.
    system: Option<ContactProblem<'a>>,
}

/// Newton run to the residual tolerance on the last mesh (docs/method.md §5.3). After (S_lin)
/// stopped it: the Newton steps (crack solves included), δ reductions and estimates that
/// finished it, their wall time \[s\] (also in the level's solve and estimate times), and
/// η_lin \[Pa m\] of the estimate that stopped Newton. On a mesh known to be the last before
/// its solve, Newton ran to the residual tolerance from the start ([`Finish::FROM_START`]):
/// nothing was added, and no estimate stopped Newton.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Finish {
    pub n_lin: usize,
    pub n_reg: usize,
    pub n_est: usize,
    pub seconds: f64,
    pub eta_lin_stopped: Option<f64>,
}

impl Finish {
    /// Newton run to the residual tolerance at every δ of the level, (S_lin) never tested.
    pub const FROM_START: Finish = Finish { n_lin: 0, n_reg: 0, n_est: 0, seconds: 0.0, eta_lin_stopped: None };
}

/// Without Γ_C: one Cholesky solve and one estimate.
pub fn linear_level<'a>(problem: &Problem, disc: &Discretisation) -> Result<Level<'a>, AdaptError> {
    let clock = Instant::now();
    let solution = problem.solve_refined(disc)?;
    let solve_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let estimate = estimate_displacement(problem, &disc.topology, &solution.displacement(problem, disc), None)?;
    Ok(Level {
        solution: Solution::Linear(solution),
        estimate,
        n_reg: 0,
        n_lin: 0,
        n_est: 1,
        solve_seconds,
        estimate_seconds: clock.elapsed().as_secs_f64(),
        trend: None,
        finish: None,
        stalled_before_tolerance: false,
        system: None,
    })
}

/// Number and wall time [s] of the estimates of a level.
#[derive(Default)]
struct EstimateCount {
    n: usize,
    seconds: f64,
}

/// The estimate of the contact iterate x + lo (`lo` None: x) and its global values, counted
/// in `count`.
fn estimate_timed(
    problem: &Problem,
    disc: &Discretisation,
    (x, lo): (&[f64], Option<&[f64]>),
    state: &Linearisation,
    count: &mut EstimateCount,
) -> Result<(Estimate, GlobalEstimators), AdaptError> {
    let clock = Instant::now();
    let u = match lo {
        Some(lo) => Refined { x: x.to_vec(), lo: lo.to_vec() }.displacement(problem, disc),
        None => problem.displacement(disc, x).into(),
    };
    let e = estimate_displacement(problem, &disc.topology, &u, Some(state))?;
    count.n += 1;
    count.seconds += clock.elapsed().as_secs_f64();
    let global = e.estimators.global();
    Ok((e, global))
}

/// (S_lin): η_lin ≤ γ_lin (η_osc + η_flux + η_Neu + η_disc).
fn linearisation_small(g: &GlobalEstimators, gamma_lin: f64) -> bool {
    g.lin <= gamma_lin * (g.osc + g.flux + g.neu + g.disc)
}

/// (S_reg): η_reg ≤ γ_reg (η_osc + η_flux + η_Neu + η_disc + η_lin).
pub(super) fn regularisation_small(g: &GlobalEstimators, gamma_reg: f64) -> bool {
    g.reg <= gamma_reg * (g.osc + g.flux + g.neu + g.disc + g.lin)
}

/// η_lin of the last estimate per unit of Newton residual, κ = η_lin / ‖F(u^k)‖, and the
/// rest η_osc + η_flux + η_Neu + η_disc of that estimate. The Γ_C traction t₃ behind η_lin
/// is what u^k leaves of the nonlinear equation, so κ ‖F(u^k)‖ predicts η_lin of a later
/// iterate without an estimate.
#[derive(Debug, Clone, Copy)]
pub struct Trend {
    per_residual: f64,
    rest: f64,
}

impl Trend {
    fn new(g: &GlobalEstimators, residual: f64) -> Option<Trend> {
        (residual > 0.0).then(|| Trend { per_residual: g.lin / residual, rest: g.osc + g.flux + g.neu + g.disc })
    }

    /// Whether the predicted η_lin of an iterate with residual ‖F‖ = `residual` meets (S_lin)
    /// against the last known rest.
    fn promising(&self, residual: f64, gamma_lin: f64) -> bool {
        self.per_residual * residual <= gamma_lin * self.rest
    }
}

/// How a level starts.
#[derive(Debug, Clone, Copy)]
pub enum StartDelta {
    /// The δ the previous mesh ended with, and its linearisation trend.
    Kept(f64, Option<Trend>),
    /// The first mesh: δ₀ from the first Newton iterate, given the stress scale S of the loads;
    /// with a load `path`, its end instead, followed from delta0 · S to δ₀ = 10⁻⁴ S at λ = 0
    /// and at δ₀ beyond, as `damfem solve` does (max |P_γ| over an open crack is γ times its
    /// opening, no stress scale).
    FirstIterate { load_scale: f64, path: Option<LoadPath> },
}

impl StartDelta {
    /// δ of the first Newton step: the kept δ, or delta0 · S.
    fn first_step(&self, delta0: f64) -> f64 {
        match *self {
            StartDelta::Kept(delta, _) => delta,
            StartDelta::FirstIterate { load_scale, .. } => delta0 * load_scale,
        }
    }
}

/// One Newton step from `x0` with the projection of `contact` (δ = delta0 · S, S =
/// `load_scale`), then δ₀ = delta0 · max_{Γ_C} |P_γ(u_h¹)| over the quadrature points of the
/// iterate u_h¹, or δ₀ = delta0 · S when that maximum is 0. Returns the stage of that step
/// (its report holds u_h¹) and δ₀.
fn first_iterate(
    contact: &ContactProblem,
    x0: Vec<f64>,
    newton: &NewtonOptions,
    delta0: f64,
    load_scale: f64,
) -> Result<(Stage, f64), AdaptError> {
    let one_step = NewtonOptions { max_iter: 1, min_steps: 1, ..*newton };
    let delta = contact.smoothing.delta;
    let report =
        newton_until(contact, x0, &one_step, |it| !it.probe).map_err(|source| AdaptError::Newton { delta, source })?;
    let p_max = contact.max_abs_p_gamma(&report.x);
    let scale = if p_max > 0.0 { p_max } else { load_scale };
    Ok((Stage { delta, report }, delta0 * scale))
}

/// δ of the load path on the first mesh, as a multiple of the stress scale S (that of `damfem
/// solve`).
const PATH_DELTA: f64 = 1e-4;

/// How many Newton runs in a row a level starts again at ρ_δ δ after a run that did not
/// converge, while no δ has been solved on it.
const MAX_RETRIES: usize = 4;

/// With contact on `joint`: Newton from `x0` (with the friction law on the slip from the state
/// `slip_origin`, None: from rest) at δ, stopped by (S_lin), and δ ← δ/ρ_δ until
/// (S_reg); with the reservoir's pressure in the crack at the heel, solved again at that δ
/// until the crack settles. On the first mesh δ₀ comes from the first Newton iterate, which counts in N_lin.
/// An estimate follows every full Newton step that at least halved the residual, and the full
/// step of every step that the line search cut (docs/method.md §5.3), unless the
/// [`Trend`] of the last estimate (on this mesh or the previous one) predicts that (S_lin)
/// fails: a damped step does not solve the linearised problem, so its η_lin would not be a
/// bound, and while the residual does not contract (the active set still moves) (S_lin)
/// cannot hold. The prediction only saves estimates: Newton stops on an estimated (S_lin).
/// The final iterate is always estimated. If Newton fails twice in a row below a δ_s solved on
/// this level (at δ_s/ρ_δ, then at the middle), the level ends at δ_s with (S_reg) unmet.
/// With [`Stopping::Residual`] (a mesh known to be the last), Newton runs to the residual
/// tolerance at every δ: the only estimates are the one (S_reg) needs after each run, the last
/// of them the final one, and the level's [`Finish`] is [`Finish::FROM_START`]; a run that
/// stalls before the tolerance goes on under (S_lin) at its δ, and the level, flagged
/// [`Level::stalled_before_tolerance`], has no [`Finish`].
pub fn contact_level<'a>(
    problem: &'a Problem,
    disc: &'a Discretisation,
    joint: &ContactJoint,
    newton: &NewtonOptions,
    settings: &AdaptSettings,
    ((x0, slip_origin), start): ((Vec<f64>, Option<Vec<f64>>), StartDelta),
    stopping: Stopping,
) -> Result<Level<'a>, AdaptError> {
    let delta = start.first_step(settings.delta0);
    let mut contact = ContactProblem::new(problem, disc, joint, Smoothing { delta });
    contact.set_slip_origin(slip_origin.as_deref());
    let clock = Instant::now();
    let (mut stages, mut discarded_steps) = (Vec::new(), 0);
    let (x, delta, trend) = match start {
        StartDelta::Kept(_, trend) => (x0, delta, trend),
        // the end of the load path at its δ, which the level goes on from
        StartDelta::FirstIterate { load_scale, path: Some(path) } => {
            contact.stage_loads(path.weight);
            let deltas = (PATH_DELTA * load_scale, delta);
            let followed = follow(&mut contact, deltas, x0, newton, path.trace, &[])?;
            stages.extend(followed.stages);
            discarded_steps = followed.discarded_steps;
            (followed.x, PATH_DELTA * load_scale, None)
        }
        StartDelta::FirstIterate { load_scale, path: None } => {
            let (stage, delta0) = first_iterate(&contact, x0, newton, settings.delta0, load_scale)?;
            let x1 = stage.report.x.clone();
            stages.push(stage);
            (x1, delta0, None)
        }
    };
    let run = Run { x, delta, trend, stages, discarded_steps, solve_seconds: clock.elapsed().as_secs_f64() };
    let level = solve_level(contact, newton, settings, run, stopping)?;
    let finish = (stopping == Stopping::Residual && !level.stalled_before_tolerance).then_some(Finish::FROM_START);
    Ok(Level { finish, ..level })
}

impl<'a> Level<'a> {
    /// Newton finished on the level's last iterate at its δ, to the residual tolerance of
    /// `newton` (‖F‖ ≤ rtol ‖b‖, as `damfem solve`), and then what [`contact_level`] does after
    /// a Newton run: the finished iterate estimated, δ ← δ/ρ_δ while (S_reg) fails on that
    /// estimate, and the cracks settled again from it (a crack that stays within
    /// [`Crack::TOLERANCE`] L takes no solve). The forces, crack and estimate of the level are
    /// then those of one iterate that solves the equations to Newton's tolerance. Its counters,
    /// wall time and the η_lin that (S_lin) stopped on go to the level's [`Finish`]; N_reg,
    /// N_lin and N_est stay those of the adaptive solve. A level without Γ_C is returned as it
    /// is; a failure is an error (of Newton: [`AdaptError::Finish`]), never the unfinished
    /// iterate.
    pub fn finish(mut self, newton: &NewtonOptions, settings: &AdaptSettings) -> Result<Level<'a>, AdaptError> {
        let Some(contact) = self.system.take() else { return Ok(self) };
        let x = self.solution.x().to_vec();
        let delta = contact.smoothing.delta;
        let run = Run { x, delta, trend: self.trend, stages: Vec::new(), discarded_steps: 0, solve_seconds: 0.0 };
        let mut finished =
            solve_level(contact, newton, settings, run, Stopping::Residual).map_err(super::unfinished)?;
        finished.finish = (!finished.stalled_before_tolerance).then(|| Finish {
            n_lin: finished.n_lin,
            n_reg: finished.n_reg,
            n_est: finished.n_est,
            seconds: finished.solve_seconds + finished.estimate_seconds,
            eta_lin_stopped: Some(self.estimate.estimators.global().lin),
        });
        if let (Solution::Contact(before), Solution::Contact(after)) = (&mut self.solution, &mut finished.solution) {
            after.stages.splice(0..0, before.stages.drain(..));
            // the solves of the crack's fixed point on this mesh: the level's, then the re-solves here
            for (crack, earlier) in after.cracks.iter_mut().zip(&before.cracks) {
                if let (Some(c), Some(e)) = (crack, earlier) {
                    c.iterations += e.iterations.saturating_sub(1);
                }
            }
        }
        Ok(Level {
            n_reg: self.n_reg,
            n_lin: self.n_lin,
            n_est: self.n_est,
            solve_seconds: self.solve_seconds + finished.solve_seconds,
            estimate_seconds: self.estimate_seconds + finished.estimate_seconds,
            ..finished
        })
    }
}

/// Where [`solve_level`] starts: the iterate, δ, the trend of the last estimate, and the
/// Newton stages already run on the level (and the steps of the attempts it discarded) with
/// their wall time \[s\].
struct Run {
    x: Vec<f64>,
    delta: f64,
    trend: Option<Trend>,
    stages: Vec<Stage>,
    discarded_steps: usize,
    solve_seconds: f64,
}

/// What stops Newton at each δ.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stopping {
    /// (S_lin) on an estimated iterate, or the residual tolerance.
    Linearisation,
    /// The residual tolerance alone.
    Residual,
}

/// The last estimated iterate of a Newton run, with its estimate.
type Estimated = (Vec<f64>, Result<(Estimate, GlobalEstimators), AdaptError>);

/// Newton on `contact` from `x`, stopped under (S_lin) where `stopping` asks it: a full step
/// that contracted and whose estimate the `trend` finds promising is estimated (its refinement
/// pair, which the returned iterate will be), and Newton stops where η_lin is small. Returns
/// the run and the last estimated iterate; the estimates are counted in `count`.
fn newton_stopped(
    contact: &ContactProblem,
    x: &[f64],
    newton: &NewtonOptions,
    settings: &AdaptSettings,
    stopping: Stopping,
    trend: &mut Option<Trend>,
    count: &mut EstimateCount,
) -> (Result<NewtonReport, NewtonError>, Option<Estimated>) {
    let (problem, disc, smoothing) = (contact.problem, contact.disc, contact.smoothing);
    let mut latest = None;
    let attempt = newton_until(contact, x.to_vec(), newton, |it: &Iterate| {
        // the full step of a damped one is estimated as any other, when promising
        let contracted = it.last.full() && (it.probe || it.residual <= 0.5 * it.last.residual);
        let promising = trend.is_none_or(|t| t.promising(it.residual, settings.gamma_lin));
        if stopping == Stopping::Residual || !contracted || !promising {
            return false;
        }
        let state = Linearisation::new(problem, disc, &contact.nitsche, smoothing, it.x_prev);
        let (x, lo) = it.refined().map_or((it.x, None), |(x, lo)| (&x[..], Some(&lo[..])));
        let e = estimate_timed(problem, disc, (x, lo), &state, count);
        let stop = e.as_ref().map_or(true, |(_, g)| linearisation_small(g, settings.gamma_lin));
        if let Ok((_, g)) = &e {
            *trend = Trend::new(g, it.residual).or(*trend);
        }
        latest = Some((x.to_vec(), e));
        stop
    });
    (attempt, latest)
}

/// A level's last converged Newton run: its δ, iterate and estimate.
type Solved = (f64, Vec<f64>, Estimate);

/// What [`solve_level`] does after a Newton run that failed: its stopping rule, the restarts
/// at a larger δ since its last converged run, and that run.
struct Retry<'r> {
    stopping: &'r mut Stopping,
    retries: &'r mut usize,
    solved: &'r mut Option<Solved>,
}

impl Retry<'_> {
    /// After the run that `failed` at `delta` from `x`: None to run again, at the same δ under
    /// (S_lin) where a run to the residual tolerance stalled (it may stop on an iterate the
    /// crawl of a softening law never leaves, docs/method.md §5.3), or from the same iterate
    /// at a smoother δ: once halfway (geometrically) back to a δ_s solved on this level, else
    /// at ρ_δ δ, up to MAX_RETRIES times in a row; the estimate at δ_s where the level ends
    /// there after the second failure (δ and x set back), or the error.
    fn after(
        self,
        failed: NewtonError,
        delta: &mut f64,
        x: &mut Vec<f64>,
        rho_delta: f64,
    ) -> Result<Option<Estimate>, AdaptError> {
        if *self.stopping == Stopping::Residual && matches!(failed, NewtonError::NotConverged { .. }) {
            *self.stopping = Stopping::Linearisation;
            return Ok(None);
        }
        *self.retries += 1;
        match self.solved.take() {
            Some(s) if *self.retries == 1 => {
                *delta = (s.0 * *delta).sqrt();
                *self.solved = Some(s);
                Ok(None)
            }
            Some((at, solution, estimate)) => {
                (*delta, *x) = (at, solution);
                Ok(Some(estimate))
            }
            None if *self.retries <= MAX_RETRIES => {
                *delta *= rho_delta;
                Ok(None)
            }
            None => Err(AdaptError::Newton { delta: *delta, source: failed }),
        }
    }
}

/// The crack fixed point of a level: the δ at which the cracks were last settled and how, the
/// crack solves so far, and the level's Newton stages.
struct CrackState<'r> {
    settled: &'r mut Option<(f64, Cracks)>,
    solves: &'r mut usize,
    stages: &'r mut Vec<Stage>,
}

impl CrackState<'_> {
    /// With a crack filled by the reservoir, its fixed point at the δ of `contact`, once per δ:
    /// the cracks where `x` settles them (none without such a crack), None where a crack moved
    /// (the level goes on from the new solution, left in `x`, so that its last iterate is
    /// estimated; a crack settled by its bracket stays: it would not settle again).
    fn settle(
        self,
        contact: &mut ContactProblem,
        x: &mut Vec<f64>,
        newton: &NewtonOptions,
    ) -> Result<Option<Cracks>, AdaptError> {
        if !contact.nitsche.uplift.iter().any(|up| up.diagram.rule.follows_crack()) {
            return Ok(Some(Vec::new()));
        }
        let delta = contact.smoothing.delta;
        let found = match self.settled.clone().filter(|(at, _)| *at == delta) {
            Some((_, found)) => found,
            None => {
                let mut more = Vec::new();
                let (solution, found) = settle_crack(contact, std::mem::take(x), newton, &mut more)?;
                *self.solves += more.len();
                (*x, *self.settled) = (solution, Some((delta, found.clone())));
                if !more.is_empty() {
                    self.stages.extend(more);
                    return Ok(None);
                }
                found
            }
        };
        let iterations = *self.solves + 1;
        Ok(Some(found.into_iter().map(|c| c.map(|c| Crack { iterations, ..c })).collect()))
    }
}

/// The loop of [`contact_level`] on `contact` from `run`, Newton stopped as `stopping` says.
fn solve_level<'a>(
    mut contact: ContactProblem<'a>,
    newton: &NewtonOptions,
    settings: &AdaptSettings,
    run: Run,
    mut stopping: Stopping,
) -> Result<Level<'a>, AdaptError> {
    let asked = stopping;
    let (problem, disc) = (contact.problem, contact.disc);
    let Run { mut x, mut delta, mut trend, mut stages, mut discarded_steps, mut solve_seconds } = run;
    let (mut estimates, mut n_reg) = (EstimateCount::default(), 0);
    // the crack solves, and the restarts at a larger δ since the last converged run (whose
    // discarded Newton steps count to N_lin)
    let (mut crack_solves, mut retries) = (0, 0);
    let (mut solved, mut settled): (Option<Solved>, Option<(f64, Cracks)>) = (None, None);
    loop {
        contact.set_delta(delta);
        let smoothing = contact.smoothing;
        let mut inside = EstimateCount::default();
        let clock = Instant::now();
        let (attempt, latest) = newton_stopped(&contact, &x, newton, settings, stopping, &mut trend, &mut inside);
        solve_seconds += clock.elapsed().as_secs_f64() - inside.seconds;
        estimates.n += inside.n;
        estimates.seconds += inside.seconds;
        // a Newton run that stalls at δ (steps cut short by the line search where the law is
        // steep in P_γ, docs/solver.md §3) starts again (§9, [`Retry::after`]); a level that
        // ends at a δ_s solved before has its estimate, which bounds the error too (η_reg above
        // its share); (S_reg) then brings δ down
        let estimate = match attempt {
            Ok(report) => {
                let (estimate, global) = match latest {
                    Some((at, e)) if at == report.x => e?,
                    _ => {
                        let state = Linearisation::new(problem, disc, &contact.nitsche, smoothing, &report.x_prev);
                        let (estimate, global) =
                            estimate_timed(problem, disc, (&report.x, report.lo.as_deref()), &state, &mut estimates)?;
                        trend = Trend::new(&global, report.residual).or(trend);
                        (estimate, global)
                    }
                };
                x = report.x.clone();
                retries = 0;
                stages.push(Stage { delta, report });
                if !regularisation_small(&global, settings.gamma_reg) {
                    if n_reg == settings.max_delta_reductions {
                        return Err(AdaptError::Regularisation { delta, reductions: n_reg, eta_reg: global.reg });
                    }
                    solved = Some((delta, x.clone(), estimate));
                    delta /= settings.rho_delta;
                    n_reg += 1;
                    continue;
                }
                estimate
            }
            Err(failed) => {
                discarded_steps += failed.steps();
                let retry = Retry { stopping: &mut stopping, retries: &mut retries, solved: &mut solved };
                match retry.after(failed, &mut delta, &mut x, settings.rho_delta)? {
                    Some(estimate) => {
                        contact.set_delta(delta);
                        estimate
                    }
                    None => continue,
                }
            }
        };
        let crack = CrackState { settled: &mut settled, solves: &mut crack_solves, stages: &mut stages };
        let Some(cracks) = crack.settle(&mut contact, &mut x, newton)? else { continue };
        let n_lin = discarded_steps + newton_steps(&stages);
        return Ok(Level {
            solution: Solution::Contact(Box::new(contact.solution(x, stages, cracks))),
            estimate,
            n_reg,
            n_lin,
            n_est: estimates.n,
            solve_seconds,
            estimate_seconds: estimates.seconds,
            trend,
            finish: None,
            stalled_before_tolerance: stopping != asked,
            // a run to the residual tolerance leaves nothing to finish
            system: (asked == Stopping::Linearisation).then_some(contact),
        });
    }
}
