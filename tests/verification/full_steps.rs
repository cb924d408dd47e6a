//! The bound at every full Newton step of a contact solve: the loop that the friction and the
//! cohesive bound tests share.

use damfem::contact::projection::Smoothing;
use damfem::contact::{ContactJoint, ContactProblem, Linearisation};
use damfem::elasticity::{Discretisation, Problem};
use damfem::estimate::estimators::GlobalEstimators;
use damfem::estimate::reference::{sharp_reference, REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS};
use damfem::solve::{newton_until, NewtonOptions};

/// At one full Newton step: ‖F‖, the global estimators, the sharp reference of the residual's
/// dual norm and the worst equilibration check.
pub struct FullStep {
    pub residual: f64,
    pub eta: GlobalEstimators,
    pub reference: f64,
    pub worst: f64,
}

/// Newton on `joint` from u = 0 at each smoothing of `deltas` in turn, with every full step
/// estimated and its residual's dual norm computed by the sharp reference; the converged
/// iterate and the steps.
pub fn full_steps(
    problem: &Problem,
    disc: &Discretisation,
    joint: &ContactJoint,
    deltas: &[f64],
) -> (Vec<f64>, Vec<FullStep>) {
    let mut contact = ContactProblem::new(problem, disc, joint, Smoothing { delta: deltas[0] });
    let (mut x, mut steps) = (vec![0.0; disc.dofs.n_free], Vec::new());
    for &delta in deltas {
        contact.set_delta(delta);
        let report = newton_until(&contact, x, &NewtonOptions::default(), |it| {
            if it.last.step == 1.0 {
                let state = Linearisation::new(problem, disc, &contact.nitsche, contact.smoothing, it.x_prev);
                let e = damfem::estimate::estimate_iterate(problem, disc, it.x, Some(&state))
                    .unwrap_or_else(|e| panic!("{e}"));
                let u = problem.displacement(disc, it.x);
                let reference = sharp_reference(problem, &u, Some(joint), REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS)
                    .unwrap_or_else(|e| panic!("{e}"))
                    .norm();
                let (eta, worst) = (e.estimators.global(), e.equilibration.worst(problem.mesh.order));
                steps.push(FullStep { residual: it.residual, eta, reference, worst });
            }
            false
        })
        .unwrap_or_else(|e| panic!("Newton at δ = {delta:e}: {e}"));
        x = report.x;
    }
    (x, steps)
}

/// Every step equilibrated to round-off (10⁻¹⁰) and η_tot ≥ its reference; `label` names the case.
pub fn assert_bounds(label: &str, steps: &[FullStep]) {
    assert!(!steps.is_empty(), "{label}: no full step");
    for s in steps {
        let g = &s.eta;
        println!(
            "{label} |F| {:.2e}: eta_tot {:.4e} (disc {:.2e} reg {:.2e} lin {:.2e}) reference {:.4e} I_eff {:.3}; worst check {:.1e}",
            s.residual,
            g.tot,
            g.disc,
            g.reg,
            g.lin,
            s.reference,
            g.tot / s.reference,
            s.worst
        );
        assert!(s.worst < 1e-10, "{label}: equilibration {:e}", s.worst);
        assert!(g.tot >= s.reference, "{label}: eta_tot {} below the reference {}", g.tot, s.reference);
    }
}
