//! The estimator's guarantee outside its hypotheses: iterates that do not solve their
//! linearised problem (a damped Newton step, a perturbed displacement) are either refused
//! with `EstimateError::NotEquilibrated`, or estimated with η_tot above the reference.

use super::support::*;

use damfem::contact::projection::Smoothing;
use damfem::contact::{solve_by_continuation, ContactJoint, ContactProblem, Continuation, Linearisation};
use damfem::elasticity::{Discretisation, Problem};
use damfem::estimate::reference::{residual_dual_norm, residual_riesz, sharp_reference, sharp_start};
use damfem::estimate::{estimate_iterate, EstimateError};
use damfem::fem::dofs::FIXED;
use damfem::mesh::structured::{unit_square, BOTTOM};
use damfem::solve::NewtonOptions;
use damfem::verify::rng::Rng;
use damfem::verify::{v1, v3};

/// What the estimator made of an iterate.
#[derive(Debug, PartialEq)]
enum Outcome {
    Refused,
    Bound,
}

/// Estimates `x` (with the linearisation point `x_prev` on Γ_C = `joint`) and checks the
/// guarantee: a refusal names an equilibration condition, an accepted η_tot is at least the
/// dual-norm reference on the mesh refined twice.
fn guarantee(problem: &Problem, disc: &Discretisation, x: &[f64], contact: Option<(&ContactJoint, &[f64])>) -> Outcome {
    let nitsche = contact.map(|(joint, _)| joint.faces(problem, disc));
    let state = contact
        .zip(nitsche.as_ref())
        .map(|((_, x_prev), nitsche)| Linearisation::new(problem, disc, nitsche, Smoothing { delta: DELTA }, x_prev));
    match estimate_iterate(problem, disc, x, state.as_ref()) {
        Err(EstimateError::NotEquilibrated(v)) => {
            println!("  refused: {} by {:.1e} at ({:.3}, {:.3})", v.condition, v.value, v.at[0], v.at[1]);
            assert!(v.value > damfem::estimate::EQUILIBRATION_TOLERANCE, "{v:?}");
            Outcome::Refused
        }
        Err(e) => panic!("{e}"),
        Ok(e) => {
            let u = problem.displacement(disc, x);
            let reference = residual_dual_norm(problem, &u, contact.map(|(j, _)| j), 2).unwrap();
            let tot = e.estimators.global().tot;
            println!("  accepted: eta_tot {tot:.4e}, reference {reference:.4e}");
            assert!(tot >= reference, "accepted an eta_tot {tot:e} below the reference {reference:e}");
            Outcome::Bound
        }
    }
}

/// δ of the contact cases.
const DELTA: f64 = 1e-3;

/// `x` plus `amplitude` · max|x| times a smooth field on the free dofs.
fn smooth_perturbation(problem: &Problem, disc: &Discretisation, x: &[f64], amplitude: f64) -> Vec<f64> {
    let scale = amplitude * x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut y = x.to_vec();
    for (node, p) in problem.mesh.points.iter().enumerate() {
        let field = [(3.0 * p[0]).sin() * (2.0 * p[1]).cos(), (2.0 * p[0]).cos() * (3.0 * p[1] + 1.0).sin()];
        for (i, value) in field.iter().enumerate() {
            let free = disc.dofs.free[2 * node + i];
            if free != FIXED {
                y[free] += scale * value;
            }
        }
    }
    y
}

/// `x` plus `amplitude` · max|x| times an independent uniform value in [−1, 1) per free dof.
fn rough_perturbation(x: &[f64], amplitude: f64, seed: u64) -> Vec<f64> {
    let scale = amplitude * x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut rng = Rng::new(seed);
    x.iter().map(|v| v + scale * rng.symmetric()).collect()
}

/// Source: docs/method.md §5 (the bound rests on the equilibration conditions), issue
/// "Estimator: a bound that holds for every input it accepts".
/// Goal: without Γ_C, a displacement that is not the discrete solution (perturbed by a
/// smooth field and per dof, 10⁻¹ relative) is never estimated with η_tot below the dual-norm
/// reference; it is refused with the violated condition named.
/// Parameters: V1 (manufactured, clamped square), structured n = 8, P1 and P2; reference on
/// the mesh refined twice.
#[test]
fn perturbed_discrete_solution_is_refused_or_bounded() {
    for order in [1, 2] {
        let problem = v1::problem(unit_square(8, order), &[1, 2, 3, 4]);
        let disc = problem.discretise();
        let x = problem.solve_linear(&disc).unwrap();
        println!("V1 P{order}, the discrete solution:");
        assert_eq!(guarantee(&problem, &disc, &x, None), Outcome::Bound);
        for (name, y) in
            [("smooth", smooth_perturbation(&problem, &disc, &x, 0.1)), ("rough", rough_perturbation(&x, 0.1, 7))]
        {
            println!("V1 P{order}, {name} perturbation of 1e-1:");
            assert_eq!(guarantee(&problem, &disc, &y, None), Outcome::Refused, "P{order} {name}");
        }
    }
}

