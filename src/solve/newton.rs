//! Newton's method with backtracking for F(x) = 0 on a fixed sparsity pattern.
//!
//! Step k solves J(x_k) Δ = −F(x_k), by the system's [`LayerSchur`] if it has one (a dense
//! factorisation on its nonlinear layer, the constant bulk factorised once) and otherwise by
//! sparse LU (symbolic factorisation reused), then takes
//! the largest t ∈ {1, ½, ¼, …} with ‖F(x_k + tΔ)‖ ≤ κ ‖F(x_k)‖, κ = `max_growth`. A system
//! that asks for a monotone residual (Coulomb friction, whose full steps can cycle) gets the
//! largest t that lowers ‖F‖, or keeps it within κ, moves x by at most ‖x‖ and passes the
//! natural monotonicity test ‖J(x_k)⁻¹F(x_k + tΔ)‖ ≤ (1 − t/4) ‖Δ‖, instead (the latter only
//! while ‖F‖ reached a new low in the last three steps: alone it lets steps cycle), and the
//! rule above only where none does (a kink). Each linear solve gets one step of iterative
//! refinement. It stops when ‖F(x_k)‖ ≤ rtol · scale,
//! where `scale` is the system's load norm, or when it stagnates at round-off: ‖Δ‖ ≤ 10⁻¹⁰ ‖x‖
//! with no halving of ‖F‖. After three exact steps in a row cut below t = 1/16, a system
//! with a [`NonlinearSystem::frozen_jacobian`] (a softening law) takes its steps until one is
//! full. A run that gets there by a damped or frozen step takes one exact full step more,
//! so that the iterate it returns solves the linearised problem of its last step (what the
//! estimator's bound assumes). A run whose ‖F‖ rises to 10³ times its smallest stops
//! there, as one that runs out of iterations, and so does one whose ‖F‖ has not halved in
//! [`NewtonOptions::patience`] steps. Where the line search cuts an exact step, the
//! full step x_k + Δ, which solves the linearised problem all the same, is shown to the
//! stopping rule ([`Iterate::probe`]) before Newton goes on from the damped iterate. Running
//! out of iterations is an error that carries the whole history: never a silent wrong answer.
//!
//! A system with a linearised residual in difference form
//! ([`NonlinearSystem::linearised_residual`]) gets a refinement round on the iterate it
//! returns after a full step (and on the iterates a stopping rule asks for,
//! [`Iterate::refined`]): lo = −J⁻¹ F_lin(x) with the last step's factors, so that the pair
//! x + lo solves the linearised problem of that step to the round-off of the strain, not of
//! the values of x (docs/method.md §5.2).

use super::lu::{LuFactors, SparseLu};
use super::schur::{LayerSchur, SchurFactors};
use super::{two_sum, SolveError};
use crate::fem::sparse::SparsePattern;
use serde::Serialize;
use std::cell::OnceCell;
use std::time::Instant;

/// A nonlinear system F(x) = 0 whose Jacobian lives on a fixed pattern.
pub trait NonlinearSystem {
    /// Pattern of the Jacobian.
    fn pattern(&self) -> &SparsePattern;
    /// Writes F(x) into `residual` and, when asked, the Jacobian values into `jacobian`.
    fn evaluate(&self, x: &[f64], residual: &mut [f64], jacobian: Option<&mut [f64]>);
    /// Norm of the load vector: the residual scale for the relative tolerance.
    fn scale(&self) -> f64;
    /// Whether a step must lower ‖F‖ when some halving of it does. Semismooth steps that
    /// change an active set may raise ‖F‖ for a while and still converge, so by default a
    /// step is only kept from blowing ‖F‖ up; a Jacobian with non-symmetric couplings
    /// (Coulomb friction) lets full steps cycle, which a monotone ‖F‖ breaks.
    fn monotone(&self) -> bool {
        false
    }
    /// The constant part of the Jacobian factorised once, with the layer of dofs that the
    /// nonlinear part touches; None (the default): every step factors J by sparse LU.
    fn schur(&self) -> Option<&LayerSchur> {
        None
    }
    /// Writes into `jacobian` the Jacobian at x of a model whose law does not soften (the
    /// cohesion's closed indicator held at its value at x), for the steps of a stalled run;
    /// false (the default): the system has none.
    fn frozen_jacobian(&self, _x: &[f64], _jacobian: &mut [f64]) -> bool {
        false
    }
    /// F(x_prev) + J(x_prev)(x + lo − x_prev), the residual at the pair x + lo of the Newton
    /// equation linearised at `x_prev`, computed without the rounding of the values of x
    /// (differences of nearby nodal values, compensated sums); None (the default): iterates
    /// stay double.
    fn linearised_residual(&self, _x: &[f64], _lo: &[f64], _x_prev: &[f64]) -> Option<Vec<f64>> {
        None
    }
}

