//! A posteriori error estimation (docs/method.md §3–§5). The reference it is verified
//! against, the dual norm of the residual on a finer space, is `verify::dual_norm`.

pub mod afw;
pub mod checks;
pub mod estimators;
pub mod face;
pub mod patch;
pub mod reconstruction;

use crate::contact::Linearisation;
use crate::elasticity::{Discretisation, Problem};
use checks::{check, Equilibration};
use estimators::{estimate, Estimators};
use reconstruction::{reconstruct, EstimateError, Reconstruction};

/// The reconstruction, the estimators and, if asked, the equilibration checks of one iterate.
pub struct Estimate {
    pub reconstruction: Reconstruction,
    pub estimators: Estimators,
    pub equilibration: Option<Equilibration>,
}

/// Estimates the error of the free unknowns `x` (with the state of its Newton step when Γ_C
/// exists).
pub fn estimate_iterate(
    problem: &Problem,
    disc: &Discretisation,
    x: &[f64],
    contact: Option<&Linearisation>,
    checks: bool,
) -> Result<Estimate, EstimateError> {
    let u = problem.displacement(disc, x);
    let reconstruction = reconstruct(problem, &disc.topology, &u, contact)?;
    let estimators = estimate(problem, &disc.topology, &u, &reconstruction, contact);
    let equilibration = checks.then(|| check(problem, &disc.topology, &u, &reconstruction, contact));
    Ok(Estimate { reconstruction, estimators, equilibration })
}