/// Source: as [`perturbed_discrete_solution_is_refused_or_bounded`]; docs/method.md §1.5
/// (a damped step leaves (1 − t) F(x_{k−1}) of the linearised equation).
/// Goal: on Γ_C, a damped Newton iterate x_{k−1} + ½Δ and perturbed converged iterates are
/// refused or bounded, never accepted below the reference; the full step x_{k−1} + Δ is
/// accepted with the bound.
/// Parameters: V3 (manufactured Signorini solution), structured n = 8, P1 and P2, θ = 0,
/// γ₀ = 100, δ = 10⁻³; x_{k−1} the converged solution at δ = 10⁻² (a real active-set change
/// remains); reference on the mesh refined twice.
#[test]
fn damped_and_perturbed_contact_iterates_are_refused_or_bounded() {
    for order in [1, 2] {
        let problem = v3::problem(unit_square(8, order));
        let disc = problem.discretise();
        let joint = ContactJoint::frictionless(vec![BOTTOM], crate::nitsche_parameters());
        let warm = Continuation { delta: 1e-2, delta_start: 0.1, newton: NewtonOptions::default(), path: None };
        let x0 = solve_by_continuation(&problem, &disc, &joint, &warm).unwrap().x;
        let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: DELTA });
        let (xs, _) = full_newton(&contact, x0.clone(), 1);
        let step: Vec<f64> = xs[1].iter().zip(&x0).map(|(a, b)| a - b).collect();
        let damped: Vec<f64> = x0.iter().zip(&step).map(|(a, d)| a + 0.5 * d).collect();
        println!("V3 P{order}, the full step:");
        assert_eq!(guarantee(&problem, &disc, &xs[1], Some((&joint, &x0))), Outcome::Bound);
        println!("V3 P{order}, the step damped by 1/2:");
        assert_eq!(guarantee(&problem, &disc, &damped, Some((&joint, &x0))), Outcome::Refused);
        for (name, y) in [
            ("smooth", smooth_perturbation(&problem, &disc, &xs[1], 0.1)),
            ("rough", rough_perturbation(&xs[1], 0.1, 11)),
        ] {
            println!("V3 P{order}, {name} perturbation of 1e-1 of the full step:");
            assert_eq!(guarantee(&problem, &disc, &y, Some((&joint, &x0))), Outcome::Refused, "P{order} {name}");
        }
    }
}

/// Source: docs/method.md §2 (the Riesz lower bound on nested spaces), issue "Estimator: … a
/// sharp reference".
/// Goal: the sharp reference starts from the space of the uniform reference refined
/// `sharp_start(p)` times (the same value), grows through nested spaces, ends with two values within 2 %, is at least the
/// uniform reference refined twice at a fraction of its unknowns, and lies below η_tot.
/// Parameters: Scene A (contact at the heel, singular at the Γ_D/Γ_C junction), P1 and P2, the
/// scene's mesh; uniform references refined `sharp_start(p)` times and twice.
#[test]
fn sharp_reference_beats_uniform_refinement_near_singularities() {
    for order in [1, 2] {
        let (problem, tags, run) = scene_with_contact("geo/scene_a.toml", order, 1.0);
        let joint = ContactJoint::frictionless(tags.clone(), run.nitsche.laws[0].parameters);
        let sharp = sharp_reference(&problem, &run.u, Some(&joint), 0.02, 4_000_000).unwrap();
        let uniform: Vec<_> = [sharp_start(order), 2]
            .iter()
            .map(|&l| residual_riesz(&problem, &run.u, Some(&joint), l).unwrap())
            .collect();
        let eta = evaluate(&problem, &run.u, run.state(), &tags, None).est.tot;
        println!(
            "Scene A P{order}: sharp {:?} on {:?} unknowns; uniform {:.4e} ({}), {:.4e} ({}); eta_tot {eta:.4e}, I_eff {:.3}",
            fmt(&sharp.norms),
            sharp.unknowns,
            uniform[0].norm,
            uniform[0].n_unknowns,
            uniform[1].norm,
            uniform[1].n_unknowns,
            eta / sharp.norm()
        );
        assert!(
            (sharp.norms[0] - uniform[0].norm).abs() <= 1e-10 * uniform[0].norm,
            "P{order}: not the same first space"
        );
        assert!(sharp.norms.windows(2).all(|w| w[1] >= w[0] * (1.0 - 1e-12)), "P{order}: not increasing");
        assert!(sharp.converged, "P{order}: {:?}", sharp.norms);
        assert!(sharp.norm() >= uniform[1].norm, "P{order}: below the uniform reference refined twice");
        assert!(sharp.unknowns.last().unwrap() < &uniform[1].n_unknowns, "P{order}: no cheaper than uniform");
        assert!(eta >= sharp.norm(), "P{order}: eta_tot {eta:e} below the reference {:e}", sharp.norm());
    }
}