/// How the Newton steps solve with the Jacobian.
enum Linear<'a> {
    Schur(&'a LayerSchur),
    Lu(SparseLu),
}

/// The factors of one Jacobian.
enum Factors<'a> {
    Schur(SchurFactors<'a>),
    Lu(Box<LuFactors<'a>>),
}

impl<'a> Linear<'a> {
    fn new(system: &'a impl NonlinearSystem) -> Result<Self, SolveError> {
        match system.schur() {
            Some(schur) => Ok(Linear::Schur(schur)),
            None => SparseLu::analyse(system.pattern()).map(Linear::Lu),
        }
    }

    fn factor(&self, pattern: &SparsePattern, jacobian: &[f64]) -> Result<Factors<'_>, SolveError> {
        match self {
            Linear::Schur(schur) => schur.factor(jacobian).map(Factors::Schur),
            Linear::Lu(lu) => lu.factor(pattern, jacobian).map(|f| Factors::Lu(Box::new(f))),
        }
    }
}

impl Factors<'_> {
    /// Solves J x = b.
    fn solve(&self, rhs: &[f64]) -> Result<Vec<f64>, SolveError> {
        match self {
            Factors::Schur(schur) => schur.solve(rhs),
            Factors::Lu(lu) => Ok(lu.solve(rhs)),
        }
    }
}

/// Stopping and damping parameters.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct NewtonOptions {
    /// Maximum number of Newton steps.
    pub max_iter: usize,
    /// Relative residual tolerance: ‖F‖ ≤ rtol · scale.
    pub rtol: f64,
    /// Steps taken even if x0 already meets the tolerance. With at least one, the returned
    /// iterate solves the linearised equation of its last step exactly, which the
    /// equilibrated-stress estimator relies on.
    pub min_steps: usize,
    /// Maximum number of step halvings in the line search.
    pub max_halvings: usize,
    /// A step is halved while it multiplies the residual norm by more than this factor.
    pub max_growth: f64,
    /// A run whose ‖F‖ has not halved in this many steps stops, as one that runs out of
    /// iterations (None: it runs on to `max_iter`).
    pub patience: Option<usize>,
    /// Called with k and ‖F(x_k)‖ / scale at every iterate x_k, x_0 included (progress).
    #[serde(skip)]
    pub trace: Option<fn(usize, f64)>,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        let (max_iter, rtol, min_steps, max_halvings, max_growth) = (50, 1e-10, 1, 20, 2.0);
        NewtonOptions { max_iter, rtol, min_steps, max_halvings, max_growth, patience: None, trace: None }
    }
}

/// One Newton step: residual before it, increment taken, step length, and whether its
/// direction came from the frozen Jacobian ([`NonlinearSystem::frozen_jacobian`]).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Iteration {
    pub residual: f64,
    pub increment: f64,
    pub step: f64,
    pub frozen: bool,
}

impl Iteration {
    /// A full step of the exact Jacobian: its iterate solves the linearised problem of the
    /// step, as the estimator's bound assumes.
    pub fn full(&self) -> bool {
        self.step == 1.0 && !self.frozen
    }
}

/// After this many steps without a new smallest ‖F‖, the line search of a monotone system
/// drops the natural monotonicity test until ‖F‖ falls below its smallest again: the test
/// alone lets steps cycle.
const CYCLING_STEPS: usize = 3;

/// A run whose ‖F‖ exceeds this many times its smallest so far has diverged: it stops there.
const DIVERGED: f64 = 1e3;

/// An exact Newton step cut below this length counts as stalled.
const STALLED_STEP: f64 = 1.0 / 16.0;
/// After this many stalled steps in a row, the steps take the frozen Jacobian, until one of
/// them is full.
const STALLED_STEPS: usize = 3;

