//! The guaranteed bound on un-converged Newton iterates, with η_lin following the
//! linearisation error.

use super::support::*;

use damfem::contact::projection::Smoothing;
use damfem::contact::{solve_by_continuation, ContactJoint, ContactProblem, Continuation};
use damfem::mesh::structured::{unit_square, BOTTOM};
use damfem::solve::NewtonOptions;
use damfem::verify::v3;

/// One row of the Newton table: the estimator of the iterate x_k against x_{k−1}.
struct NewtonRow {
    residual: f64,
    eval: Evaluation,
}

/// V3 (n = 8, degree `order`), θ = 0, γ₀ = 100: full Newton steps at δ from `x0` (zero, or
/// the converged solution at `warm_delta`), until ‖F‖ ≤ 10⁻¹² ‖b‖ or `max_steps`; every
/// iterate evaluated with the linearisation point u_prev = x_{k−1} and the dual norm (levels 1).
fn v3_newton_rows(order: usize, delta: f64, warm_delta: Option<f64>, max_steps: usize) -> Vec<NewtonRow> {
    let problem = v3::problem(unit_square(8, order));
    let disc = problem.discretise();
    let parameters = crate::nitsche_parameters();
    let joint = ContactJoint::frictionless(vec![BOTTOM], parameters);
    let x0 = match warm_delta {
        None => vec![0.0; disc.dofs.n_free],
        Some(d) => {
            let settings = Continuation { delta: d, delta_start: 0.1, newton: NewtonOptions::default(), path: None };
            solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("{e}")).x
        }
    };
    let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta });
    let nitsche = &contact.nitsche;
    let (xs, residuals) = full_newton(&contact, x0, max_steps);
    let last = residuals.iter().position(|&r| r <= 1e-12).unwrap_or(max_steps).max(1);
    let start = if warm_delta.is_some() { "warm start" } else { "x_0 = 0" };
    println!("V3 P{order}, delta = {delta:.0e}, {start}: |F(x_k)|/|b| = {:?}", fmt(&residuals));
    println!("  k  |F|/|b|   eta_tot     dual        I_eff  eta_flux   eta_disc   eta_reg    eta_lin    lin_k/lin_(k-1)^2  worst check");
    let mut rows: Vec<NewtonRow> = Vec::new();
    for k in 1..=last {
        let u = problem.displacement(&disc, &xs[k]);
        let u_prev = problem.displacement(&disc, &xs[k - 1]);
        let eval = evaluate(&problem, &u, Some((nitsche, delta, &u_prev)), &[BOTTOM], Some(1));
        let ratio = rows.last().map_or(f64::NAN, |r| eval.est.lin / r.eval.est.lin.powi(2));
        println!(
            " {k:2}  {:.2e}  {:.4e}  {:.4e}  {:5.3}  {:.3e}  {:.3e}  {:.3e}  {:.3e}  {ratio:9.3e}          {:.1e}",
            residuals[k],
            eval.est.tot,
            eval.dual.unwrap(),
            eval.est.tot / eval.dual.unwrap(),
            eval.est.flux,
            eval.est.disc,
            eval.est.reg,
            eval.est.lin,
            eval.eq.worst(order)
        );
        rows.push(NewtonRow { residual: residuals[k], eval });
    }
    rows
}

/// Equilibration to round-off and η_tot ≥ dual norm on every row.
fn assert_bound_on_every_iterate(order: usize, rows: &[NewtonRow]) {
    for (k, row) in rows.iter().enumerate().map(|(i, r)| (i + 1, r)) {
        let (eq, tot, dual) = (&row.eval.eq, row.eval.est.tot, row.eval.dual.unwrap());
        assert!(eq.worst(order) < 1e-10, "P{order} k = {k} (|F|/|b| = {:.2e}): {eq:?}", row.residual);
        assert!(tot >= dual, "P{order} k = {k}: bound violated, eta {tot} < dual {dual}");
    }
}

