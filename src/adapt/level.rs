//! The solve on one mesh of the adaptive loop: Newton stopped by the estimators (S_lin),
//! inside a loop on the regularisation δ stopped by (S_reg).

use super::{AdaptError, AdaptSettings};
use crate::contact::nitsche::{Nitsche, NitscheParameters};
use crate::contact::projection::QuadraticSmoothing;
use crate::contact::ContactProblem;
use crate::elasticity::{Discretisation, Problem};
use crate::estimate::estimators::GlobalEstimators;
use crate::estimate::{estimate_iterate, Estimate, Linearisation};
use crate::solve::{newton_until, Cholesky, Iterate, NewtonOptions};
use std::time::Instant;

/// The result of one mesh level.
pub struct Level {
    /// Free unknowns of the final iterate.
    pub x: Vec<f64>,
    pub estimate: Estimate,
    /// The contact faces (None without Γ_C).
    pub nitsche: Option<Nitsche>,
    /// δ of the final iterate (None without Γ_C).
    pub delta: Option<f64>,
    /// Number of δ reductions and of Newton steps on this level.
    pub n_reg: usize,
    pub n_lin: usize,
    /// Wall time of the solves (Newton or Cholesky) and of the estimator runs [s].
    pub solve_seconds: f64,
    pub estimate_seconds: f64,
}

/// Without Γ_C: one Cholesky solve and one estimate.
pub fn solve_linear(problem: &Problem, disc: &Discretisation) -> Result<Level, AdaptError> {
    let clock = Instant::now();
    let system = problem.assemble(disc);
    let x = Cholesky::analyse(&disc.pattern)?.solve(&disc.pattern, &system.values, &system.rhs)?;
    let solve_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let estimate = estimate_iterate(problem, disc, &x, None, false)?;
    Ok(Level {
        x,
        estimate,
        nitsche: None,
        delta: None,
        n_reg: 0,
        n_lin: 0,
        solve_seconds,
        estimate_seconds: clock.elapsed().as_secs_f64(),
    })
}

/// The estimate of the contact iterate `x` and its global values; adds its time to `seconds`.
fn estimate_timed(
    problem: &Problem,
    disc: &Discretisation,
    x: &[f64],
    state: Linearisation,
    seconds: &mut f64,
) -> Result<(Estimate, GlobalEstimators), AdaptError> {
    let clock = Instant::now();
    let e = estimate_iterate(problem, disc, x, Some(state), false)?;
    *seconds += clock.elapsed().as_secs_f64();
    let global = e.estimators.global();
    Ok((e, global))
}

/// (S_lin): η_lin ≤ γ_lin (η_osc + η_flux + η_Neu + η_disc).
fn linearisation_small(g: &GlobalEstimators, gamma_lin: f64) -> bool {
    g.lin <= gamma_lin * (g.osc + g.flux + g.neu + g.disc)
}

/// (S_reg): η_reg ≤ γ_reg (η_osc + η_flux + η_Neu + η_disc + η_lin).
fn regularisation_small(g: &GlobalEstimators, gamma_reg: f64) -> bool {
    g.reg <= gamma_reg * (g.osc + g.flux + g.neu + g.disc + g.lin)
}

/// With contact on the facets tagged `tags`: Newton from `x0` at δ, stopped by (S_lin), and
/// δ ← δ/ρ_δ until (S_reg). An estimate follows every full Newton step that at least halved
/// the residual: a damped step does not solve the linearised problem, so its η_lin would not
/// be a bound, and while the residual does not contract (the active set still moves) (S_lin)
/// cannot hold. The final iterate is always estimated.
#[allow(clippy::too_many_arguments)]
pub fn solve_contact(
    problem: &Problem,
    disc: &Discretisation,
    tags: &[i32],
    parameters: NitscheParameters,
    newton: &NewtonOptions,
    settings: &AdaptSettings,
    x0: Vec<f64>,
    delta: f64,
) -> Result<Level, AdaptError> {
    let nitsche = Nitsche::new(&problem.mesh, &disc.topology, &problem.materials, tags, parameters);
    let mut contact = ContactProblem::new(problem, disc, nitsche, Box::new(QuadraticSmoothing { delta }));
    let (mut x, mut delta, mut n_reg, mut n_lin) = (x0, delta, 0, 0);
    let (mut solve_seconds, mut estimate_seconds) = (0.0, 0.0);
    loop {
        contact.projection = Box::new(QuadraticSmoothing { delta });
        let mut latest = None;
        let mut inside = 0.0;
        let clock = Instant::now();
        let report = newton_until(&contact, x, newton, |it: &Iterate| {
            if it.last.step < 1.0 || it.residual > 0.5 * it.last.residual {
                return false;
            }
            let state = Linearisation { nitsche: &contact.nitsche, x_prev: it.x_prev, delta };
            let e = estimate_timed(problem, disc, it.x, state, &mut inside);
            let stop = e.as_ref().map_or(true, |(_, g)| linearisation_small(g, settings.gamma_lin));
            latest = Some((it.x.to_vec(), e));
            stop
        })
        .map_err(|source| AdaptError::Newton { delta, source })?;
        solve_seconds += clock.elapsed().as_secs_f64() - inside;
        estimate_seconds += inside;
        n_lin += report.iterations.len();
        let (estimate, global) = match latest {
            Some((at, e)) if at == report.x => e?,
            _ => {
                let state = Linearisation { nitsche: &contact.nitsche, x_prev: &report.x_prev, delta };
                estimate_timed(problem, disc, &report.x, state, &mut estimate_seconds)?
            }
        };
        x = report.x;
        if regularisation_small(&global, settings.gamma_reg) {
            return Ok(Level {
                x,
                estimate,
                nitsche: Some(contact.nitsche),
                delta: Some(delta),
                n_reg,
                n_lin,
                solve_seconds,
                estimate_seconds,
            });
        }
        if n_reg == settings.max_delta_reductions {
            return Err(AdaptError::Regularisation { delta, reductions: n_reg, eta_reg: global.reg });
        }
        delta /= settings.rho_delta;
        n_reg += 1;
    }
}
