//! A posteriori error estimation (docs/method.md §3–§5). The reference it is verified
//! against, the dual norm of the residual on a finer space, is `estimate::reference`.

pub mod afw;
pub mod checks;
pub mod estimators;
pub mod face;
pub mod facets;
pub mod patch;
pub mod reconstruction;
pub mod reference;

use crate::contact::Linearisation;
use crate::elasticity::problem::load_degree;
use crate::elasticity::{BodyForce, Discretisation, Displacement, Problem};
use crate::mesh::Topology;
use checks::{check_sampled, Equilibration, Violation};
use estimators::{estimate_sampled, Estimators};
use facets::sampled_facets;
use reconstruction::{covered, reconstruct_sampled, Reconstruction};

/// Why an iterate has no estimate.
#[derive(Debug, thiserror::Error)]
pub enum EstimateError {
    #[error("the estimator covers the Nitsche variant theta = 0 only (this run uses theta = {0})")]
    Theta(f64),
    #[error("patch of the vertex at ({x}, {y}): {why}")]
    Patch { x: f64, y: f64, why: patch::PatchError },
    #[error(
        "no guaranteed bound: the reconstructed stress violates {} by {:.1e} near ({:.4}, {:.4}); \
         the iterate does not solve its linearised problem, or the mesh is too thin (docs/method.md §4.1)",
        .0.condition, .0.value, .0.at[0], .0.at[1]
    )]
    NotEquilibrated(Violation),
}

/// The largest relative violation of an equilibration condition that an estimate accepts
/// on any mesh (see [`equilibration_tolerance`] for graded ones). Discrete solutions and full
/// Newton steps stay below it on the adaptive runs of docs/method.md §5.2 (up to 1.5·10⁻¹¹ as
/// doubles), the refined linear solve ([`Problem::solve_refined`]) at 3.4·10⁻¹⁵ on cells graded
/// by 10⁸, the refined contact iterates of Hertz's adaptive runs at 8.5·10⁻¹⁴; a damped step
/// leaves 10⁻⁵ and more.
pub const EQUILIBRATION_TOLERANCE: f64 = 1e-10;

/// How many times [`checks::representation_bound`] an estimate accepts: the violations of
/// converged double solves measured on graded meshes reach 25 times it (docs/method.md §5.2).
pub const REPRESENTATION_FACTOR: f64 = 300.0;

/// The largest relative violation an estimate of the iterate `u` accepts:
/// max([`EQUILIBRATION_TOLERANCE`], [`REPRESENTATION_FACTOR`] × the representation bound).
/// The second term, ε |u_h| / (h |∇u_h|) up to material factors (γ₀ times that on Γ_C), is
/// what a double u_h leaves on cells much smaller than |u_h| / |∇u_h|; it exceeds the first
/// only on cells about 10³ times smaller than that (10 on Γ_C with γ₀ = 100;
/// docs/method.md §5.2). For a refined pair hi + lo it is ε times smaller, and the first term
/// decides on any mesh.
pub fn equilibration_tolerance(problem: &Problem, u: &Displacement, contact: Option<&Linearisation>) -> f64 {
    EQUILIBRATION_TOLERANCE.max(REPRESENTATION_FACTOR * checks::representation_bound(problem, u, contact))
}

/// Degree of the cell rule of the volume data (docs/method.md §4) and of the divergence
/// check: 2p integrates exactly every product of σ(u_h), the stress basis, ψ_a and P_{p−1},
/// and f ψ_a ψ_m for an f constant on each cell (none, or ρ a); a general field f gets the
/// load rule of the assembly.
pub(crate) fn volume_degree(problem: &Problem) -> usize {
    match problem.body_force {
        BodyForce::Field(_) => load_degree(problem.mesh.order),
        BodyForce::None | BodyForce::Acceleration(_) => 2 * problem.mesh.order,
    }
}

/// The reconstruction, the estimators and the equilibration checks of one iterate.
pub struct Estimate {
    pub reconstruction: Reconstruction,
    pub estimators: Estimators,
    pub equilibration: Equilibration,
}

/// Estimates the error of the free unknowns `x` (with the state of its Newton step when Γ_C
/// exists).
///
/// # Guarantee
///
/// An `Ok` estimate is a guaranteed bound, η_tot ≥ ‖R(u_h)‖ (docs/method.md §5): every
/// equilibration condition on which the bound rests (divergence, normal continuity, Neumann
/// and contact tractions, weak symmetry for p ≥ 2, patch compatibility) holds to
/// [`equilibration_tolerance`] relative. They hold for the discrete solution without Γ_C and
/// for a contact iterate that solves the linearised problem of its Newton step (a full step,
/// converged or not); a damped or perturbed iterate, or a mesh outside the estimator's range,
/// fails them and gets [`EstimateError::NotEquilibrated`] naming the condition and the place.
/// A double `x` solves its equation only to ε |u_h| / (h |∇u_h|) relative, so on cells much
/// smaller than |u_h| / |∇u_h| the checks hold only to that ([`checks::representation_bound`]);
/// the refined pair of a linear solve, or of a contact iterate after a full Newton step
/// (`ContactSolution::displacement`), does not have that floor ([`estimate_displacement`]).
pub fn estimate_iterate(
    problem: &Problem,
    disc: &Discretisation,
    x: &[f64],
    contact: Option<&Linearisation>,
) -> Result<Estimate, EstimateError> {
    estimate_displacement(problem, &disc.topology, &problem.displacement(disc, x).into(), contact)
}

/// [`estimate_iterate`] of the nodal displacements `u`, a double u_h or a refined pair x + lo
/// ([`Problem::solve_refined`], or a contact iterate's `ContactSolution::displacement`): the
/// estimator reads u_h only through the nodal differences of each cell
/// ([`Displacement::relative`], exact for the pair) and, on Γ_C, through the Nitsche terms in
/// difference form (`contact::nitsche::FaceDisplacement`: the nodal differences and the
/// compensated jump of the first nodes less the gap). Same guarantee, for u_h = x + lo: on the
/// refined pair every condition holds to round-off whatever the grading; measured ≤ 3.4·10⁻¹⁵
/// for linear solves graded by 10⁸ and ≤ 8.5·10⁻¹⁴ along Hertz's adaptive runs
/// (docs/method.md §5.2).
pub fn estimate_displacement(
    problem: &Problem,
    topology: &Topology,
    u: &Displacement,
    contact: Option<&Linearisation>,
) -> Result<Estimate, EstimateError> {
    covered(contact)?;
    // the Γ_C data, sampled once for the reconstruction, the checks and the estimators
    let facets = contact.map(|c| sampled_facets(&problem.mesh, topology, c, u));
    let facets = facets.as_deref();
    let reconstruction = reconstruct_sampled(problem, topology, u, contact.is_some(), facets.unwrap_or_default())?;
    let equilibration = check_sampled(problem, topology, &reconstruction, facets.unwrap_or_default());
    let violation = equilibration.violation(problem.mesh.order);
    if violation.value.is_nan() || violation.value > equilibration_tolerance(problem, u, contact) {
        return Err(EstimateError::NotEquilibrated(violation));
    }
    let estimators = estimate_sampled(problem, topology, u, &reconstruction, facets);
    Ok(Estimate { reconstruction, estimators, equilibration })
}