/// Wall time spent in each part of the Newton loop, in seconds.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct NewtonTimings {
    pub assemble: f64,
    pub factor: f64,
    pub solve: f64,
    pub line_search: f64,
}

/// The converged iterate and how it was reached.
#[derive(Debug, Clone, Serialize)]
pub struct NewtonReport {
    #[serde(skip)]
    pub x: Vec<f64>,
    /// The iterate before the last step (x itself if no step was taken): the estimator
    /// needs it for the linearisation error.
    #[serde(skip)]
    pub x_prev: Vec<f64>,
    /// The refinement of x after a full last step: the iterate is the pair x + lo (None: x).
    #[serde(skip)]
    pub lo: Option<Vec<f64>>,
    pub iterations: Vec<Iteration>,
    /// Final residual norm ‖F(x)‖.
    pub residual: f64,
    pub scale: f64,
    pub seconds: NewtonTimings,
}

impl NewtonReport {
    /// Ratios ‖Δ_{k+1}‖ / ‖Δ_k‖² of the last steps: bounded for quadratic convergence.
    pub fn quadratic_ratios(&self) -> Vec<f64> {
        self.iterations.windows(2).map(|w| w[1].increment / (w[0].increment * w[0].increment)).collect()
    }
}

/// Why Newton stopped without an answer.
#[derive(Debug, thiserror::Error)]
pub enum NewtonError {
    #[error(
        "Newton {} in {} step(s): relative residuals {}",
        if diverged(.history) { "diverged (its residual grew)" } else { "did not converge" },
        .history.len(),
        format_history(.history, *.scale)
    )]
    NotConverged { history: Vec<Iteration>, scale: f64 },
    #[error("Newton step {step}: the increment is not finite (the Jacobian is numerically singular)")]
    NonFinite { step: usize },
    #[error("Newton step {step}: {source}")]
    Solve { step: usize, source: SolveError },
}

impl NewtonError {
    /// The Newton steps the run took before it stopped.
    pub fn steps(&self) -> usize {
        match self {
            NewtonError::NotConverged { history, .. } => history.len(),
            NewtonError::NonFinite { step } | NewtonError::Solve { step, .. } => *step,
        }
    }
}

/// Whether the residual at the end of `history` is larger than at its start.
pub fn diverged(history: &[Iteration]) -> bool {
    history.first().zip(history.last()).is_some_and(|(first, last)| last.residual > first.residual)
}

/// The relative residuals of `history`: all of them up to [`SHOWN_RESIDUALS`], else the first
/// and last few around the count of those left out.
fn format_history(history: &[Iteration], scale: f64) -> String {
    let show = |its: &[Iteration]| its.iter().map(|it| format!("{:.2e}", it.residual / scale)).collect::<Vec<_>>();
    let n = history.len();
    if n <= SHOWN_RESIDUALS {
        return show(history).join(", ");
    }
    let half = SHOWN_RESIDUALS / 2;
    format!(
        "{}, … ({} more), {}",
        show(&history[..half]).join(", "),
        n - 2 * half,
        show(&history[n - half..]).join(", ")
    )
}

/// How many residuals an error message lists.
const SHOWN_RESIDUALS: usize = 6;

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// Solves F(x) = 0 from `x0`.
pub fn newton(
    system: &impl NonlinearSystem,
    x0: Vec<f64>,
    options: &NewtonOptions,
) -> Result<NewtonReport, NewtonError> {
    newton_until(system, x0, options, |_| false)
}

/// The current iterate x_k, the previous one and the step between them, shown to a
/// stopping rule.
pub struct Iterate<'a> {
    pub x: &'a [f64],
    pub x_prev: &'a [f64],
    /// The step that led to x_k.
    pub last: &'a Iteration,
    /// Whether x_k is the full step x_{k−1} + Δ that the line search cut short: Newton goes
    /// on from the damped iterate unless the rule accepts this one.
    pub probe: bool,
    /// ‖F(x_k)‖.
    pub residual: f64,
    refined: &'a OnceCell<Option<Pair>>,
    refine: &'a dyn Fn() -> Option<Pair>,
}

/// An iterate as the pair (x, lo) of the refinement round, x = fl(x + lo).
pub type Pair = (Vec<f64>, Vec<f64>);

impl Iterate<'_> {
    /// x_k refined to the pair (x, lo) with the factors of its step, computed once when asked
    /// (docs/method.md §5.2); None after a damped step, or if the system has no
    /// [`NonlinearSystem::linearised_residual`].
    pub fn refined(&self) -> Option<&Pair> {
        self.refined.get_or_init(self.refine).as_ref()
    }
}

