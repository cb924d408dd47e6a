//! Component-wise verification of the equilibrated-stress estimator (docs/method.md §2–§5):
//! the guaranteed bound for un-converged Newton iterates, η_reg = O(δ), the terms that must
//! vanish exactly, checks that do fail on a tampered reconstruction, and equilibration on
//! gmsh meshes of the scenes.
//!
//! Notation: η_* are the global estimators (Σ_T η_T²)^{1/2} of damfem::estimate::estimators,
//! "dual" is the Riesz lower bound ‖r‖_{C,h} ≤ ‖R(u_h)‖ of damfem::estimate::dual_norm on the
//! coarse mesh refined once (P2), "worst" the largest relative equilibration violation of
//! damfem::estimate::checks.

mod common;

use common::{v1, v3};
use damfem::contact::nitsche::{Nitsche, NitscheParameters};
use damfem::contact::projection::Smoothing;
use damfem::contact::{solve_by_continuation, ContactJoint, ContactProblem, Continuation, Linearisation};
use damfem::elasticity::{BodyForce, Discretisation, Material, Neumann, Problem, Traction};
use damfem::estimate::afw::COMPONENTS;
use damfem::estimate::checks::{check, Equilibration};
use damfem::estimate::dual_norm::residual_dual_norm;
use damfem::estimate::estimators::{estimate, GlobalEstimators};
use damfem::estimate::reconstruction::{reconstruct, Reconstruction};
use damfem::io::gmsh::{mesh_geo, MeshOptions};
use damfem::mesh::structured::{rectangle, unit_square, BOTTOM, LEFT, RIGHT, TOP};
use damfem::mesh::{Mesh, Topology};
use damfem::scene::Scene;
use damfem::solve::{Cholesky, NewtonOptions, NonlinearSystem, SparseLu};
use std::path::{Path, PathBuf};
use std::sync::Arc;

// ---------------------------------------------------------------------------------------
// helpers
// ---------------------------------------------------------------------------------------

