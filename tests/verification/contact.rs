//! Verification of Nitsche contact (docs/method.md §7, V2).

use crate::common;

use damfem::contact::nitsche::NitscheParameters;
use damfem::contact::projection::Smoothing;
use damfem::contact::{continuation, ContactJoint, ContactProblem};
use damfem::elasticity::{BodyForce, Dirichlet, Material, Problem};
use damfem::mesh::structured::{unit_square, BOTTOM, TOP};
use damfem::solve::{newton, NewtonOptions};
use std::sync::Arc;

/// V2 patch test. Source: docs/method.md §7 V2. Ω = (0,1)², E = 1, ν = 0, f = 0;
/// Γ_C = {y = 0}, Γ_D = {y = 1} with u = (0, top_uy), lateral sides traction-free.
/// Returns the largest nodal error against `exact` and the Newton steps.
fn patch_test(order: usize, theta: f64, top_uy: f64, exact: impl Fn([f64; 2]) -> f64) -> (f64, usize) {
    let mesh = unit_square(4, order);
    let material = Material { young: 1.0, poisson: 0.0, density: 0.0 };
    let problem = Problem {
        materials: vec![material; mesh.n_cells()],
        dirichlet: vec![Dirichlet { tag: TOP, fix: [true; 2], value: Arc::new(move |_| [0.0, top_uy]) }],
        neumann: vec![],
        body_force: BodyForce::None,
        mesh,
    };
    let disc = problem.discretise();
    let parameters = NitscheParameters { theta, ..crate::nitsche_parameters() };
    let joint = ContactJoint::frictionless(vec![BOTTOM], parameters);
    let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 1e-4 });
    let report = newton(&contact, vec![0.0; disc.dofs.n_free], &NewtonOptions::default()).expect("Newton converges");
    let u = problem.displacement(&disc, &report.x);
    let error =
        problem.mesh.points.iter().zip(&u).map(|(x, v)| v[0].abs().max((v[1] - exact(*x)).abs())).fold(0.0, f64::max);
    (error, report.iterations.len())
}

#[test]
fn v2_patch_test_full_contact_is_exact() {
    for order in [1, 2] {
        for theta in [1.0, 0.0, -1.0] {
            let (error, steps) = patch_test(order, theta, -1e-2, |x| -1e-2 * x[1]);
            println!("P{order} θ = {theta}: max nodal error {error:.2e} after {steps} Newton steps");
            assert!(error < 1e-12, "P{order} θ = {theta}: error {error}");
        }
    }
}

#[test]
fn v2_lift_off_is_a_rigid_translation() {
    for order in [1, 2] {
        for theta in [1.0, 0.0, -1.0] {
            // u = (0, d): no stress, so no contact pressure
            let (error, _) = patch_test(order, theta, 1e-2, |_| 1e-2);
            assert!(error < 1e-12, "P{order} θ = {theta}: error {error}");
        }
    }
}

/// (h, H¹ error, contact length, Newton steps) of V3 on an n × n mesh of degree p.
fn solve_v3(n: usize, order: usize) -> (f64, f64, f64, usize) {
    use damfem::fem::norms::errors;
    use damfem::verify::v3;
    let problem = v3::problem(unit_square(n, order));
    let disc = problem.discretise();
    let joint = ContactJoint::frictionless(vec![BOTTOM], crate::nitsche_parameters());
    let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 1e-10 });
    let x0 = vec![0.0; disc.dofs.n_free];
    let (x, stages) =
        continuation(&mut contact, 1e-10, 0.1, x0, &NewtonOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let steps = stages.iter().map(|s| s.report.iterations.len()).sum();
    let u = problem.displacement(&disc, &x);
    let (_, h1) = errors(&problem.mesh, &u, v3::u, v3::grad_u);
    let contact_length = contact.face_states(&x).iter().map(|s| s.contact_length).sum();
    (1.0 / n as f64, h1, contact_length, steps)
}

#[test]
fn v3_signorini_rates_and_contact_zone() {
    for (order, sizes, min_rate) in [(1, [8, 16, 32, 64], 0.9), (2, [4, 8, 16, 32], 1.4)] {
        let runs: Vec<_> = sizes.iter().map(|&n| solve_v3(n, order)).collect();
        let h: Vec<f64> = runs.iter().map(|r| r.0).collect();
        let e: Vec<f64> = runs.iter().map(|r| r.1).collect();
        let rate = common::fitted_rate(&h, &e);
        for r in &runs {
            println!(
                "P{order} h = {:.4}: |e|_H1 = {:.3e}, contact zone [0, {:.4}], {} Newton steps",
                r.0, r.1, r.2, r.3
            );
            // P2 locates the point within one cell; for P1 the O(h²) error of u_h^n hides the
            // quartic separation gap ψ = (x − ½)⁴ over a zone of width ~ h^{1/2}
            let tolerance = if order == 2 { r.0 } else { r.0.sqrt() };
            assert!((r.2 - 0.5).abs() <= tolerance, "contact–separation point {} not within {tolerance} of 1/2", r.2);
        }
        println!("P{order}: fitted H1 rate {rate:.3}");
        assert!(rate >= min_rate, "P{order} H1 rate {rate} < {min_rate}");
    }
}