/// Whether ‖F‖ = r at `step` has gone `patience` steps without halving; `halved` holds the last
/// ‖F‖ that halved the one before it, and its step.
fn stale(halved: &mut (f64, usize), r: f64, step: usize, patience: Option<usize>) -> bool {
    if r <= 0.5 * halved.0 {
        *halved = (r, step);
    }
    patience.is_some_and(|p| step - halved.1 >= p)
}

/// Newton that also stops when `stop` accepts an iterate. `stop` sees every iterate after
/// the first `min_steps` steps, including the one that meets the residual tolerance, so
/// it can record a quantity of the final iterate.
pub fn newton_until(
    system: &impl NonlinearSystem,
    x0: Vec<f64>,
    options: &NewtonOptions,
    mut stop: impl FnMut(&Iterate) -> bool,
) -> Result<NewtonReport, NewtonError> {
    let pattern = system.pattern();
    let linear = Linear::new(system).map_err(|source| NewtonError::Solve { step: 0, source })?;
    let scale = system.scale().max(f64::MIN_POSITIVE);
    let (mut x, mut trial) = (x0, vec![0.0; pattern.n()]);
    let mut x_prev = x.clone();
    let (mut residual, mut trial_residual) = (vec![0.0; pattern.n()], vec![0.0; pattern.n()]);
    let mut jacobian = vec![0.0; pattern.nnz()];
    let (mut history, mut seconds) = (Vec::new(), NewtonTimings::default());
    let (mut polished, mut factors_of_last_step) = (false, None);
    let (mut stalled, mut frozen) = (0, false);
    // the smallest ‖F‖ so far and the iterates since: the natural test may let steps cycle
    let (mut best, mut since_best) = (f64::INFINITY, 0);
    let mut halved = (f64::INFINITY, 0);
    for step in 0..=options.max_iter {
        let clock = Instant::now();
        system.evaluate(&x, &mut residual, Some(&mut jacobian));
        seconds.assemble += clock.elapsed().as_secs_f64();
        let r = norm(&residual);
        if let Some(trace) = options.trace {
            trace(step, r / scale);
        }
        // round-off floor: a tiny step that no longer reduces the residual
        let stagnated =
            history.last().is_some_and(|it: &Iteration| it.increment <= 1e-10 * norm(&x) && r >= 0.5 * it.residual);
        let converged = r <= options.rtol * scale || stagnated;
        let due = step >= options.min_steps;
        let full_step = history.last().filter(|it| it.full()).and(factors_of_last_step.as_ref());
        let refine = || refinement(system, &x, &x_prev, full_step?);
        let refined = OnceCell::new();
        let it = |last| Iterate {
            x: &x,
            x_prev: &x_prev,
            last,
            probe: false,
            residual: r,
            refined: &refined,
            refine: &refine,
        };
        let accepted = due && history.last().is_some_and(|last| stop(&it(last)));
        // a converged iterate should solve the linearised problem of its step, which the
        // estimator's bound assumes: after a damped step, one full step more (once), and after
        // a frozen step always
        let polish =
            step < options.max_iter && history.last().is_some_and(|it| it.frozen || (!polished && it.step < 1.0));
        if accepted || (due && converged && !polish) {
            let clock = Instant::now();
            let (x, lo) = returned(&x, refined.into_inner().unwrap_or_else(refine));
            seconds.solve += clock.elapsed().as_secs_f64();
            return Ok(NewtonReport { x, x_prev, lo, iterations: history, residual: r, scale, seconds });
        }
        polished |= due && converged;
        let stale = stale(&mut halved, r, step, options.patience);
        if step == options.max_iter || r > DIVERGED * best || stale {
            break;
        }
        // the polishing step takes the exact Jacobian
        let frozen_step = frozen && !(due && converged) && system.frozen_jacobian(&x, &mut jacobian);
        let (factors, delta) = direction(&linear, pattern, &jacobian, &residual, &mut trial, &mut seconds, step)?;
        let clock = Instant::now();
        let (t, r_full) = if due && converged {
            (1.0, None)
        } else {
            (best, since_best) = if r < best { (r, 0) } else { (best, since_best + 1) };
            let natural = (since_best < CYCLING_STEPS).then_some(&factors);
            line_search(system, &x, &delta, r, options, &mut trial, &mut trial_residual, natural)
        };
        seconds.line_search += clock.elapsed().as_secs_f64();
        factors_of_last_step = (!frozen_step).then_some(factors);
        // the full step solves the linearised problem at x even where the line search cuts it:
        // the stopping rule may take it (the factors of an exact step only: a frozen step has none)
        let offered = t < 1.0 && step + 1 >= options.min_steps;
        if let (Some(r_full), Some(factors), true) = (r_full, &factors_of_last_step, offered) {
            let last = Iteration { residual: r, increment: norm(&delta), step: 1.0, frozen: false };
            if let Some((full, lo)) = probe_full_step(system, &x, &delta, factors, &last, r_full, &mut stop) {
                history.push(last);
                return Ok(NewtonReport {
                    x: full,
                    x_prev: x,
                    lo,
                    iterations: history,
                    residual: r_full,
                    scale,
                    seconds,
                });
            }
        }
        (stalled, frozen) = stall(frozen_step, t, stalled);
        x_prev.copy_from_slice(&x);
        for (xi, di) in x.iter_mut().zip(&delta) {
            *xi += t * di;
        }
        history.push(Iteration { residual: r, increment: t * norm(&delta), step: t, frozen: frozen_step });
    }
    Err(NewtonError::NotConverged { history, scale })
}