/// η_lin decreases at every step and by several orders overall, and quadratically: the
/// ratios η_lin,k+1 / η_lin,k² of the steps above round-off (η_lin > 10⁻¹³ η_tot) stay below
/// 10/δ (|t₃| ≤ |P_γ(u^k) − P_γ(u^{k−1})|²/(4δ), the derivative of [·]_{reg,δ} being
/// 1/(2δ)-Lipschitz). A linear rate ρ would give ratios ρ/η_lin,k, growing without bound.
fn assert_quadratic_linearisation_error(order: usize, delta: f64, rows: &[NewtonRow]) {
    let lin: Vec<f64> = rows.iter().map(|r| r.eval.est.lin).collect();
    for k in 1..lin.len() {
        assert!(lin[k] < lin[k - 1], "P{order}: eta_lin rose at step {}: {lin:?}", k + 1);
    }
    let drop = lin[0] / lin[lin.len() - 1];
    let above: Vec<f64> =
        rows.iter().filter(|r| r.eval.est.lin > 1e-13 * r.eval.est.tot).map(|r| r.eval.est.lin).collect();
    let ratios: Vec<f64> = above.windows(2).map(|w| w[1] / (w[0] * w[0])).collect();
    println!(
        "P{order}: eta_lin dropped by {drop:.2e} over {} steps; ratios above round-off {:?}",
        lin.len(),
        fmt(&ratios)
    );
    assert!(drop > 1e4, "P{order}: eta_lin dropped only by {drop:.2e}: {lin:?}");
    assert!(!ratios.is_empty(), "P{order}: fewer than two steps above round-off: {lin:?}");
    for r in &ratios {
        assert!(*r < 10.0 / delta, "P{order}: eta_lin,k+1 / eta_lin,k^2 = {r:.3e} >= 10/delta: {lin:?}");
    }
}

/// Source: docs/method.md §1.5 and §4 (σ_h3 carries the linearisation defect t₃ of the
/// iterate u^k against u^{k−1}); Ern & Vohralík (2013) for the inexact-Newton splitting.
/// Goal: the bound η_tot ≥ ‖R(u^k)‖ and equilibration to round-off hold for every Newton
/// iterate, not only the converged one; η_lin decreases along the iterations, quadratically
/// once the contact zone has settled.
/// Parameters: V3 (manufactured Signorini solution), structured n = 8, P2, θ = 0, γ₀ = 100,
/// δ = 10⁻³ (stress scale ~1); full Newton steps (no damping, so u^k solves the linearised
/// equation at u^{k−1} to round-off): (a) k = 1, 2, 3 from x_0 = 0, (b) from the converged
/// solution at δ = 10⁻² (one continuation stage) until ‖F‖ ≤ 10⁻¹² ‖b‖; dual norm on the mesh
/// refined once.
#[test]
fn unconverged_newton_iterates_p2() {
    let rows = v3_newton_rows(2, 1e-3, None, 3);
    assert_bound_on_every_iterate(2, &rows);
    let rows = v3_newton_rows(2, 1e-3, Some(1e-2), 10);
    assert_bound_on_every_iterate(2, &rows);
    assert_quadratic_linearisation_error(2, 1e-3, &rows);
}

/// As [`unconverged_newton_iterates_p2`] (b), at P1: warm-started from δ = 10⁻², P_γ(u^k) and
/// P_γ(u^{k−1}) stay above δ on the contact face at the corner (1, 0), so t₃ = 0 there and
/// every check holds (compare [`unconverged_newton_iterates_p1_from_zero`]).
#[test]
fn unconverged_newton_iterates_p1_warm_start() {
    let rows = v3_newton_rows(1, 1e-3, Some(1e-2), 10);
    assert_bound_on_every_iterate(1, &rows);
    assert_quadratic_linearisation_error(1, 1e-3, &rows);
}

/// As [`unconverged_newton_iterates_p2`] (a), at P1: k = 1, 2, 3 from x_0 = 0.
#[test]
fn unconverged_newton_iterates_p1_from_zero() {
    let rows = v3_newton_rows(1, 1e-3, None, 3);
    assert_bound_on_every_iterate(1, &rows);
}
