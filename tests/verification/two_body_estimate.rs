//! The estimator across a joint between two bodies (docs/method.md §5.6): equilibration on
//! both sides to round-off, the estimators that vanish at an exact solution, and the bound
//! against the dual norm of the residual.

use super::two_body::{joint, pressed_blocks};
use damfem::contact::projection::Smoothing;
use damfem::contact::uplift::Drains;
use damfem::contact::{continuation, ContactJoint, ContactProblem, CrackRule, JointLine, Linearisation, Uplift};
use damfem::elasticity::Problem;
use damfem::estimate::{estimate_iterate, Estimate};
use damfem::solve::NewtonOptions;
use damfem::verify::dual_norm::{residual_dual_norm, sharp_reference, REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS};

/// Newton to δ = 10⁻¹² across the joint, and the estimate of the solution: the nodal
/// displacement and the estimate.
fn solve_and_estimate(problem: &Problem, joint: &ContactJoint) -> (Vec<[f64; 2]>, Estimate) {
    let disc = problem.discretise();
    let smoothing = Smoothing { delta: 1e-12 };
    let mut contact = ContactProblem::new(problem, &disc, joint, smoothing);
    let x0 = vec![0.0; disc.dofs.n_free];
    let (x, stages) =
        continuation(&mut contact, 1e-12, 1e-3, x0, &NewtonOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let x_prev = &stages.last().expect("one stage at least").report.x_prev;
    let nitsche = joint.faces(problem, &disc);
    let state = Linearisation::new(problem, &disc, &nitsche, smoothing, x_prev);
    let estimate = estimate_iterate(problem, &disc, &x, Some(&state)).unwrap_or_else(|e| panic!("{e}"));
    (problem.displacement(&disc, &x), estimate)
}

/// The two-body patch test, estimated. Source: docs/method.md §5.6 (the bound across a joint).
/// Goal: on matching and non-matching sides, P1 and P2, the reconstruction is equilibrated on
/// both blocks to round-off, η_flux and η_disc vanish (u_h = u, whose traction on the joint is
/// constant), so η_tot is round-off of ‖σ_h‖, and so does the dual norm of the residual, whose
/// jump term on the joint balances the volume terms of both blocks only if it is right.
/// Parameters: the data of the two-body patch test (tests/verification/two_body.rs), 4 | 4 and
/// 3 | 5 faces along the joint, γ₀ = 100, θ = 0.
#[test]
fn two_body_patch_test_estimate_vanishes() {
    for order in [1, 2] {
        for nx in [[4, 4], [3, 5]] {
            let (problem, _, _) = pressed_blocks(nx, order, 0.0);
            let joint = joint(0.0);
            let (u, estimate) = solve_and_estimate(&problem, &joint);
            let eq = estimate.equilibration;
            let worst = eq.divergence.max(eq.normal_continuity).max(eq.contact).max(eq.compatibility);
            let global = estimate.estimators.global();
            let stress = damfem::estimate::estimators::stress_norm(&problem, &estimate.reconstruction);
            println!(
                "P{order}, {} | {} faces: worst equilibration {worst:.1e}, η_flux {:.1e}, η_disc {:.1e}, η_tot {:.1e} (‖σ_h‖ {stress:.2e})",
                nx[0], nx[1], global.flux, global.disc, global.tot
            );
            let residual = residual_dual_norm(&problem, &u, Some(&joint), 1).unwrap_or_else(|e| panic!("{e}"));
            println!("  dual norm of the residual (refined once): {residual:.1e}");
            assert!(worst < 1e-12, "P{order} {nx:?}: equilibration {worst:.2e}");
            assert!(global.flux.max(global.disc) < 1e-10 * stress, "P{order} {nx:?}: {global:?}");
            assert!(residual < 1e-12 * stress, "P{order} {nx:?}: the residual of the exact solution is {residual:.2e}");
        }
    }
}

/// The bound across a joint. Source: docs/method.md §5.6. Goal: for blocks pressed by a tilted
/// top (a non-trivial joint traction, partly closed), η_tot ≥ the dual norm of the residual
/// (its Riesz representative on a richer P2 space), on matching and non-matching
/// sides, P1 and P2; the effectivity is printed.
/// Parameters: [`pressed_blocks`] with tilt −1.5 (the top's right end pulled up, so the joint
/// opens on the right), 4 | 4 and 3 | 5 faces along the joint, γ₀ = 100, θ = 0; the sharp
/// reference (refined where the representative concentrates until two values agree within 2 %).
#[test]
fn two_body_estimate_bounds_the_residual() {
    for order in [1, 2] {
        for nx in [[4, 4], [3, 5]] {
            let (problem, _, _) = pressed_blocks(nx, order, -1.5);
            let joint = joint(0.0);
            let (u, estimate) = solve_and_estimate(&problem, &joint);
            let sharp = sharp_reference(&problem, &u, Some(&joint), REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS)
                .unwrap_or_else(|e| panic!("{e}"));
            let reference = sharp.norm();
            let global = estimate.estimators.global();
            println!(
                "P{order}, {} | {} faces: η_tot {:.4e}, reference {reference:.4e} (converged {}), I_eff {:.2}",
                nx[0],
                nx[1],
                global.tot,
                sharp.converged,
                global.tot / reference
            );
            assert!(global.tot >= reference, "P{order} {nx:?}: η_tot {:.4e} < reference {reference:.4e}", global.tot);
        }
    }
}

/// The bound across a joint with uplift. Source: docs/method.md §1.8 and §5.6 (the pore
/// pressure is part of the Γ_C datum of both sides). Goal: for the tilted blocks of
/// [`two_body_estimate_bounds_the_residual`] with a drained uplift diagram in the joint, the
/// reconstruction is equilibrated on both blocks to round-off (the slave facets carry
/// t = (q(P_γ) − p_u) ν + …, the master facets −t dx/dy) and η_tot ≥ the sharp reference, on
/// matching and non-matching sides, P1 and P2; the effectivity is printed.
/// Parameters: [`pressed_blocks`] with tilt −1.5, 4 | 4 and 3 | 5 faces along the joint,
/// γ₀ = 100, θ = 0; p_u from 5·10⁻³ at the heel (x = 0) to 10⁻³ at the toe (x = 1), drains at
/// x = 0.37 (inside a face of either side) with efficiency ½, the crack's pressure ignored.
#[test]
fn two_body_estimate_with_uplift_is_equilibrated_and_bounds_the_residual() {
    let uplift = Uplift {
        line: JointLine::new([0.0, 0.5], [1.0, 0.5]),
        upstream: 5e-3,
        downstream: 1e-3,
        drains: Some(Drains { distance: 0.37, efficiency: 0.5 }),
        rule: CrackRule::Kept { prior: 0.0 },
        crack: 0.0,
    };
    for order in [1, 2] {
        for nx in [[4, 4], [3, 5]] {
            let (problem, _, _) = pressed_blocks(nx, order, -1.5);
            let joint = joint(0.0).with_uplift(uplift.clone());
            let (u, estimate) = solve_and_estimate(&problem, &joint);
            let eq = estimate.equilibration;
            let worst = eq.divergence.max(eq.normal_continuity).max(eq.contact).max(eq.compatibility);
            let sharp = sharp_reference(&problem, &u, Some(&joint), REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS)
                .unwrap_or_else(|e| panic!("{e}"));
            let reference = sharp.norm();
            let global = estimate.estimators.global();
            println!(
                "P{order}, {} | {} faces: worst equilibration {worst:.1e}, η_tot {:.4e}, reference {reference:.4e} \
                 (converged {}), I_eff {:.2}",
                nx[0],
                nx[1],
                global.tot,
                sharp.converged,
                global.tot / reference
            );
            assert!(worst < 1e-12, "P{order} {nx:?}: equilibration {worst:.2e}");
            assert!(global.tot >= reference, "P{order} {nx:?}: η_tot {:.4e} < reference {reference:.4e}", global.tot);
        }
    }
}