/// The count of successive steps cut below `STALLED_STEP` and whether the next step takes the
/// frozen Jacobian, after a step of length t: a softening law's exact steps stall where the
/// Newton model holds only over tiny steps; the frozen Jacobian's steps go on until one is full.
fn stall(frozen_step: bool, t: f64, stalled: usize) -> (usize, bool) {
    match frozen_step {
        true => (0, t < 1.0),
        false => {
            let stalled = if t < STALLED_STEP { stalled + 1 } else { 0 };
            (stalled, stalled >= STALLED_STEPS)
        }
    }
}

/// The Newton direction Δ of J Δ = −F at the iterate of Newton step `step`, with the factors
/// of J: one step of iterative refinement makes Δ solve it to round-off.
fn direction<'a>(
    linear: &'a Linear,
    pattern: &SparsePattern,
    jacobian: &[f64],
    residual: &[f64],
    product: &mut [f64],
    seconds: &mut NewtonTimings,
    step: usize,
) -> Result<(Factors<'a>, Vec<f64>), NewtonError> {
    let solve_error = |source| NewtonError::Solve { step, source };
    let clock = Instant::now();
    let factors = linear.factor(pattern, jacobian).map_err(solve_error)?;
    seconds.factor += clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let minus_r: Vec<f64> = residual.iter().map(|v| -v).collect();
    let mut delta = factors.solve(&minus_r).map_err(solve_error)?;
    pattern.multiply(jacobian, &delta, product);
    let defect: Vec<f64> = minus_r.iter().zip(product.iter()).map(|(b, jd)| b - jd).collect();
    for (d, c) in delta.iter_mut().zip(factors.solve(&defect).map_err(solve_error)?) {
        *d += c;
    }
    seconds.solve += clock.elapsed().as_secs_f64();
    match delta.iter().all(|v| v.is_finite()) {
        true => Ok((factors, delta)),
        false => Err(NewtonError::NonFinite { step }),
    }
}

/// The full step x + Δ offered to the stopping rule where the line search cut it (it solves
/// the linearised problem at x): x + Δ and its refinement pair if `stop` takes it.
fn probe_full_step(
    system: &impl NonlinearSystem,
    x: &[f64],
    delta: &[f64],
    factors: &Factors,
    last: &Iteration,
    r_full: f64,
    stop: &mut impl FnMut(&Iterate) -> bool,
) -> Option<(Vec<f64>, Option<Vec<f64>>)> {
    let full: Vec<f64> = x.iter().zip(delta).map(|(x, d)| x + d).collect();
    let refine = || refinement(system, &full, x, factors);
    let refined = OnceCell::new();
    let it = Iterate { x: &full, x_prev: x, last, probe: true, residual: r_full, refined: &refined, refine: &refine };
    stop(&it).then(|| returned(&full, refined.into_inner().unwrap_or_else(refine)))
}

