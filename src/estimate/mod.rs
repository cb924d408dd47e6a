//! Error measures and a posteriori error estimation (docs/method.md §2–§4).
//!
//! [`dual_norm`] computes the dual norm of the residual on a finer space, the reference
//! against which estimators are verified.

pub mod afw;
pub mod checks;
pub mod dual_norm;
pub mod estimators;
pub mod face;
pub mod patch;
pub mod reconstruction;

use crate::contact::nitsche::Nitsche;
use crate::contact::projection::QuadraticSmoothing;
use crate::elasticity::{Discretisation, Problem};
use checks::{check, Equilibration};
use estimators::{estimate, Estimators};
use reconstruction::{reconstruct, ContactState, EstimateError, Reconstruction};

/// The reconstruction, the estimators and, if asked, the equilibration checks of one iterate.
pub struct Estimate {
    pub reconstruction: Reconstruction,
    pub estimators: Estimators,
    pub equilibration: Option<Equilibration>,
}

/// What the contact terms need of a Newton iterate: the faces, the previous iterate (the
/// linearisation point, free unknowns) and the regularisation δ.
#[derive(Clone, Copy)]
pub struct Linearisation<'a> {
    pub nitsche: &'a Nitsche,
    pub x_prev: &'a [f64],
    pub delta: f64,
}

/// Estimates the error of the free unknowns `x` (with the contact state when Γ_C exists).
pub fn estimate_iterate(
    problem: &Problem,
    disc: &Discretisation,
    x: &[f64],
    contact: Option<Linearisation>,
    checks: bool,
) -> Result<Estimate, EstimateError> {
    let u = problem.displacement(disc, x);
    let u_prev = contact.map(|c| problem.displacement(disc, c.x_prev));
    let projection = QuadraticSmoothing { delta: contact.map_or(0.0, |c| c.delta) };
    let state = contact.zip(u_prev.as_deref()).map(|(c, u_prev)| ContactState {
        nitsche: c.nitsche,
        projection: &projection,
        u_prev,
    });
    let reconstruction = reconstruct(problem, &disc.topology, &u, state.as_ref())?;
    let estimators = estimate(problem, &disc.topology, &u, &reconstruction, state.as_ref());
    let equilibration = checks.then(|| check(problem, &disc.topology, &u, &reconstruction, state.as_ref()));
    Ok(Estimate { reconstruction, estimators, equilibration })
}
