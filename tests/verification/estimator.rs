//! Verification of the equilibrated-stress estimator (docs/method.md §4–§5).

use crate::common;

use damfem::contact::{solve_by_continuation, ContactJoint, ContactSolution, Continuation, Linearisation};
use damfem::elasticity::{Displacement, Problem};
use damfem::estimate::checks::check;
use damfem::estimate::estimators::estimate;
use damfem::estimate::reconstruction::reconstruct;
use damfem::estimate::reference::{sharp_reference, REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS};
use damfem::mesh::structured::unit_square;
use damfem::mesh::structured::BOTTOM;
use damfem::solve::Cholesky;
use damfem::solve::NewtonOptions;
use damfem::verify::{v1, v3};

/// The sharp reference of ‖R(u_h)‖ (the one of `damfem solve --effectivity`), converged.
fn reference(problem: &Problem, u: &[[f64; 2]], joint: Option<&ContactJoint>) -> f64 {
    let r = sharp_reference(problem, u, joint, REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(r.converged, "the reference did not converge: {:?}", r.norms);
    r.norm()
}

/// Solves a linear problem and returns the nodal displacement.
fn solve(problem: &Problem) -> Vec<[f64; 2]> {
    let disc = problem.discretise();
    let system = problem.assemble(&disc);
    let x = Cholesky::analyse(&disc.pattern).unwrap().solve(&disc.pattern, &system.values, &system.rhs).unwrap();
    problem.displacement(&disc, &x)
}

/// V1 (source: docs/method.md §7), μ = λ = 1, Dirichlet everywhere, p = 1, 2, four
/// structured meshes. Goal: equilibration to round-off, η ≥ ‖R(u_h)‖ (the sharp reference,
/// converged to 2 %), I_eff ≤ 2, η at the rate of the error.
#[test]
fn v1_equilibration_and_guaranteed_bound() {
    for (order, sizes) in [(1, [4, 8, 16, 32]), (2, [2, 4, 8, 16])] {
        let (mut h, mut eta) = (Vec::new(), Vec::new());
        for n in sizes {
            let problem = v1::problem(unit_square(n, order), &[1, 2, 3, 4]);
            let u = solve(&problem);
            let nodal = Displacement::from(u.clone());
            let topology = damfem::mesh::Topology::new(&problem.mesh);
            let rec = reconstruct(&problem, &topology, &nodal, None).unwrap();
            let eq = check(&problem, &topology, &nodal, &rec, None);
            let est = estimate(&problem, &topology, &nodal, &rec, None).global();
            let dual = reference(&problem, &u, None);
            println!(
                "P{order} n = {n}: eta = {:.4e} (osc {:.2e}, flux {:.2e}), dual norm >= {dual:.4e}, I_eff <= {:.3}; checks {eq:?}",
                est.tot, est.osc, est.flux, est.tot / dual
            );
            assert!(eq.worst(order) < 1e-10, "P{order} n = {n}: {eq:?}");
            assert!(est.tot >= dual, "P{order} n = {n}: bound violated, eta {} < {dual}", est.tot);
            assert!(est.tot / dual <= 2.0, "P{order} n = {n}: effectivity {}", est.tot / dual);
            h.push(1.0 / n as f64);
            eta.push(est.tot);
        }
        let rate = common::fitted_rate(&h, &eta);
        println!("P{order}: eta rate {rate:.3}");
        assert!((rate - order as f64).abs() < 0.2, "P{order}: eta rate {rate}");
    }
}

/// The converged contact solution of `problem` with contact on `joint` at δ: the nodal
/// displacement and the contact solution.
fn solve_with_contact(problem: &Problem, joint: &ContactJoint, delta: f64) -> (Vec<[f64; 2]>, ContactSolution) {
    let disc = problem.discretise();
    let settings = Continuation { delta, delta_start: 0.1, newton: NewtonOptions::default(), path: None };
    let solution = solve_by_continuation(problem, &disc, joint, &settings).unwrap();
    (problem.displacement(&disc, &solution.x), solution)
}

/// V3 (source: docs/method.md §7), the manufactured Signorini solution, θ = 0, γ₀ = 100,
/// δ = 10⁻⁸, p = 1, 2, four structured meshes. Goal: equilibration to round-off including
/// the three Γ_C traces, η ≥ ‖R(u_h)‖ (the sharp reference, converged to 2 %, exact
/// projection), I_eff ≤ 2 and η at the optimal rate.
#[test]
fn v3_contact_equilibration_and_guaranteed_bound() {
    for (order, sizes) in [(1, [4, 8, 16, 32]), (2, [4, 8, 16, 32])] {
        let (mut h, mut eta) = (Vec::new(), Vec::new());
        for n in sizes {
            let problem = v3::problem(unit_square(n, order));
            let delta = 1e-8;
            let joint = ContactJoint::frictionless(vec![BOTTOM], crate::nitsche_parameters());
            let (u, solution) = solve_with_contact(&problem, &joint, delta);
            let topology = damfem::mesh::Topology::new(&problem.mesh);
            let state = Linearisation {
                nitsche: &solution.nitsche,
                smoothing: solution.smoothing,
                u_prev: problem.displacement(&problem.discretise(), &solution.x_prev),
            };
            let nodal = Displacement::from(u.clone());
            let rec = reconstruct(&problem, &topology, &nodal, Some(&state)).unwrap();
            let eq = check(&problem, &topology, &nodal, &rec, Some(&state));
            let est = estimate(&problem, &topology, &nodal, &rec, Some(&state)).global();
            let dual = reference(&problem, &u, Some(&joint));
            println!(
                "P{order} n = {n}: eta = {:.4e} (flux {:.2e}, Neu {:.2e}, disc {:.2e}, reg {:.2e}, lin {:.2e}), dual norm >= {dual:.4e}, I_eff <= {:.3}; worst check {:.1e}",
                est.tot, est.flux, est.neu, est.disc, est.reg, est.lin, est.tot / dual, eq.worst(order)
            );
            assert!(eq.worst(order) < 1e-10, "P{order} n = {n}: {eq:?}");
            assert!(est.tot >= dual, "P{order} n = {n}: bound violated, eta {} < {dual}", est.tot);
            assert!(est.tot / dual <= 2.0, "P{order} n = {n}: effectivity {}", est.tot / dual);
            h.push(1.0 / n as f64);
            eta.push(est.tot);
        }
        let rate = common::fitted_rate(&h, &eta);
        println!("P{order}: eta rate {rate:.3}");
        assert!((rate - order as f64).abs() < 0.2, "P{order}: eta rate {rate}");
    }
}
