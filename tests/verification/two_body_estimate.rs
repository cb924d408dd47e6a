//! The estimator across a joint between two bodies (docs/method.md §5.6): equilibration on
//! both sides to round-off, the estimators that vanish at an exact solution, and the bound
//! against the dual norm of the residual.

use damfem::contact::nitsche::NitscheParameters;
use damfem::contact::projection::Smoothing;
use damfem::contact::uplift::Drains;
use damfem::contact::{continuation, ContactJoint, ContactProblem, JointLine, Linearisation, Uplift};
use damfem::elasticity::{BodyForce, Dirichlet, Material, Neumann, Problem, Traction, VectorFn};
use damfem::estimate::{estimate_iterate, Estimate};
use damfem::mesh::structured::{two_blocks, BOTTOM, JOINT, JOINT_LOWER, LEFT, LOWER, RIGHT, TOP};
use damfem::solve::NewtonOptions;
use damfem::verify::dual_norm::{residual_dual_norm, sharp_reference, REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS};
use std::sync::Arc;

/// The joint between the blocks of [`two_blocks`], the upper block's side the slave (θ = 0).
fn joint() -> ContactJoint {
    ContactJoint { masters: vec![JOINT_LOWER], ..ContactJoint::frictionless(vec![JOINT], NitscheParameters::default()) }
}

/// Blocks pressed together by u = (0, −b) at the top over u = 0 at the bottom, with the
/// lateral tractions of uniaxial strain (the two-body patch test's data, whose solution is in
/// V_h) or, with `tilt`, the top pushed by u = (0, −b(1 + tilt x)) without lateral tractions.
fn pressed_blocks(nx: [usize; 2], order: usize, tilt: f64) -> Problem {
    let b = 1e-2;
    let (lower, upper) =
        (Material { young: 3.0, poisson: 0.3, density: 0.0 }, Material { young: 1.0, poisson: 0.2, density: 0.0 });
    let modulus = |m: Material| {
        let (lambda, mu) = m.lame();
        (lambda, lambda + 2.0 * mu)
    };
    let ((l2, m2), (l1, m1)) = (modulus(lower), modulus(upper));
    let p = b / (0.5 / m2 + 0.5 / m1);
    let sigma_xx = move |y: f64| if y < 0.5 { -l2 * p / m2 } else { -l1 * p / m1 };
    let side = |sign: f64| -> VectorFn { Arc::new(move |x: [f64; 2]| [sign * sigma_xx(x[1]), 0.0]) };
    let mesh = two_blocks(nx[0], nx[1], 2, 0.5, order);
    let neumann = if tilt == 0.0 {
        vec![
            Neumann { tag: LEFT, traction: Traction::Field(side(-1.0)) },
            Neumann { tag: RIGHT, traction: Traction::Field(side(1.0)) },
        ]
    } else {
        Vec::new()
    };
    Problem {
        materials: mesh.cell_tags.iter().map(|&t| if t == LOWER { lower } else { upper }).collect(),
        dirichlet: vec![
            Dirichlet { tag: BOTTOM, fix: [true; 2], value: Arc::new(|_| [0.0; 2]) },
            Dirichlet { tag: TOP, fix: [true; 2], value: Arc::new(move |x| [0.0, -b * (1.0 + tilt * x[0])]) },
        ],
        neumann,
        body_force: BodyForce::None,
        mesh,
    }
}

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
            let problem = pressed_blocks(nx, order, 0.0);
            let joint = joint();
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
            let problem = pressed_blocks(nx, order, -1.5);
            let joint = joint();
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
        crack_filled: false,
        crack: 0.0,
    };
    for order in [1, 2] {
        for nx in [[4, 4], [3, 5]] {
            let problem = pressed_blocks(nx, order, -1.5);
            let joint = ContactJoint { uplift: Some(uplift.clone()), ..joint() };
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
