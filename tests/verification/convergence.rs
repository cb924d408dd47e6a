//! V1 (theory §7): manufactured solution of linear elasticity on the unit square.
//!
//! Source: the manufactured field of the project's docs/method.md §7 (V1), μ = λ = 1,
//!   u = (sin πx cos πy + x²/(2λ), −cos πx sin πy + y²/(2λ)),
//!   f = −∇·σ(u) = (2μπ² sin πx cos πy − 2μ/λ − 1, −2μπ² cos πx sin πy − 2μ/λ − 1).
//! Boundary conditions: u = exact on all of ∂Ω (nodal interpolation).
//! Goal: fitted rates |u − u_h|_{H¹} ~ h^p and ‖u − u_h‖_{L²} ~ h^{p+1} within ±0.1.

use crate::common;

use damfem::fem::norms::errors;
use damfem::mesh::structured::unit_square;
use damfem::solve::Cholesky;
use damfem::verify::v1;

/// (h, L² error, H¹ error) of V1 on an n × n mesh of degree p.
fn solve_v1(n: usize, p: usize) -> (f64, f64, f64) {
    let problem = v1::problem(unit_square(n, p), &[1, 2, 3, 4]);
    let disc = problem.discretise();
    let system = problem.assemble(&disc);
    let x = Cholesky::analyse(&disc.pattern).unwrap().solve(&disc.pattern, &system.values, &system.rhs).unwrap();
    let u = problem.displacement(&disc, &x);
    let (l2, h1) = errors(&problem.mesh, &u, v1::exact, v1::exact_gradient);
    (1.0 / n as f64, l2, h1)
}

fn assert_rates(p: usize, sizes: &[usize]) {
    let runs: Vec<_> = sizes.iter().map(|&n| solve_v1(n, p)).collect();
    let h: Vec<f64> = runs.iter().map(|r| r.0).collect();
    let l2: Vec<f64> = runs.iter().map(|r| r.1).collect();
    let h1: Vec<f64> = runs.iter().map(|r| r.2).collect();
    let (rate_l2, rate_h1) = (common::fitted_rate(&h, &l2), common::fitted_rate(&h, &h1));
    println!("P{p}: L2 errors {l2:?} rate {rate_l2:.3}; H1 errors {h1:?} rate {rate_h1:.3}");
    assert!((rate_h1 - p as f64).abs() <= 0.1, "P{p} H1 rate {rate_h1}");
    assert!((rate_l2 - (p + 1) as f64).abs() <= 0.1, "P{p} L2 rate {rate_l2}");
}

#[test]
fn v1_p1_rates() {
    assert_rates(1, &[8, 16, 32, 64]);
}

#[test]
fn v1_p2_rates() {
    assert_rates(2, &[4, 8, 16, 32]);
}