/// The iterate Newton returns and its refinement: the `refined` pair if there is one, else x.
fn returned(x: &[f64], refined: Option<Pair>) -> (Vec<f64>, Option<Vec<f64>>) {
    match refined {
        Some((x, lo)) => (x, Some(lo)),
        None => (x.to_vec(), None),
    }
}

/// The refinement round of the iterate `x` reached by a full step from `x_prev` with the
/// `factors` of J(x_prev): lo = −J⁻¹ F_lin(x), F_lin the system's linearised residual, and
/// (x, lo) renormalised by TwoSum so that x = fl(x + lo). None if the system has no linearised
/// residual, or if the solve fails (the double iterate then stands, and the estimator's checks
/// judge it as such).
fn refinement(system: &impl NonlinearSystem, x: &[f64], x_prev: &[f64], factors: &Factors) -> Option<Pair> {
    let residual = system.linearised_residual(x, &vec![0.0; x.len()], x_prev)?;
    let minus_r: Vec<f64> = residual.iter().map(|v| -v).collect();
    let lo = factors.solve(&minus_r).ok()?;
    Some(x.iter().zip(lo).map(|(&x, d)| two_sum(x, d)).unzip())
}

/// Deuflhard's natural monotonicity test of the step length t: the simplified Newton step
/// Δ̄ = −J(x_k)⁻¹ F(x_k + tΔ), with the factors of the step, is shorter than (1 − t/4) ‖Δ‖.
/// It measures the residual in the metric of J, which the scaling of the rows (the Nitsche
/// rows weigh γ = γ₀E/h) does not distort.
fn natural_monotonicity(factors: &Factors, trial_residual: &[f64], step_norm: f64, t: f64) -> bool {
    let minus: Vec<f64> = trial_residual.iter().map(|v| -v).collect();
    factors.solve(&minus).is_ok_and(|simplified| norm(&simplified) <= (1.0 - 0.25 * t) * step_norm)
}

/// The step length: the largest t = 2^−j with ‖F(x + tΔ)‖ ≤ κ‖F(x)‖ (for a monotone system,
/// the largest with ‖F(x + tΔ)‖ < ‖F(x)‖ or, within κ, t‖Δ‖ ≤ ‖x‖ and with the step's factors
/// `natural`, [`natural_monotonicity`] first); the last halving if none qualifies. Also
/// ‖F(x + Δ)‖ of the full step.
#[allow(clippy::too_many_arguments)]
fn line_search(
    system: &impl NonlinearSystem,
    x: &[f64],
    delta: &[f64],
    r: f64,
    options: &NewtonOptions,
    trial: &mut [f64],
    trial_residual: &mut [f64],
    natural: Option<&Factors>,
) -> (f64, Option<f64>) {
    let (mut t, mut bounded, mut r_full) = (1.0, None, None);
    let (step_norm, reach) = (norm(delta), norm(x));
    for _ in 0..options.max_halvings {
        for ((y, xi), di) in trial.iter_mut().zip(x).zip(delta) {
            *y = xi + t * di;
        }
        system.evaluate(trial, trial_residual, None);
        let r_trial = norm(trial_residual);
        r_full = r_full.or(Some(r_trial));
        let within = r_trial <= options.max_growth * r;
        if (within && !system.monotone()) || r_trial < r {
            return (t, r_full);
        }
        // a step longer than the iterate (a nearly singular J) proves nothing in J's metric
        let moderate = within && system.monotone() && t * step_norm <= reach;
        if moderate && natural.is_some_and(|f| natural_monotonicity(f, trial_residual, step_norm, t)) {
            return (t, r_full);
        }
        if within && bounded.is_none() {
            bounded = Some(t);
        }
        t *= 0.5;
    }
    (bounded.unwrap_or(2.0 * t), r_full)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_residual_that_grows_is_named_divergence() {
        let at = |residual| Iteration { residual, increment: 1.0, step: 1.0, frozen: false };
        let grown = NewtonError::NotConverged { history: vec![at(1.0), at(0.5), at(8.0)], scale: 1.0 };
        assert!(grown.to_string().starts_with("Newton diverged (its residual grew) in 3 step(s)"), "{grown}");
        let slow = NewtonError::NotConverged { history: vec![at(1.0), at(4.0), at(0.5)], scale: 1.0 };
        assert!(slow.to_string().starts_with("Newton did not converge in 3 step(s)"), "{slow}");
    }
}