fn manifest(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// Solves a linear problem (no contact) and returns the nodal displacement.
fn solve_linear(problem: &Problem) -> Vec<[f64; 2]> {
    let disc = problem.discretise();
    let system = problem.assemble(&disc);
    let x = Cholesky::analyse(&disc.pattern).unwrap().solve(&disc.pattern, &system.values, &system.rhs).unwrap();
    problem.displacement(&disc, &x)
}

/// A converged contact solution and what the reconstruction needs.
struct ContactRun {
    u: Vec<[f64; 2]>,
    /// The iterate before the last Newton step of the last stage.
    u_prev: Vec<[f64; 2]>,
    nitsche: Nitsche,
    delta: f64,
    newton_steps: usize,
    contact_length: f64,
}

/// Solves along the δ path of `settings` (as tests/estimator.rs does).
fn solve_with_contact(
    problem: &Problem,
    disc: &Discretisation,
    joint: &ContactJoint,
    settings: &Continuation,
) -> ContactRun {
    let solution = solve_by_continuation(problem, disc, joint, settings).unwrap_or_else(|e| panic!("{e}"));
    let last = &solution.stages.last().unwrap().report;
    ContactRun {
        u: problem.displacement(disc, &last.x),
        u_prev: problem.displacement(disc, &last.x_prev),
        nitsche: solution.nitsche.clone(),
        delta: settings.delta,
        newton_steps: solution.stages.iter().map(|s| s.report.iterations.len()).sum(),
        contact_length: solution.contact_length(),
    }
}

impl ContactRun {
    fn state(&self) -> Option<(&Nitsche, f64, &[[f64; 2]])> {
        Some((&self.nitsche, self.delta, &self.u_prev))
    }
}

/// Equilibration checks, global estimators and (if asked) the dual norm of one iterate.
struct Evaluation {
    eq: Equilibration,
    est: GlobalEstimators,
    dual: Option<f64>,
}

/// Reconstructs σ_h for the iterate `u` (with `contact` = (faces, δ, u_prev) on Γ_C = `tags`),
/// checks it, computes the estimators and, if `levels` is given, the dual norm on the mesh
/// refined `levels` times.
fn evaluate(
    problem: &Problem,
    u: &[[f64; 2]],
    contact: Option<(&Nitsche, f64, &[[f64; 2]])>,
    tags: &[i32],
    levels: Option<usize>,
) -> Evaluation {
    let topology = Topology::new(&problem.mesh);
    let state = contact.map(|(nitsche, delta, u_prev)| Linearisation {
        nitsche,
        smoothing: Smoothing { delta },
        u_prev: u_prev.to_vec(),
    });
    let rec = reconstruct(problem, &topology, u, state.as_ref()).unwrap_or_else(|e| panic!("{e}"));
    let eq = check(problem, &topology, u, &rec, state.as_ref());
    let est = estimate(problem, &topology, u, &rec, state.as_ref()).global();
    let dual = levels.map(|levels| {
        let data = contact.map(|(nitsche, _, _)| ContactJoint::frictionless(tags.to_vec(), nitsche.parameters));
        residual_dual_norm(problem, u, data.as_ref(), levels).unwrap_or_else(|e| panic!("{e}"))
    });
    Evaluation { eq, est, dual }
}

fn components(e: &GlobalEstimators) -> String {
    format!(
        "osc {:.3e}  flux {:.3e}  Neu {:.3e}  disc {:.3e}  reg {:.3e}  lin {:.3e}  tot {:.4e}",
        e.osc, e.flux, e.neu, e.disc, e.reg, e.lin, e.tot
    )
}

/// Full Newton steps (no damping, one step of iterative refinement per linear solve) from
/// x0: the iterates x_0, …, x_steps and the relative residuals ‖F(x_k)‖/‖b‖.
fn full_newton(contact: &ContactProblem, x0: Vec<f64>, steps: usize) -> (Vec<Vec<f64>>, Vec<f64>) {
    let pattern = contact.pattern();
    let lu = SparseLu::analyse(pattern).unwrap();
    let (n, scale) = (pattern.n(), contact.scale());
    let (mut r, mut jac, mut product) = (vec![0.0; n], vec![0.0; pattern.nnz()], vec![0.0; n]);
    let mut xs = vec![x0];
    let mut residuals = Vec::new();
    for _ in 0..=steps {
        let x = xs.last().unwrap().clone();
        contact.evaluate(&x, &mut r, Some(&mut jac));
        residuals.push(r.iter().map(|v| v * v).sum::<f64>().sqrt() / scale);
        if xs.len() > steps {
            break;
        }
        let factors = lu.factor(pattern, &jac).unwrap();
        let minus_r: Vec<f64> = r.iter().map(|v| -v).collect();
        let mut d = factors.solve(&minus_r);
        pattern.multiply(&jac, &d, &mut product);
        let defect: Vec<f64> = minus_r.iter().zip(&product).map(|(b, a)| b - a).collect();
        for (di, c) in d.iter_mut().zip(factors.solve(&defect)) {
            *di += c;
        }
        xs.push(x.iter().zip(&d).map(|(a, b)| a + b).collect());
    }
    (xs, residuals)
}

/// A small deterministic pseudo-random generator (xorshift64*), values in [−1, 1].
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (v >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// A scene file loaded and meshed by gmsh at degree `order`, the mesh sizes multiplied by
/// `size_factor` on top of the scene's own factor.
fn scene_mesh(file: &str, order: usize, size_factor: f64) -> (Scene, Mesh) {
    let scene = Scene::load(&manifest(file)).unwrap_or_else(|e| panic!("{e}"));
    let m = &scene.mesh;
    let options = MeshOptions {
        order,
        size_factor: size_factor * m.size_factor,
        size_min: m.size_min,
        size_max: m.size_max,
        algorithm: m.algorithm,
    };
    let mesh = mesh_geo(&scene.geometry, &options, false, false).unwrap_or_else(|e| panic!("{file}: {e}"));
    (scene, mesh)
}

/// Solves a scene with contact (CLI settings): the problem, its contact tags and the run.
fn scene_with_contact(file: &str, order: usize, size_factor: f64) -> (Problem, Vec<i32>, ContactRun) {
    let (scene, mesh) = scene_mesh(file, order, size_factor);
    let (problem, joint) = scene.problem(mesh).unwrap_or_else(|e| panic!("{e}"));
    let joint = joint.unwrap_or_else(|| panic!("{file} has a contact curve"));
    let disc = problem.discretise();
    let settings = scene.continuation(&problem, &disc.topology);
    assert_eq!(joint.parameters.theta, 0.0, "{file}: the estimator needs theta = 0");
    let run = solve_with_contact(&problem, &disc, &joint, &settings);
    (problem, joint.tags, run)
}

// ---------------------------------------------------------------------------------------
// 1. un-converged Newton iterates
// ---------------------------------------------------------------------------------------

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
    let parameters = NitscheParameters::default();
    let joint = ContactJoint::frictionless(vec![BOTTOM], parameters);
    let x0 = match warm_delta {
        None => vec![0.0; disc.dofs.n_free],
        Some(d) => {
            let settings = Continuation { delta: d, delta_start: 0.1, newton: NewtonOptions::default() };
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

fn fmt(v: &[f64]) -> Vec<String> {
    v.iter().map(|r| format!("{r:.2e}")).collect()
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
/// Fails in src/estimate/patch.rs: the contact check (σ_hi n = Π_F^p t_i n, i = 1, 2, 3)
/// reaches 1.2·10⁻⁴ (k = 1), 2.3·10⁻⁴ (k = 2), 3.9·10⁻⁶ (k = 3), all on the face
/// (0.875, 1) × {0}, where σ_h1 and σ_h3 miss their traces by equal and opposite amounts (σ_h is
/// right). At p = 1 the patch of the corner (1, 0) is one cell; Π⁰ of the rigid motions spans
/// only the translations, so the rotation about the centroid stays free (deficiency 1) and is
/// handled by the pseudo-inverse. The p = 1 rotation correction makes case 0 (σ_h) compatible,
/// but the linearisation case gets none: its data ψ_a t₃ n is compatible only if
/// ∫_F ψ_a t₃ (x − x_centroid) = 0, which holds for constant t₃ on this cell but not here
/// (P_γ(u^k) = −0.56 … 2.17 along the face at k = 1, P_γ(u^0) = 0), so its Γ_C trace misses
/// ψ_a t₃ n. The regularisation case (σ_h2) takes the same code path. Possible fix: apply the rotation
/// correction (or a per-case compatibility projection) to every case, not just case 0.
#[test]
fn unconverged_newton_iterates_p1_from_zero() {
    let rows = v3_newton_rows(1, 1e-3, None, 3);
    assert_bound_on_every_iterate(1, &rows);
}

// ---------------------------------------------------------------------------------------
// 2. η_reg = O(δ)
// ---------------------------------------------------------------------------------------

/// Source: geo/scene_a.toml, geo/hertz.toml (docs/method.md §6), solved as the CLI does
/// (src/cli/solve.rs: δ = 10⁻⁴ S with S = problem.stress_scale, γ₀ = 100, θ = 0, one stage).
/// Goal: every equilibration check below 10⁻¹⁰ (relative) on unstructured gmsh meshes with
/// contact, hydrostatic loads and self-weight; the estimator components are reported, and
/// η_tot ≥ dual norm (mesh refined once) is asserted as well.
/// Parameters: Scene A at P1 and P2, Hertz at P2, mesh sizes × 2 (size_factor 2) for speed.
#[test]
fn scenes_with_contact_equilibrate() {
    for (file, order) in [("geo/scene_a.toml", 1), ("geo/scene_a.toml", 2), ("geo/hertz.toml", 2)] {
        let clock = std::time::Instant::now();
        let (problem, tags, run) = scene_with_contact(file, order, 2.0);
        let e = evaluate(&problem, &run.u, run.state(), &tags, Some(1));
        let dual = e.dual.unwrap();
        println!(
            "{file} P{order}: {} cells, delta = {:.3e}, {} Newton steps, contact length {:.4}; {}; dual {dual:.4e}, I_eff {:.3}; worst check {:.1e} ({:.2} s)",
            problem.mesh.n_cells(),
            run.delta,
            run.newton_steps,
            run.contact_length,
            components(&e.est),
            e.est.tot / dual,
            e.eq.worst(order),
            clock.elapsed().as_secs_f64()
        );
        println!("    {:?}", e.eq);
        assert!(e.eq.worst(order) < 1e-10, "{file} P{order}: {:?}", e.eq);
        assert!(e.est.tot >= dual, "{file} P{order}: bound violated, eta {} < dual {dual}", e.est.tot);
    }
}

/// Source: geo/scene_b.toml (docs/method.md §6): the dam bonded to a rock block, two
/// materials, the rock clamped at the bottom and on rollers (u_x = 0) on its sides, hydrostatic
/// water on the upstream face and the reservoir floor, self-weight; no contact (a linear solve).
/// Goal: every equilibration check below 10⁻¹⁰ with rollers and a material interface.
/// Parameters: P1 and P2, mesh sizes × 2.
#[test]
fn scene_b_equilibrates() {
    for order in [1, 2] {
        let clock = std::time::Instant::now();
        let (scene, mesh) = scene_mesh("geo/scene_b.toml", order, 2.0);
        let (problem, _) = scene.problem(mesh).unwrap_or_else(|e| panic!("{e}"));
        assert!(problem.dirichlet.iter().any(|bc| bc.fix == [true, false]), "scene B has rollers");
        let u = solve_linear(&problem);
        let e = evaluate(&problem, &u, None, &[], None);
        println!(
            "scene B P{order}: {} cells; {}; worst check {:.1e} ({:.2} s)",
            problem.mesh.n_cells(),
            components(&e.est),
            e.eq.worst(order),
            clock.elapsed().as_secs_f64()
        );
        println!("    {:?}", e.eq);
        assert!(e.eq.worst(order) < 1e-10, "scene B P{order}: {:?}", e.eq);
    }
}

// ---------------------------------------------------------------------------------------
// 3. terms that vanish exactly
// ---------------------------------------------------------------------------------------

/// |Ω| and the largest cell diameter.
fn area_and_size(mesh: &Mesh) -> (f64, f64) {
    let area = (0..mesh.n_cells()).map(|c| mesh.cell_area(c).abs()).sum();
    let h = (0..mesh.n_cells()).map(|c| mesh.cell_diameter(c)).fold(0.0, f64::max);
    (area, h)
}

/// √h_max · ‖g‖_{L²(Γ_N)} sampled at the facet midpoints: the scale of η_Neu.
fn neumann_scale(problem: &Problem) -> f64 {
    let (mesh, topology) = (&problem.mesh, Topology::new(&problem.mesh));
    let (_, h) = area_and_size(mesh);
    let mut sum = 0.0;
    for bc in &problem.neumann {
        for f in (0..mesh.n_facets()).filter(|&f| mesh.facet_tags[f] == bc.tag) {
            let n = mesh.facet(f);
            let (a, b) = (mesh.points[n[0]], mesh.points[n[1]]);
            let g = bc.traction.at([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])], topology.outward_normal(mesh, f));
            sum += (g[0] * g[0] + g[1] * g[1]) * mesh.facet_length(f);
        }
    }
    h.sqrt() * sum.sqrt()
}

/// Source: docs/method.md §5 and src/estimate/estimators.rs: η_osc,T = (h_T/π)‖f − Π^{p−1}f‖_T
/// vanishes for piecewise constant f, η_Neu for tractions that are polynomials of degree ≤ p
/// on every face (hydrostatic pressure below the water level, constant tractions).
/// Goal: (a) η_osc = η_Neu = 0 exactly on Scene A (self-weight, flood level 70 m above the
/// 50 m crest, so every facet of the upstream face is below water), P1 and P2; (b) the same
/// data given as general fields (BodyForce::Field, Traction::Field), which the estimator does
/// integrate, give round-off only (relative to (h/π)‖f‖_Ω and h^{1/2}‖g_N‖_{Γ_N}); (c) a water
/// level inside the upstream face (30.3 m) gives η_Neu > 0 (the pressure has a kink in one
/// facet). Equilibration < 10⁻¹⁰ is asserted for (a) and (b); for (c) it fails, see
/// [`kinked_hydrostatic_load_equilibrates`].
/// Parameters: geo/scene_a.toml, mesh sizes × 2, CLI contact settings.
#[test]
fn zero_oscillation_and_neumann_terms_on_scene_a() {
    for order in [1, 2] {
        let (problem, tags, run) = scene_with_contact("geo/scene_a.toml", order, 2.0);
        let e = evaluate(&problem, &run.u, run.state(), &tags, None);
        println!("scene A P{order} (gravity, hydrostatic level 70): {}", components(&e.est));
        assert_eq!(e.est.osc, 0.0, "P{order}: eta_osc with self-weight");
        assert_eq!(e.est.neu, 0.0, "P{order}: eta_Neu with the whole upstream face under water");
        assert!(e.eq.worst(order) < 1e-10, "P{order}: {:?}", e.eq);

        // the same data as general fields
        let BodyForce::Gravity(g) = problem.body_force else { panic!("scene A has self-weight") };
        let weight = problem.materials[0].density * g;
        assert!(problem.materials.iter().all(|m| m.density * g == weight), "one material");
        let mut fields = problem.clone();
        fields.body_force = BodyForce::Field(Arc::new(move |_| [0.0, -weight]));
        let mut levels = Vec::new();
        for bc in &mut fields.neumann {
            let Traction::Hydrostatic { density, gravity, level } = bc.traction else { continue };
            levels.push(level);
            // the upstream face is x = 0 with outward normal (−1, 0): g_N = −p n = (p, 0)
            bc.traction = Traction::Field(Arc::new(move |x| [density * gravity * (level - x[1]).max(0.0), 0.0]));
        }
        assert_eq!(levels, [70.0], "scene A: one hydrostatic curve");
        let f = evaluate(&fields, &run.u, run.state(), &tags, None);
        let (area, h) = area_and_size(&problem.mesh);
        let (osc_scale, neu_scale) = (h / std::f64::consts::PI * weight * area.sqrt(), neumann_scale(&fields));
        println!(
            "scene A P{order} as fields: eta_osc {:.3e} (relative {:.1e}), eta_Neu {:.3e} (relative {:.1e}), eta_tot {:.4e} vs {:.4e}",
            f.est.osc,
            f.est.osc / osc_scale,
            f.est.neu,
            f.est.neu / neu_scale,
            f.est.tot,
            e.est.tot
        );
        assert!(f.est.osc <= 1e-12 * osc_scale, "P{order}: eta_osc of a constant field {}", f.est.osc);
        assert!(f.est.neu <= 1e-12 * neu_scale, "P{order}: eta_Neu of a linear field {}", f.est.neu);
        assert!((f.est.tot - e.est.tot).abs() <= 1e-10 * e.est.tot, "P{order}: eta_tot changed");
        assert!(f.eq.worst(order) < 1e-10, "P{order} fields: {:?}", f.eq);

        // a water level inside the upstream face: a kink of g_N inside one face
        let (low, l) = scene_a_low_water(&problem, &tags);
        println!(
            "scene A P{order}, water level 30.3: {} (eta_Neu relative {:.2e}); worst check {:.1e}",
            components(&l.est),
            l.est.neu / neumann_scale(&low),
            l.eq.worst(order)
        );
        assert!(l.est.neu > 1e-6 * neumann_scale(&low), "P{order}: eta_Neu {} with a kink in a face", l.est.neu);
    }
}

/// Scene A with the water level lowered to 30.3 m (inside the upstream face), solved with the
/// CLI settings, and its evaluation.
fn scene_a_low_water(problem: &Problem, tags: &[i32]) -> (Problem, Evaluation) {
    let mut low = problem.clone();
    for bc in &mut low.neumann {
        if let Traction::Hydrostatic { level, .. } = &mut bc.traction {
            *level = LOW_WATER;
        }
    }
    let disc = low.discretise();
    let scene = Scene::load(&manifest("geo/scene_a.toml")).unwrap();
    let settings = scene.continuation(&low, &disc.topology);
    let (_, joint) = scene.problem(low.mesh.clone()).unwrap_or_else(|e| panic!("{e}"));
    let joint = joint.expect("Scene A has a contact curve");
    assert_eq!(joint.tags, tags, "the contact curves of Scene A");
    let run = solve_with_contact(&low, &disc, &joint, &settings);
    let e = evaluate(&low, &run.u, run.state(), tags, Some(1));
    (low, e)
}

const LOW_WATER: f64 = 30.3;

/// Source: geo/scene_a.toml with the flood level lowered to 30.3 m, so that the hydrostatic
/// pressure ρ_w g (H_w − y)₊ has its kink inside one facet of the upstream face.
/// Goal: equilibration below 10⁻¹⁰, in particular σ_h n = Π_F^p g_N on that facet.
/// Parameters: mesh sizes × 2, P1 and P2, CLI contact settings.
///
/// Fails: the Neumann check is 5.7·10⁻⁵ (P1). The load (src/elasticity/problem.rs
/// add_tractions) and the reconstruction's Neumann moments (src/estimate/reconstruction.rs
/// traction_moments) integrate g_N with p + 4 Gauss points per facet without splitting at the
/// water level, the check (src/estimate/checks.rs Traces::neumann) projects with p + 2 points,
/// also unsplit; the exact moments differ from the p + 4-point ones on the kinked facet (printed
/// below), so σ_h n is not the L² projection Π_F^p g_N the bound assumes. dual_norm.rs does
/// split at the level.
#[test]
fn kinked_hydrostatic_load_equilibrates() {
    let mut worst = Vec::new();
    for order in [1, 2] {
        let (problem, tags, _) = scene_with_contact("geo/scene_a.toml", order, 2.0);
        let (low, l) = scene_a_low_water(&problem, &tags);
        // the facet holding the water level: exact against (p + 4)-point moments ∫ g_x s^m
        let mesh = &low.mesh;
        for bc in &low.neumann {
            let Traction::Hydrostatic { .. } = bc.traction else { continue };
            for f in (0..mesh.n_facets()).filter(|&f| mesh.facet_tags[f] == bc.tag) {
                let n = mesh.facet(f);
                let (a, b) = (mesh.points[n[0]], mesh.points[n[1]]);
                if (a[1] - LOW_WATER) * (b[1] - LOW_WATER) >= 0.0 {
                    continue;
                }
                let g = |s: f64| bc.traction.at([a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])], [-1.0, 0.0])[0];
                let moment = |rule: &[(f64, f64)], m: i32| rule.iter().map(|&(s, w)| g(s) * s.powi(m) * w).sum::<f64>();
                let gauss = |n: usize, lo: f64, hi: f64| -> Vec<(f64, f64)> {
                    let r = damfem::fem::quadrature::gauss_segment(n);
                    r.points.iter().zip(&r.weights).map(|(&s, &w)| (lo + s * (hi - lo), w * (hi - lo))).collect()
                };
                let cut = (LOW_WATER - a[1]) / (b[1] - a[1]);
                let exact: Vec<(f64, f64)> = gauss(6, 0.0, cut).into_iter().chain(gauss(6, cut, 1.0)).collect();
                for m in 0..=order as i32 {
                    let (e, q4, q2) = (
                        moment(&exact, m),
                        moment(&gauss(order + 4, 0.0, 1.0), m),
                        moment(&gauss(order + 2, 0.0, 1.0), m),
                    );
                    println!(
                        "P{order} facet y in [{:.2}, {:.2}], moment s^{m}: exact {e:.6e}, p+4 points {:+.2e} relative, p+2 points {:+.2e} relative",
                        a[1].min(b[1]),
                        a[1].max(b[1]),
                        (q4 - e) / e,
                        (q2 - e) / e
                    );
                }
            }
        }
        let dual = l.dual.unwrap();
        println!(
            "P{order} water level {LOW_WATER}: eta {:.4e} >= dual {dual:.4e}: {}; {:?}",
            l.est.tot,
            l.est.tot >= dual,
            l.eq
        );
        assert!(l.est.tot >= dual, "P{order}: bound violated, eta {} < dual {dual}", l.est.tot);
        worst.push((order, l.eq));
    }
    for (order, eq) in worst {
        assert!(eq.worst(order) < 1e-10, "P{order} level {LOW_WATER}: {eq:?}");
    }
}

/// A structured square (μ = λ = 1, ρ = 1) clamped on the left, self-weight g = 1, constant
/// tractions on the right and top sides, given as `Traction::Constant` or as fields.
fn constant_traction_problem(order: usize, as_fields: bool) -> Problem {
    let mesh = rectangle(0.0, 2.0, 0.0, 1.0, 8, 4, order);
    let mut material = Material::from_lame(1.0, 1.0);
    material.density = 1.0;
    let traction = |t: [f64; 2]| if as_fields { Traction::Field(Arc::new(move |_| t)) } else { Traction::Constant(t) };
    Problem {
        materials: vec![material; mesh.n_cells()],
        dirichlet: vec![damfem::elasticity::Dirichlet { tag: LEFT, fix: [true; 2], value: Arc::new(|_| [0.0; 2]) }],
        neumann: vec![
            Neumann { tag: RIGHT, traction: traction([0.3, -0.2]) },
            Neumann { tag: TOP, traction: traction([0.0, -1.0]) },
        ],
        body_force: if as_fields { BodyForce::Field(Arc::new(|_| [0.0, -1.0])) } else { BodyForce::Gravity(1.0) },
        mesh,
    }
}

/// Source: docs/method.md §5, src/estimate/estimators.rs (η_osc, η_Neu), §7 V1.
/// Goal: η_osc = η_Neu = 0 exactly for self-weight and constant tractions (P1, P2), round-off
/// when the same data are given as fields; η_osc > 0 for the smooth body force of V1, at the
/// rate h^{p+1} (‖f − Π^{p−1}f‖_T = O(h^p) times h_T/π).
/// Parameters: 2 × 1 rectangle, 8 × 4 cells, left clamped, tractions (0.3, −0.2) on the right
/// and (0, −1) on the top, g = 1; V1 on structured n = 4, 8.
#[test]
fn zero_oscillation_and_neumann_terms_on_constant_data() {
    for order in [1, 2] {
        let problem = constant_traction_problem(order, false);
        let e = evaluate(&problem, &solve_linear(&problem), None, &[], None);
        let fields = constant_traction_problem(order, true);
        let f = evaluate(&fields, &solve_linear(&fields), None, &[], None);
        let (area, h) = area_and_size(&problem.mesh);
        let (osc_scale, neu_scale) = (h / std::f64::consts::PI * area.sqrt(), neumann_scale(&problem));
        println!("constant data P{order}: {}; worst check {:.1e}", components(&e.est), e.eq.worst(order));
        println!(
            "    as fields: eta_osc {:.2e} (relative {:.1e}), eta_Neu {:.2e} (relative {:.1e}); worst check {:.1e}",
            f.est.osc,
            f.est.osc / osc_scale,
            f.est.neu,
            f.est.neu / neu_scale,
            f.eq.worst(order)
        );
        assert_eq!(e.est.osc, 0.0, "P{order}: eta_osc with self-weight");
        assert_eq!(e.est.neu, 0.0, "P{order}: eta_Neu with constant tractions");
        assert!(f.est.osc <= 1e-12 * osc_scale, "P{order}: eta_osc of a constant field {}", f.est.osc);
        assert!(f.est.neu <= 1e-12 * neu_scale, "P{order}: eta_Neu of a constant field {}", f.est.neu);
        assert!(e.eq.worst(order) < 1e-10 && f.eq.worst(order) < 1e-10, "P{order}: {:?} {:?}", e.eq, f.eq);

        let osc: Vec<f64> = [4, 8]
            .iter()
            .map(|&n| {
                let problem = v1::problem(unit_square(n, order), &[BOTTOM, RIGHT, TOP, LEFT]);
                let e = evaluate(&problem, &solve_linear(&problem), None, &[], None);
                println!("V1 P{order} n = {n}: {}", components(&e.est));
                e.est.osc
            })
            .collect();
        let rate = (osc[0] / osc[1]).log2();
        println!("V1 P{order}: eta_osc rate {rate:.3} (expected {})", order + 1);
        assert!(osc.iter().all(|&v| v > 0.0), "P{order}: eta_osc vanishes for a smooth f");
        assert!((rate - (order + 1) as f64).abs() < 0.3, "P{order}: eta_osc rate {rate}");
    }
}

/// The unit square with rollers on the left (u_x = 0) and bottom (u_y = 0) sides and constant
/// tractions (1, 0) on the right and (0, −0.5) on the top: σ = diag(1, −0.5), u affine.
fn roller_problem(mesh: Mesh, tags: [i32; 4]) -> Problem {
    let [bottom, right, top, left] = tags;
    let roller = |tag, fix| damfem::elasticity::Dirichlet { tag, fix, value: Arc::new(|_| [0.0; 2]) };
    Problem {
        materials: vec![Material::from_lame(1.0, 1.0); mesh.n_cells()],
        dirichlet: vec![roller(left, [true, false]), roller(bottom, [false, true])],
        neumann: vec![
            Neumann { tag: right, traction: Traction::Constant([1.0, 0.0]) },
            Neumann { tag: top, traction: Traction::Constant([0.0, -0.5]) },
        ],
        body_force: BodyForce::None,
        mesh,
    }
}

/// Source: docs/method.md §4.4 (free rigid motions of roller patches, the p = 1 rotation datum).
/// Goal: when u_h is the exact solution, η_tot is round-off, for P1 and P2, on a structured
/// and on a gmsh mesh. Roller patches leave one translation free and no rotation; a rotation
/// datum fitted to the round-off defect of that translation would make η large.
/// Parameters: unit square, rollers left and bottom, σ = diag(1, −0.5); structured 8 × 8,
/// gmsh geo/unit_square.geo (h = 1/8).
#[test]
fn exact_solution_with_rollers_has_zero_estimate() {
    for order in [1, 2] {
        let options = MeshOptions { order, size_factor: 1.0, ..Default::default() };
        let gmsh = mesh_geo(&manifest("geo/unit_square.geo"), &options, false, false).unwrap_or_else(|e| panic!("{e}"));
        let tags = ["bottom", "right", "top", "left"].map(|name| gmsh.group(1, name).unwrap().tag);
        for (label, problem) in [
            ("structured", roller_problem(unit_square(8, order), [BOTTOM, RIGHT, TOP, LEFT])),
            ("gmsh", roller_problem(gmsh.clone(), tags)),
        ] {
            let e = evaluate(&problem, &solve_linear(&problem), None, &[], None);
            println!("rollers {label} P{order}: {}; worst check {:.1e}", components(&e.est), e.eq.worst(order));
            let stress_norm = 1.25_f64.sqrt(); // ‖σ‖_Ω on the unit square
            assert!(e.est.tot < 1e-10 * stress_norm, "{label} P{order}: eta {} for an exact solution", e.est.tot);
            assert!(e.eq.worst(order) < 1e-10, "{label} P{order}: {:?}", e.eq);
        }
    }
}

// ---------------------------------------------------------------------------------------
// 4. the checks can fail
// ---------------------------------------------------------------------------------------

/// (δ, η_reg) of converged solutions of `problem` with contact on the bottom side, θ = 0,
/// γ₀ = 100, continuation from δ₀ = 0.1; equilibration and the bound asserted for each δ.
fn regularisation_sweep(name: &str, problem: &Problem, deltas: &[f64]) -> Vec<f64> {
    let order = problem.mesh.order;
    let disc = problem.discretise();
    let mut reg = Vec::new();
    println!("{name} P{order}:  delta  steps  eta_reg     eta_disc    eta_flux    eta_lin     eta_tot     dual        I_eff  worst");
    for &delta in deltas {
        let joint = ContactJoint::frictionless(vec![BOTTOM], NitscheParameters::default());
        let settings = Continuation { delta, delta_start: 0.1, newton: NewtonOptions::default() };
        let run = solve_with_contact(problem, &disc, &joint, &settings);
        let (e, steps) = (evaluate(problem, &run.u, run.state(), &[BOTTOM], Some(1)), run.newton_steps);
        let dual = e.dual.unwrap();
        println!(
            "        {delta:.0e}  {steps:5}  {:.4e}  {:.4e}  {:.4e}  {:.3e}  {:.4e}  {dual:.4e}  {:.3}  {:.1e}",
            e.est.reg,
            e.est.disc,
            e.est.flux,
            e.est.lin,
            e.est.tot,
            e.est.tot / dual,
            e.eq.worst(order)
        );
        assert!(e.eq.worst(order) < 1e-10, "{name} delta = {delta}: {:?}", e.eq);
        assert!(e.est.tot >= dual, "{name} delta = {delta}: bound violated, eta {} < dual {dual}", e.est.tot);
        reg.push(e.est.reg);
    }
    reg
}

/// Fitted and successive log-log slopes of η_reg against δ.
fn slopes(deltas: &[f64], reg: &[f64]) -> (f64, Vec<f64>) {
    let successive: Vec<f64> =
        reg.windows(2).zip(deltas.windows(2)).map(|(r, d)| (r[1] / r[0]).ln() / (d[1] / d[0]).ln()).collect();
    let fitted = common::fitted_rate(deltas, reg);
    println!("eta_reg against delta: fitted slope {fitted:.3}, successive slopes {:?}", fmt(&successive));
    (fitted, successive)
}

const DELTAS: [f64; 4] = [1e-1, 1e-2, 1e-3, 1e-4];

/// Source: docs/method.md §1.4 (0 ≤ [x]_{R⁻} − [x]_{reg,δ} ≤ δ/4, nonzero only where
/// |P_γ(u_h)| < δ) and §4 (σ_h2 carries t₂ = [P_γ(u_h)]_{reg,δ} − [P_γ(u_h)]_{R⁻}).
/// Goal: η_reg = O(δ) on converged solutions, and η_tot ≥ dual norm for every δ.
/// Parameters: V3, structured n = 8, P2, θ = 0, γ₀ = 100, δ = 10⁻¹, …, 10⁻⁴ (stress scale
/// ~1), solve_by_continuation from δ₀ = 0.1; dual norm on the mesh refined once.
///
/// Finding: on V3, η_reg decreases like δ², not δ (successive slopes 1.49, 2.05, 2.00). P_γ(u_h)
/// crosses zero transversally at the contact–separation point, so t₂ (of size ≤ δ/4) lives on
/// a zone of width O(δ/|P_γ'|), and σ_h2 only sees the face moments of t₂ (its normal trace
/// is Π_F^p t₂ n), which are O(δ²). The slope is asserted ≥ 0.8 (η_reg = O(δ) holds) and the
/// asymptotic δ² regime is asserted on the last two decades; the O(δ) rate itself is attained
/// by grazing contact, [`regularisation_estimator_grazing_contact`].
#[test]
fn regularisation_estimator_transversal_crossing() {
    let problem = v3::problem(unit_square(8, 2));
    let reg = regularisation_sweep("V3 n = 8", &problem, &DELTAS);
    let (fitted, successive) = slopes(&DELTAS, &reg);
    assert!(fitted >= 0.8, "eta_reg is not O(delta): slope {fitted}, {reg:?}");
    for s in &successive[1..] {
        assert!((1.8..=2.2).contains(s), "eta_reg: successive slope {s} outside the delta^2 regime: {reg:?}");
    }
}

/// V2 with d = 0 (docs/method.md §7): the unit square (E = 1, ν = 0, no load), clamped with
/// u = 0 on its top, resting on Γ_C = {y = 0} with zero gap, lateral sides free.
fn grazing_problem(order: usize) -> Problem {
    let mesh = unit_square(4, order);
    let material = Material { young: 1.0, poisson: 0.0, density: 0.0 };
    Problem {
        materials: vec![material; mesh.n_cells()],
        dirichlet: vec![damfem::elasticity::Dirichlet { tag: TOP, fix: [true; 2], value: Arc::new(|_| [0.0; 2]) }],
        neumann: vec![],
        body_force: BodyForce::None,
        mesh,
    }
}

/// Source: docs/method.md §1.4 and §7 V2 (patch test) with d = 0.
/// Goal: η_reg = O(δ) is sharp where P_γ(u_h) stays within δ of 0 along Γ_C (grazing contact:
/// the exact solution u = 0 touches the plane with zero pressure): the fitted slope of η_reg
/// against δ lies in [0.8, 1.2]; η_tot ≥ dual norm for every δ.
/// Parameters: V2 with d = 0, structured n = 4, P2, θ = 0, γ₀ = 100, δ = 10⁻¹, …, 10⁻⁴
/// (E = 1), continuation from δ₀ = 0.1; dual norm on the mesh refined once.
#[test]
fn regularisation_estimator_grazing_contact() {
    let reg = regularisation_sweep("V2 grazing n = 4", &grazing_problem(2), &DELTAS);
    let (fitted, _) = slopes(&DELTAS, &reg);
    assert!((0.8..=1.2).contains(&fitted), "eta_reg slope {fitted} against delta: {reg:?}");
}

/// As [`regularisation_estimator_grazing_contact`] at P1. Here t₂ is uniform along Γ_C, so
/// the one-cell patch at the corner (1, 0) of Γ_C, which has a free rotation at p = 1 (see
/// [`unconverged_newton_iterates_p1_from_zero`]), receives compatible data and equilibrates.
#[test]
fn regularisation_estimator_grazing_contact_p1() {
    let reg = regularisation_sweep("V2 grazing n = 4", &grazing_problem(1), &DELTAS);
    let (fitted, _) = slopes(&DELTAS, &reg);
    assert!((0.8..=1.2).contains(&fitted), "eta_reg slope {fitted} against delta: {reg:?}");
}

// ---------------------------------------------------------------------------------------
// 5. equilibration on gmsh meshes of the scenes
// ---------------------------------------------------------------------------------------

/// Adds `scale` × a pseudo-random vector to the coefficients of component `i` on `cells`.
fn perturb(rec: &mut Reconstruction, i: usize, cells: &[usize], scale: f64, random: &mut Random) {
    let n = COMPONENTS * rec.n_basis;
    for &c in cells {
        for v in &mut rec.sigma[i][c * n..(c + 1) * n] {
            *v += scale * random.next();
        }
    }
}

/// The index in `topology.vertices` of the vertex nearest to x.
fn vertex_near(mesh: &Mesh, topology: &Topology, x: [f64; 2]) -> usize {
    let d = |k: &usize| damfem::mesh::distance(mesh.points[topology.vertices[*k]], x);
    (0..topology.vertices.len()).min_by(|a, b| d(a).total_cmp(&d(b))).unwrap()
}

fn print_checks(label: &str, eq: &Equilibration) {
    println!(
        "{label:46} divergence {:.2e}  continuity {:.2e}  Neumann {:.2e}  contact {:.2e}  symmetry {:.2e}",
        eq.divergence, eq.normal_continuity, eq.neumann, eq.contact, eq.weak_symmetry
    );
}

/// Source: src/estimate/checks.rs (E1)–(E3).
/// Goal: the checks detect a broken reconstruction. A valid one is below 10⁻¹⁰; perturbing the
/// coefficients of one patch by 10⁻⁶ × a random vector raises normal continuity and divergence
/// far above it; a perturbation of one boundary patch raises the Neumann check; moving a
/// random field from σ_h2 to σ_h3 on one contact cell (σ_h unchanged) is seen by the contact
/// check alone.
/// Parameters: V1, structured n = 4, P2, the patch of the interior vertex (0.5, 0.5); V3 (n = 4,
/// P2, δ = 10⁻³, converged), the patch of the vertex (1, 0.5) on the Neumann side and the
/// cell of the contact face nearest to (0.25, 0); seeded xorshift64*.
#[test]
fn tampered_reconstruction_fails_the_checks() {
    let mut random = Random(0x9e37_79b9_7f4a_7c15);
    // V1: interior patch
    let problem = v1::problem(unit_square(4, 2), &[BOTTOM, RIGHT, TOP, LEFT]);
    let u = solve_linear(&problem);
    let topology = Topology::new(&problem.mesh);
    let mut rec = reconstruct(&problem, &topology, &u, None).unwrap();
    let valid = check(&problem, &topology, &u, &rec, None);
    print_checks("V1 P2 n = 4, valid", &valid);
    assert!(valid.worst(2) < 1e-10, "{valid:?}");
    let k = vertex_near(&problem.mesh, &topology, [0.5, 0.5]);
    let cells = topology.patch(k).to_vec();
    perturb(&mut rec, 0, &cells, 1e-6, &mut random);
    let broken = check(&problem, &topology, &u, &rec, None);
    print_checks(&format!("V1, sigma_h1 + 1e-6 random on {} cells", cells.len()), &broken);
    assert!(broken.normal_continuity > 1e-8, "{broken:?}");
    assert!(broken.divergence > 1e-8, "{broken:?}");
    assert!(broken.worst(2) > 1e3 * valid.worst(2).max(1e-14), "{broken:?}");

    // V3: a patch on the Neumann side and the σ_h2/σ_h3 split on Γ_C
    let problem = v3::problem(unit_square(4, 2));
    let disc = problem.discretise();
    let joint = ContactJoint::frictionless(vec![BOTTOM], NitscheParameters::default());
    let settings = Continuation { delta: 1e-3, delta_start: 0.1, newton: NewtonOptions::default() };
    let run = solve_with_contact(&problem, &disc, &joint, &settings);
    let state =
        Linearisation { nitsche: &run.nitsche, smoothing: Smoothing { delta: run.delta }, u_prev: run.u_prev.clone() };
    let topology = Topology::new(&problem.mesh);
    let valid_rec = reconstruct(&problem, &topology, &run.u, Some(&state)).unwrap();
    let valid = check(&problem, &topology, &run.u, &valid_rec, Some(&state));
    print_checks("V3 P2 n = 4, valid", &valid);
    assert!(valid.worst(2) < 1e-10, "{valid:?}");

    let mut rec = reconstruct(&problem, &topology, &run.u, Some(&state)).unwrap();
    let k = vertex_near(&problem.mesh, &topology, [1.0, 0.5]);
    let cells = topology.patch(k).to_vec();
    perturb(&mut rec, 0, &cells, 1e-6, &mut random);
    let broken = check(&problem, &topology, &run.u, &rec, Some(&state));
    print_checks(&format!("V3, Neumann patch + 1e-6 random on {} cells", cells.len()), &broken);
    assert!(broken.neumann > 1e-8, "{broken:?}");

    let mut rec = reconstruct(&problem, &topology, &run.u, Some(&state)).unwrap();
    let face = run
        .nitsche
        .faces
        .iter()
        .min_by(|a, b| {
            let d = |f: &damfem::contact::nitsche::ContactFace| {
                let m = f.map.to_physical([0.5 * (f.ends[0][0] + f.ends[1][0]), 0.5 * (f.ends[0][1] + f.ends[1][1])]);
                damfem::mesh::distance(m, [0.25, 0.0])
            };
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    let n = COMPONENTS * rec.n_basis;
    let shift: Vec<f64> = (0..n).map(|_| 1e-6 * random.next()).collect();
    for (j, v) in shift.iter().enumerate() {
        rec.sigma[1][face.cell * n + j] += v;
        rec.sigma[2][face.cell * n + j] -= v;
    }
    let broken = check(&problem, &topology, &run.u, &rec, Some(&state));
    print_checks("V3, 1e-6 random moved sigma_h3 -> sigma_h2", &broken);
    assert!(broken.contact > 1e-8, "{broken:?}");
    for (name, v) in
        [("divergence", broken.divergence), ("continuity", broken.normal_continuity), ("Neumann", broken.neumann)]
    {
        assert!(v < 1e-10, "{name} changed although sigma_h is unchanged: {broken:?}");
    }
}

// ---------------------------------------------------------------------------------------
// 6. V1 on gmsh meshes
// ---------------------------------------------------------------------------------------

/// Source: docs/method.md §7 V1 (tests/common/v1.rs) on geo/unit_square.geo meshed by gmsh
/// (Frontal-Delaunay, unstructured), Dirichlet data on the curves bottom, right, top, left.
/// Goal: equilibration below 10⁻¹⁰ and η_tot ≥ dual norm on unstructured meshes.
/// Parameters: p = 1, 2; size_factor 1 (h = 1/8) and 0.5 (h = 1/16); dual norm on the mesh
/// refined once.
#[test]
fn v1_on_gmsh_meshes() {
    let geo = manifest("geo/unit_square.geo");
    for order in [1, 2] {
        for size_factor in [1.0, 0.5] {
            let options = MeshOptions { order, size_factor, ..Default::default() };
            let mesh = mesh_geo(&geo, &options, false, false).unwrap_or_else(|e| panic!("{e}"));
            let tags: Vec<i32> = ["bottom", "right", "top", "left"]
                .iter()
                .map(|name| mesh.group(1, name).unwrap_or_else(|| panic!("physical curve {name}")).tag)
                .collect();
            let problem = v1::problem(mesh, &tags);
            let u = solve_linear(&problem);
            let e = evaluate(&problem, &u, None, &[], Some(1));
            let dual = e.dual.unwrap();
            println!(
                "V1 gmsh P{order} size factor {size_factor}: {} cells; eta {:.4e} (osc {:.2e}, flux {:.3e}), dual {dual:.4e}, I_eff {:.3}; worst check {:.1e}",
                problem.mesh.n_cells(),
                e.est.tot,
                e.est.osc,
                e.est.flux,
                e.est.tot / dual,
                e.eq.worst(order)
            );
            assert!(e.eq.worst(order) < 1e-10, "P{order} size factor {size_factor}: {:?}", e.eq);
            assert!(
                e.est.tot >= dual,
                "P{order} size factor {size_factor}: bound violated, eta {} < {dual}",
                e.est.tot
            );
        }
    }
}
