//! The strength reduction (docs/method.md §1.9): FS_SR, the largest k for which the sliding
//! plane with its strength divided by k (F/k, c/k, s/k) still holds the body.
//!
//! k is followed from the solution at k = 1: it goes at once to 1 − 2 tol times the k at which
//! the state at k = 1 slides by limit equilibrium (k = FS_LE), then grows by steps from
//! 2 tol k that double while the joint holds (by a quarter where a retry or no FS_LE rules
//! the jump out), then the bracket [held, failed] is bisected, every solve from the last
//! state that held at the δ of the start (after a load path, the friction law on the slip
//! from that state). Near the
//! limit Newton also fails where the joint holds (the tangential stiffness of a slipping joint
//! vanishes), so a failed solve at k counts as a loss of
//! equilibrium only where the last state that held, judged by limit equilibrium with the
//! strength of k, slides: FS_LE(held state; k) ≤ 1 + [`STRENGTH_TOLERANCE`]. Any other failure
//! is Newton's: the step from the last k that held halves, and a step below the tolerance is
//! an error ([`StrengthError::Stalled`]). On a straight joint whose plane has friction alone
//! (Coulomb, no cohesion), N and T are the statics of the body above it whatever k, so FS_SR
//! must equal FS_LE: a gap of more than [`AGREEMENT`] is an error ([`StrengthError::Disagrees`]).

use crate::contact::{
    solve_by_continuation, ContactError, ContactJoint, ContactProblem, ContactSolution, Continuation, JointLaw,
};
use crate::elasticity::{Discretisation, Problem};
use crate::solve::{newton, NewtonError, NewtonOptions};

/// The relative width of the FS_SR bracket at which `damfem solve --strength-reduction` and
/// `damfem safety` stop.
pub const STRENGTH_TOLERANCE: f64 = 2e-3;

/// The largest relative gap between FS_SR and FS_LE on a straight joint without cohesion.
pub const AGREEMENT: f64 = 5e-3;

/// k at which the search gives up as unbounded: the joint holds with almost no strength.
const UNBOUNDED: f64 = 1e3;

/// The sliding safety factor by strength reduction.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct StrengthReduction {
    /// The largest k that held, and the smallest that did not: FS_SR lies between.
    pub held: f64,
    pub failed: f64,
    /// Contact solves made, the first at k = 1 included.
    pub solves: usize,
    /// Solves that failed without a loss of equilibrium, tried again closer to the last k that held.
    pub retried: usize,
}

/// Why a strength reduction has no factor to give.
#[derive(Debug, thiserror::Error)]
pub enum StrengthError {
    #[error(
        "the strength reduction stalled at k = {held:.4}: Newton failed at k = {k:.4}, {step:.1e} above it, where the \
         last state that held still has FS_LE = {fs:.4} with the strength divided by k, so the failure is not a loss \
         of equilibrium; FS_SR is not known. Newton at k: {source}"
    )]
    Stalled { held: f64, k: f64, step: f64, fs: f64, source: NewtonError },
    #[error(
        "FS_SR in [{held:.4}, {failed:.4}] and FS_LE = {fs_le:.4} differ by {gap:.2} % on a straight joint with \
         friction alone, where both are F N / |T| of the same forces: the strength reduction is not to be trusted"
    )]
    Disagrees { held: f64, failed: f64, fs_le: f64, gap: f64 },
    /// The solve at k = 1 that the reduction starts from failed.
    #[error(transparent)]
    Start(#[from] ContactError),
}

/// FS_SR of the whole joint to the relative `tolerance`, from the solution at k = 1 reached
/// along the δ path of `settings` ([`reduce_strength`]).
pub fn strength_reduction(
    problem: &Problem,
    disc: &Discretisation,
    joint: &ContactJoint,
    settings: &Continuation,
    tolerance: f64,
) -> Result<StrengthReduction, StrengthError> {
    let start = solve_by_continuation(problem, disc, joint, settings)?;
    reduce_strength(problem, disc, joint, &joint.every_curve(), &start, &settings.newton, tolerance)
}

/// FS_SR of the sliding plane made of the curves i with `plane[i]` (the other curves keep
/// their strength) to the relative `tolerance` from `start`, the solution at k = 1 (the
/// module's doc). The crack that uplift fills is kept at its length in `start`.
pub fn reduce_strength(
    problem: &Problem,
    disc: &Discretisation,
    joint: &ContactJoint,
    plane: &[bool],
    start: &ContactSolution,
    newton_options: &NewtonOptions,
    tolerance: f64,
) -> Result<StrengthReduction, StrengthError> {
    let mut sr = StrengthReduction { held: 1.0, failed: f64::INFINITY, solves: 1, retried: 0 };
    // the last state that held, and FS_LE of its plane with its strength
    let (mut x, mut held_fs) = (start.x.clone(), plane_safety_factor(start, plane));
    // one contact problem for every k: the same faces, stiffness and factorisation
    let mut contact = ContactProblem::new(problem, disc, &joint.as_solved(start), start.smoothing);
    let mut step = 0.25;
    while sr.failed - sr.held > tolerance * sr.held && sr.held <= UNBOUNDED {
        let held = sr.held;
        let jump = predicted_limit(&sr, held_fs, tolerance).filter(|&k| k > held + step);
        let k = match (jump, sr.failed.is_finite()) {
            (Some(k), _) => k,
            (None, true) => (0.5 * (held + sr.failed)).min(held + step),
            (None, false) => held + step,
        };
        contact.nitsche.laws = joint.reduced(k, plane).laws;
        if start.nitsche.slip_origin().is_some() {
            contact.set_slip_origin(Some(&x));
        }
        sr.solves += 1;
        match newton(&contact, x.clone(), newton_options) {
            Ok(report) => {
                (sr.held, x) = (k, report.x);
                held_fs = plane_safety_factor(&contact.solution(x.clone(), Vec::new(), Vec::new()), plane);
                step = match jump {
                    Some(_) => 2.0 * tolerance * k,
                    None => (2.0 * (k - held)).min(0.25 * k),
                };
            }
            // the strength of the plane is k times smaller than that of the state that held
            Err(source) => match held_fs.map(|fs| fs * held / k) {
                Some(fs) if fs > 1.0 + tolerance => {
                    sr.retried += 1;
                    step = 0.5 * (k - held);
                    if step < 0.5 * tolerance * held {
                        return Err(StrengthError::Stalled { held, k, step: k - held, fs, source });
                    }
                }
                _ => sr.failed = k,
            },
        }
    }
    agreement(&sr, start, joint, plane)?;
    Ok(sr)
}

/// Before a bracket and before any retry, the k at which the last state that held, with
/// FS_LE = `held_fs` under the strength divided by k_held, slides by limit equilibrium
/// (k = k_held · FS_LE), less 2 `tolerance`: the search goes there at once, where a failure
/// is still Newton's (FS_LE(held; k) > 1 + tolerance) and is tried again closer.
fn predicted_limit(sr: &StrengthReduction, held_fs: Option<f64>, tolerance: f64) -> Option<f64> {
    let fresh = !sr.failed.is_finite() && sr.retried == 0;
    held_fs.filter(|fs| fresh && fs.is_finite()).map(|fs| sr.held * fs * (1.0 - 2.0 * tolerance))
}

/// FS_LE of the `plane` of `solution`, with the laws it was solved with.
fn plane_safety_factor(solution: &ContactSolution, plane: &[bool]) -> Option<f64> {
    solution.forces(|k| plane[solution.nitsche.faces[k].curve]).sliding_safety_factor
}

/// [`StrengthError::Disagrees`] where FS_SR and FS_LE of `start` must agree and do not: a
/// straight joint whose `plane` has Coulomb friction alone.
fn agreement(
    sr: &StrengthReduction,
    start: &ContactSolution,
    joint: &ContactJoint,
    plane: &[bool],
) -> Result<(), StrengthError> {
    let coulomb = (joint.laws.iter().zip(plane)).all(|(c, &on)| !on || matches!(c.law, JointLaw::Coulomb { .. }));
    let fs_le = plane_safety_factor(start, plane);
    let Some(fs_le) = fs_le.filter(|_| coulomb && start.on_one_line() && sr.failed.is_finite()) else { return Ok(()) };
    let gap = [sr.held, sr.failed].map(|k| (k - fs_le).abs() / fs_le).into_iter().fold(f64::INFINITY, f64::min);
    let inside = sr.held <= fs_le && fs_le <= sr.failed;
    match inside || gap <= AGREEMENT {
        true => Ok(()),
        false => Err(StrengthError::Disagrees { held: sr.held, failed: sr.failed, fs_le, gap: 100.0 * gap }),
    }
}
