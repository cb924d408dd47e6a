//! Behaviour of Newton's method on the contact problem (docs/method.md §1.4–1.5): quadratic
//! convergence of the regularised problem, convergence of the regularised solution as δ → 0,
//! failure reported as an error, and the Schur complement on the contact layer against the
//! sparse LU of the whole Jacobian.

use crate::common;

use damfem::contact::nitsche::NitscheParameters;
use damfem::contact::projection::Smoothing;
use damfem::contact::{
    continuation, solve_by_continuation, ContactError, ContactJoint, ContactProblem, Continuation, JointLaw,
};
use damfem::elasticity::{BodyForce, Dirichlet, Discretisation, Material, Problem};
use damfem::fem::dofs::FIXED;
use damfem::fem::sparse::SparsePattern;
use damfem::io::gmsh::{mesh_geo, MeshOptions};
use damfem::mesh::structured::{unit_square, BOTTOM, LEFT, RIGHT, TOP};
use damfem::scene::Scene;
use damfem::solve::{newton, newton_until, LayerSchur, NewtonError, NewtonOptions, NonlinearSystem, SparseLu};
use std::path::Path;
use std::sync::Arc;

/// Scene A (geo/scene_a.toml: gravity dam on rigid rock, heel side of the base in contact,
/// toe anchored, flood on the upstream face) meshed by gmsh at degree `order`: the scene,
/// its problem, discretisation, contact tags and stress scale S.
fn scene_a(order: usize) -> (Problem, Discretisation, ContactJoint, f64) {
    scene("scene_a.toml", order, 1.0)
}

/// The scene geo/`file` meshed by gmsh at degree `order` with its sizes times `size_factor`:
/// its problem, discretisation, joint and stress scale S.
fn scene(file: &str, order: usize, size_factor: f64) -> (Problem, Discretisation, ContactJoint, f64) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("geo").join(file);
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let m = &scene.mesh;
    let options = MeshOptions {
        order,
        size_factor: m.size_factor * size_factor,
        size_min: m.size_min,
        size_max: m.size_max,
        algorithm: m.algorithm,
    };
    let mesh = mesh_geo(&scene.geometry, &options, false, false).expect("gmsh meshes the scene");
    let (problem, joint) = scene.problem(mesh).unwrap_or_else(|e| panic!("{e}"));
    let disc = problem.discretise();
    let scale = problem.stress_scale(&disc.topology);
    (problem, disc, joint.expect("Scene A has a contact curve"), scale)
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt()
}

/// Quadratic convergence. Source: docs/method.md §1.5 (Newton on the C¹ regularisation, whose
/// derivative is Lipschitz). Goal: once the active set has settled, ‖Δ_{k+1}‖ ≤ C ‖Δ_k‖².
/// Problem: Scene A (geo/scene_a.toml, gmsh mesh of the scene, P1 and P2): gravity dam
/// (E = 30 GPa, ν = 0.2, ρ = 2400) on rigid rock, toe anchored (u = 0), hydrostatic flood
/// (level 70 m) on the upstream face, self-weight, frictionless Nitsche contact on the heel
/// side of the base (θ = 0, γ₀ = 100, gap 0). δ = 10⁻⁴ S (the CLI default), one Newton
/// solve from u = 0, rtol = 10⁻¹⁰.
/// Checks on the last three steps: the ratios ‖Δ_{k+1}‖/‖Δ_k‖² vary by less than a factor 10
/// (for a linear rate q they grow by 1/q per step) and the contraction ‖Δ_{k+1}‖/‖Δ_k‖ drops
/// below 10⁻² and by at least a factor 10 per step (it is constant for a linear rate).
#[test]
fn newton_converges_quadratically_once_the_active_set_settles() {
    for order in [1, 2] {
        let (problem, disc, joint, scale) = scene_a(order);
        let settings =
            Continuation { delta: 1e-4 * scale, delta_start: 0.0, newton: NewtonOptions::default(), path: None };
        let solution = solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(solution.stages.len(), 1);
        let report = &solution.stages[0].report;
        let increments: Vec<f64> = report.iterations.iter().map(|it| it.increment).collect();
        let ratios = report.quadratic_ratios();
        let n = increments.len();
        assert!(n >= 4, "P{order}: too few Newton steps ({n}) to see the rate");
        let contractions: Vec<f64> = increments.windows(2).map(|w| w[1] / w[0]).collect();
        println!(
            "P{order}: {n} Newton steps, ‖x‖ = {:.3e}, contact length {:.3} m, final relative residual {:.1e}",
            norm(&solution.x),
            solution.contact_length(),
            report.residual / report.scale
        );
        for (k, it) in report.iterations.iter().enumerate().skip(n.saturating_sub(5)) {
            println!(
                "  step {k:2}: relative residual {:.2e}, ‖Δ‖ = {:.2e}, t = {}{}",
                it.residual / report.scale,
                it.increment,
                it.step,
                if k > 0 {
                    format!(", ‖Δ_k‖/‖Δ_k−1‖² = {:.2e}, ‖Δ_k‖/‖Δ_k−1‖ = {:.2e}", ratios[k - 1], contractions[k - 1])
                } else {
                    String::new()
                }
            );
        }
        assert!(report.iterations[n - 3..].iter().all(|it| it.step == 1.0), "P{order}: damped final steps");
        let last_ratios = &ratios[ratios.len() - 3..];
        let (lo, hi) = last_ratios.iter().fold((f64::MAX, 0.0f64), |(lo, hi), &r| (lo.min(r), hi.max(r)));
        assert!(hi <= 10.0 * lo, "P{order}: ratios ‖Δ_k+1‖/‖Δ_k‖² not bounded: {last_ratios:?}");
        let q = &contractions[contractions.len() - 2..];
        assert!(q[1] <= 1e-2 && q[1] <= 0.1 * q[0], "P{order}: contractions {q:?} do not drop super-linearly");
    }
}

/// δ → 0. Source: docs/method.md §1.4: |[x]_{reg,δ} − [x]_{R⁻}| ≤ δ/4, so the regularised
/// discrete solution u_δ tends to the semismooth one u_0 (δ = 0) with ‖u_δ − u_0‖ = O(δ).
/// Goal: measure the rate. Problem: Scene A as above (P1 and P2), δ = S·10^{−k/2},
/// k = 2, …, 7 (P1) or 2, …, 6 (P2), each solved by Newton from the previous u_δ with
/// rtol = 10⁻¹²; u_0 from solve_by_continuation with δ = 0 (continuation from 10⁻¹ S).
/// Norm: Euclidean norm of the free unknowns. The fitted slope must be at least 0.9.
/// Observed: slope 2. [P_γ(u_0)]_{reg,δ} differs from [P_γ(u_0)]_{R⁻} only where
/// |P_γ(u_0)| < δ, and P_γ(u_0) crosses 0 transversally at the ends of the contact zone, so
/// that set has length O(δ) and the consistency error is O(δ²). The O(δ) bound is attained
/// only if P_γ(u_0) vanishes on a set of positive length: see the grazing test below.
/// (The paths stop where ‖u_δ − u_0‖ would come within a factor 10 of the round-off level,
/// about 10⁻¹³ ‖u‖ for P1 and 3·10⁻¹³ ‖u‖ for P2.)
#[test]
fn regularised_solution_tends_to_the_semismooth_one() {
    for (order, last_k) in [(1, 7), (2, 6)] {
        let (problem, disc, joint, scale) = scene_a(order);
        let options = NewtonOptions { rtol: 1e-12, ..Default::default() };
        let settings = Continuation { delta: 0.0, delta_start: 0.1 * scale, newton: options, path: None };
        let exact = solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("{e}"));
        let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 0.0 });
        let mut x = vec![0.0; disc.dofs.n_free];
        let (mut deltas, mut errors) = (Vec::new(), Vec::new());
        println!("P{order}: S = {scale:.4e} Pa, ‖u_0‖ = {:.4e}", norm(&exact.x));
        for k in 2..=last_k {
            let delta = scale * 10f64.powf(-0.5 * k as f64);
            contact.set_delta(delta);
            let report = newton(&contact, x, &options).unwrap_or_else(|e| panic!("δ = {delta:e}: {e}"));
            x = report.x;
            let error = distance(&x, &exact.x);
            println!(
                "  δ = {:.2e} S: ‖u_δ − u_0‖ = {error:.4e} ({:.3e} relative), {} Newton steps",
                delta / scale,
                error / norm(&exact.x),
                report.iterations.len()
            );
            deltas.push(delta);
            errors.push(error);
        }
        let slope = common::fitted_rate(&deltas, &errors);
        println!("P{order}: fitted slope of log ‖u_δ − u_0‖ against log δ: {slope:.3}");
        assert!(slope >= 0.9, "P{order}: ‖u_δ − u_0‖ decreases like δ^{slope:.2}, slower than O(δ)");
    }
}

/// δ → 0 with grazing contact: the O(δ) bound is sharp. Source: docs/method.md §1.4.
/// Goal: where P_γ(u_0) = 0 on all of Γ_C, [0]_{reg,δ} = −δ/4 pushes on the whole of Γ_C and
/// ‖u_δ − u_0‖ is exactly proportional to δ (u_δ − u_0 = δ w for one w, by homogeneity of
/// the smoothing: [δy]_{reg,δ} = δ [y]_{reg,1}). Problem: unit square, 8 × 8 P2, E = 1, ν = 0,
/// u = (εx, 0) with ε = 10⁻² on the top, left and right sides, contact on the bottom with
/// gap 0, θ = 0, γ₀ = 100. The discrete semismooth solution is u_0 = (εx, 0): no stress
/// normal to the bottom and no gap, so P_γ(u_0) = 0 there. δ = S·10^{−k}, k = 1, …, 4.
/// The fitted slope must lie in [0.9, 1.1].
#[test]
fn regularised_solution_error_is_linear_in_delta_for_grazing_contact() {
    let strain = 1e-2;
    let mesh = unit_square(8, 2);
    let stretch: Arc<dyn Fn([f64; 2]) -> [f64; 2] + Send + Sync> = Arc::new(move |x| [strain * x[0], 0.0]);
    let problem = Problem {
        materials: vec![Material { young: 1.0, poisson: 0.0, density: 0.0 }; mesh.n_cells()],
        dirichlet: [TOP, LEFT, RIGHT]
            .into_iter()
            .map(|tag| Dirichlet { tag, fix: [true; 2], value: stretch.clone() })
            .collect(),
        neumann: vec![],
        body_force: BodyForce::None,
        mesh,
    };
    let disc = problem.discretise();
    let scale = problem.stress_scale(&disc.topology);
    let joint = ContactJoint::frictionless(vec![BOTTOM], NitscheParameters::default());
    let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 0.0 });
    // u_0: the interpolant of (εx, 0), which must solve the semismooth problem
    let mut exact = vec![0.0; disc.dofs.n_free];
    for (node, p) in problem.mesh.points.iter().enumerate() {
        for a in 0..2 {
            if disc.dofs.free[2 * node + a] != FIXED {
                exact[disc.dofs.free[2 * node + a]] = stretch(*p)[a];
            }
        }
    }
    let mut residual = vec![0.0; disc.dofs.n_free];
    contact.evaluate(&exact, &mut residual, None);
    assert!(norm(&residual) <= 1e-12 * contact.scale(), "u_0 = (εx, 0) is not the semismooth solution");
    assert!(contact.face_states(&exact).iter().all(|f| f.pressure == 0.0 && f.normal_displacement.abs() < 1e-15));
    let (mut deltas, mut errors) = (Vec::new(), Vec::new());
    let options = NewtonOptions { rtol: 1e-12, ..Default::default() };
    for k in 1..=4 {
        let delta = scale * 10f64.powi(-k);
        contact.set_delta(delta);
        let report = newton(&contact, exact.clone(), &options).unwrap_or_else(|e| panic!("δ = {delta:e}: {e}"));
        let error = distance(&report.x, &exact);
        println!("δ = {:.0e} S: ‖u_δ − u_0‖ = {error:.4e}, ‖u_δ − u_0‖/δ = {:.6e}", delta / scale, error / delta);
        deltas.push(delta);
        errors.push(error);
    }
    let slope = common::fitted_rate(&deltas, &errors);
    println!("grazing contact: fitted slope {slope:.4}");
    assert!((0.9..=1.1).contains(&slope), "slope {slope} not 1");
}

/// A Newton failure is an error. Source: src/solve/newton.rs (running out of iterations is
/// NewtonError::NotConverged with the residual history). Problem: Scene A at P1 as above,
/// δ = 10⁻⁴ S, solved from u = 0 with max_iter = 1 through solve_by_continuation, and with
/// max_iter = 3 through newton directly: both must return NotConverged (no panic, no
/// answer) whose message lists every relative residual of the history.
#[test]
fn newton_failure_is_a_clear_error() {
    let (problem, disc, joint, scale) = scene_a(1);
    let expect_not_converged = |result: Result<Vec<f64>, NewtonError>, max_iter: usize| {
        let error = result.expect_err("Newton cannot converge in so few steps");
        let message = error.to_string();
        println!("max_iter = {max_iter}: {message}");
        match error {
            NewtonError::NotConverged { history, scale } => {
                assert_eq!(history.len(), max_iter);
                let listed: Vec<String> = history.iter().map(|it| format!("{:.2e}", it.residual / scale)).collect();
                assert!(
                    message.contains(&format!("in {max_iter} step(s)")) && message.contains(&listed.join(", ")),
                    "the message does not list the residual history {listed:?}: {message}"
                );
            }
            other => panic!("expected NotConverged, got {other:?}"),
        }
    };
    let mut settings = Continuation {
        delta: 1e-4 * scale,
        delta_start: 0.0,
        newton: NewtonOptions { max_iter: 1, ..Default::default() },
        path: None,
    };
    let result = solve_by_continuation(&problem, &disc, &joint, &settings).map(|s| s.x);
    expect_not_converged(
        result.map_err(|e| match e {
            ContactError::Newton(newton) => newton,
            other => panic!("{other}"),
        }),
        1,
    );
    settings.newton.max_iter = 3;
    let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: settings.delta });
    expect_not_converged(newton(&contact, vec![0.0; disc.dofs.n_free], &settings.newton).map(|r| r.x), 3);
}

/// A system that hides the `LayerSchur` of the one it wraps: Newton factors its Jacobian by
/// sparse LU.
struct WithoutSchur<'a>(&'a ContactProblem<'a>);

impl NonlinearSystem for WithoutSchur<'_> {
    fn pattern(&self) -> &SparsePattern {
        self.0.pattern()
    }
    fn evaluate(&self, x: &[f64], residual: &mut [f64], jacobian: Option<&mut [f64]>) {
        self.0.evaluate(x, residual, jacobian)
    }
    fn scale(&self) -> f64 {
        self.0.scale()
    }
    fn monotone(&self) -> bool {
        self.0.monotone()
    }
}

/// Scene A at P2 with the Nitsche variant θ and the joint law `law`, and its contact problem
/// at δ = 10⁻⁴ S.
fn scene_a_joint(theta: f64, law: JointLaw) -> (Problem, Discretisation, ContactJoint, f64) {
    let (problem, disc, joint, scale) = scene_a(2);
    let parameters = NitscheParameters { theta, ..joint.laws[0].parameters };
    (problem, disc, ContactJoint::uniform(joint.tags, Vec::new(), law, parameters), scale)
}

/// The Schur complement on the contact layer. Source: docs/solver.md §1 and the block
/// elimination of J = K + E C Eᵀ with the interior and the layer's dofs off the rows R of C
/// eliminated first (src/solve/schur.rs). Goal: a Newton step by the dense Schur complement S_R
/// on R solves the same equation as the sparse LU of the whole Jacobian, for symmetric and
/// non-symmetric C. Problem: Scene A (P2, gmsh, as above) at δ = 10⁻⁴ S with θ = 1, 0, −1
/// (frictionless) and θ = 0 with Coulomb friction F = 0.84, whose Jacobian couples the normal
/// columns into the tangential rows. J is evaluated at the converged frictionless solution,
/// which has closed and open faces. Checks: the layer (dofs of the cells owning a contact face)
/// is under a tenth of n and factorised dense; R is the whole layer for θ ≠ 0 and, for θ = 0,
/// the dofs of the nodes on Γ_C, under half of the layer; for b = F(0) (the load, with its
/// sign) and for b with entries sin(i), the two solutions agree to 10⁻¹⁰ relative and
/// ‖J x − b‖ ≤ 10⁻¹⁰ ‖b‖ for the Schur solution.
#[test]
fn schur_complement_on_the_layer_solves_the_newton_equation() {
    let (problem, disc, joint, scale) = scene_a_joint(0.0, JointLaw::Frictionless);
    let settings = Continuation { delta: 1e-4 * scale, delta_start: 0.0, newton: NewtonOptions::default(), path: None };
    let x = solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("{e}")).x;
    let n = disc.dofs.n_free;
    let laws = [(1.0, JointLaw::Frictionless), (0.0, JointLaw::Frictionless), (-1.0, JointLaw::Frictionless)];
    for (theta, law) in laws.into_iter().chain([(0.0, JointLaw::Coulomb { friction: 0.84 })]) {
        let parameters = NitscheParameters { theta, ..joint.laws[0].parameters };
        let joint = ContactJoint::uniform(joint.tags.clone(), Vec::new(), law, parameters);
        let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: settings.delta });
        let schur = contact.schur().expect("the layer of Scene A is factorised dense");
        let m = schur.layer_size();
        assert!(m == contact.layer().len() && 10 * m < n, "layer of {m} dofs for {n} unknowns");
        let rows = schur.rows();
        let expected = if theta == 0.0 { contact.layer_rows().len() } else { m };
        assert!(rows == expected && (theta != 0.0 || 2 * rows < m), "θ = {theta}: {rows} rows of {m}");
        let pattern = contact.pattern();
        let (mut residual, mut jacobian) = (vec![0.0; n], vec![0.0; pattern.nnz()]);
        contact.evaluate(&x, &mut residual, Some(&mut jacobian));
        let lu = SparseLu::analyse(pattern).unwrap();
        let lu = lu.factor(pattern, &jacobian).unwrap();
        let factors = schur.factor(&jacobian).unwrap();
        let defect = |x: &[f64], b: &[f64]| {
            let mut jx = vec![0.0; n];
            pattern.multiply(&jacobian, x, &mut jx);
            distance(&jx, b) / norm(b)
        };
        let mut load = vec![0.0; n];
        contact.evaluate(&vec![0.0; n], &mut load, None);
        let oscillating: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        for b in [load, oscillating] {
            let (by_schur, by_lu) = (factors.solve(&b).unwrap(), lu.solve(&b));
            let (defect_schur, defect_lu) = (defect(&by_schur, &b), defect(&by_lu, &b));
            let difference = distance(&by_schur, &by_lu) / norm(&by_lu);
            println!(
                "θ = {theta}, {law:?}: layer {m} of {n} dofs, {rows} rows, ‖Jx − b‖/‖b‖ = {defect_schur:.1e} (LU {defect_lu:.1e}), \
                 Schur vs LU {difference:.1e}"
            );
            assert!(
                defect_schur <= 1e-10 && difference <= 1e-10,
                "θ = {theta}, {law:?}: defect {defect_schur:e}, difference {difference:e}"
            );
        }
    }
}

/// Contact rows outside R. Source: src/solve/schur.rs (the rows of J outside R must be those of
/// K, to round-off). Goal: a Jacobian whose contact terms reach rows outside the rows R that K
/// was factorised for is refused, not solved with a wrong Schur complement. Problem: Scene A
/// (P2, gmsh, as above), δ = 10⁻⁴ S, K factorised with R the dofs of the nodes on Γ_C (the
/// rows of θ = 0), and the Jacobians at u = 0 of θ = 0 and of θ = 1, whose term
/// −(θ/γ) σ^n(w) σ^n(v) reaches every dof of the cells along Γ_C. Checks: the first is
/// factorised, the second refused with an error.
#[test]
fn contact_rows_outside_the_layer_rows_are_refused() {
    let jacobian_of = |theta: f64| {
        let (problem, disc, joint, scale) = scene_a_joint(theta, JointLaw::Frictionless);
        let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 1e-4 * scale });
        let pattern = contact.pattern();
        let n = disc.dofs.n_free;
        let (mut residual, mut jacobian) = (vec![0.0; n], vec![0.0; pattern.nnz()]);
        contact.evaluate(&vec![0.0; n], &mut residual, Some(&mut jacobian));
        jacobian
    };
    let (problem, disc, joint, scale) = scene_a_joint(0.0, JointLaw::Frictionless);
    let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 1e-4 * scale });
    let stiffness = problem.assemble_on(&disc, contact.pattern()).values;
    let schur = LayerSchur::new(contact.pattern(), &stiffness, &contact.layer(), &contact.layer_rows())
        .expect("the layer of Scene A is factorised dense");
    assert!(schur.factor(&jacobian_of(0.0)).is_ok(), "θ = 0 refused");
    match schur.factor(&jacobian_of(1.0)) {
        Ok(_) => panic!("θ = 1 factorised with the rows of θ = 0"),
        Err(e) => println!("θ = 1 with the rows of θ = 0: {e}"),
    }
}

/// Converged displacements by either linear solver. Source: the Newton tolerance
/// (src/solve/newton.rs). Goal: Newton with the Schur complement on the contact layer reaches
/// the solution that it reaches with the sparse LU of the whole Jacobian, to the Newton
/// tolerance. Problem: Scene A (P2, gmsh, as above), δ = 10⁻⁴ S, rtol = 10⁻¹⁰, from u = 0,
/// with θ = 0 and θ = 1 (frictionless). Check: ‖x_Schur − x_LU‖ ≤ 10⁻⁸ ‖x_LU‖.
#[test]
fn newton_by_the_schur_complement_reaches_the_lu_solution() {
    for theta in [0.0, 1.0] {
        let (problem, disc, joint, scale) = scene_a_joint(theta, JointLaw::Frictionless);
        let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 1e-4 * scale });
        assert!(contact.schur().is_some());
        let x0 = vec![0.0; disc.dofs.n_free];
        let options = NewtonOptions::default();
        let by_schur = newton(&contact, x0.clone(), &options).unwrap_or_else(|e| panic!("θ = {theta}: {e}"));
        let by_lu = newton(&WithoutSchur(&contact), x0, &options).unwrap_or_else(|e| panic!("θ = {theta}: {e}"));
        let difference = distance(&by_schur.x, &by_lu.x) / norm(&by_lu.x);
        println!(
            "θ = {theta}: {} Newton steps by the Schur complement, {} by LU, ‖x_S − x_LU‖/‖x_LU‖ = {difference:.1e}",
            by_schur.iterations.len(),
            by_lu.iterations.len()
        );
        assert!(difference <= 1e-8, "θ = {theta}: the converged displacements differ by {difference:e}");
    }
}

/// The fully active start. Source: docs/solver.md §4 (Smoothing::CLOSED: [P_γ] replaced by
/// P_γ). Goal: `fully_active_start` solves the linear problem with every point of Γ_C held
/// closed, and Newton from it reaches the solution it reaches from u = 0. Problem: Scene A
/// (P2, gmsh, as above), θ = 0, γ₀ = 100, δ = 10⁻⁴ S. Checks: the residual of the start with
/// Smoothing::CLOSED is ≤ 10⁻¹⁰ of the load norm; the start is not the solution (the heel is
/// held down: ‖x_start − x‖ ≥ 10⁻³ ‖x‖); both converged solutions agree to 10⁻⁸ relative.
#[test]
fn fully_active_start_solves_the_closed_problem() {
    let (problem, disc, joint, scale) = scene_a_joint(0.0, JointLaw::Frictionless);
    let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 1e-4 * scale });
    let start = contact.fully_active_start().unwrap_or_else(|e| panic!("{e}"));
    let n = disc.dofs.n_free;
    let mut residual = vec![0.0; n];
    contact.set_delta(f64::NEG_INFINITY);
    assert_eq!(contact.smoothing, Smoothing::CLOSED);
    contact.evaluate(&start, &mut residual, None);
    let closed_residual = norm(&residual) / contact.scale();
    contact.set_delta(1e-4 * scale);
    let options = NewtonOptions::default();
    let cold = newton(&contact, vec![0.0; n], &options).unwrap_or_else(|e| panic!("{e}"));
    let warm = newton(&contact, start.clone(), &options).unwrap_or_else(|e| panic!("{e}"));
    let (from_start, difference) =
        (distance(&start, &cold.x) / norm(&cold.x), distance(&warm.x, &cold.x) / norm(&cold.x));
    println!(
        "closed residual {closed_residual:.1e}, ‖x_start − x‖/‖x‖ = {from_start:.2e}, Newton steps {} cold, {} from the start, difference {difference:.1e}",
        cold.iterations.len(),
        warm.iterations.len()
    );
    assert!(closed_residual <= 1e-10 && from_start >= 1e-3 && difference <= 1e-8);
}

/// A body held only by its contact. Source: src/solve/schur.rs (K is factorised once only if
/// every Cholesky pivot keeps L_ii² ≥ 10⁻¹⁰ K_ii). Goal: a stiffness that leaves a rigid
/// motion free, which only the contact stops, is not used for the Schur complement, and
/// Newton solves by sparse LU instead. Problem: the unit square (8 × 2 cells, P1, E = 1,
/// ν = 0.3, ρ = 1) under its weight (g = 1), u_x = 0 on the left and right sides, u_y free
/// there, frictionless Nitsche contact on the bottom (θ = 0, γ₀ = 100, δ = 0): the vertical
/// translation is free in K. The solve goes the way of `damfem solve`, [`continuation`] from
/// u = 0: there the contact sits on its kink (p_γ = 0), J = K is singular and the first step
/// is set by the round-off of K, so the path starts again from the closed state
/// (docs/solver.md §4). Checks: no Schur complement; the path converges; the contact force
/// balances the weight, ∫ p_c = 1, to 10⁻⁸.
#[test]
fn a_body_held_only_by_its_contact_is_solved_by_lu() {
    let mesh = unit_square(8, 2);
    let zero: Arc<dyn Fn([f64; 2]) -> [f64; 2] + Send + Sync> = Arc::new(|_| [0.0, 0.0]);
    let problem = Problem {
        materials: vec![Material { young: 1.0, poisson: 0.3, density: 1.0 }; mesh.n_cells()],
        dirichlet: [LEFT, RIGHT]
            .into_iter()
            .map(|tag| Dirichlet { tag, fix: [true, false], value: zero.clone() })
            .collect(),
        neumann: vec![],
        body_force: BodyForce::Acceleration([0.0, -1.0]),
        mesh,
    };
    let disc = problem.discretise();
    let joint = ContactJoint::frictionless(vec![BOTTOM], NitscheParameters::default());
    let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing::NONE);
    assert!(contact.schur().is_none(), "a singular stiffness was factorised for the Schur complement");
    let rest = vec![0.0; disc.dofs.n_free];
    let (x, stages) =
        continuation(&mut contact, 0.0, 0.0, rest, &NewtonOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let steps: usize = stages.iter().map(|s| s.report.iterations.len()).sum();
    let solution = contact.solution(x, stages, Vec::new());
    println!("contact force {:.12}, {steps} Newton steps", solution.normal_force());
    assert!((solution.normal_force() - 1.0).abs() <= 1e-8);
}

/// The full step of a damped one, offered to the stopping rule. Source: src/solve/newton.rs
/// (`Iterate::probe`) and docs/method.md §5.3: x_k + Δ solves the Newton equation linearised
/// at x_k, F(x_k) + J(x_k) Δ = 0, whatever the line search makes of it, so a rule that
/// estimates it may stop there. Problem: Scene A at P1 as above, δ = 10⁻⁴ S, Newton from u = 0,
/// where no step is cut, and the lift joint of geo/dam_lift_joint.toml (P1, sizes × 2:
/// Mohr–Coulomb, F = 0.84, c = 0.5 MPa, softening), where the first steps are. Checks: with a rule that takes the
/// first probe, Newton returns it: its last step is full, the iterate differs from the damped
/// one it was offered beside, and ‖F(x_prev) + J(x_prev)(x − x_prev)‖ ≤ 10⁻¹⁰ ‖b‖ (the
/// damped iterate leaves (1 − t) ‖F(x_prev)‖); with a rule that takes no probe, Newton runs on
/// and converges, offered at least that probe on the way.
#[test]
fn the_full_step_of_a_damped_one_is_offered_to_the_stopping_rule() {
    let options = NewtonOptions { max_iter: 100, ..Default::default() };
    let probes = |file: &str, order: usize, size_factor: f64| {
        let (problem, disc, joint, scale) = scene(file, order, size_factor);
        let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 1e-4 * scale });
        let mut probes = 0;
        let converged = newton_until(&contact, vec![0.0; disc.dofs.n_free], &options, |it| {
            probes += it.probe as usize;
            false
        })
        .unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(converged.residual <= options.rtol * converged.scale, "{file}: converged");
        probes
    };
    assert_eq!(probes("scene_a.toml", 1, 1.0), 0, "no step cut on Scene A, no probe");
    assert!(probes("dam_lift_joint.toml", 1, 2.0) > 0, "the lift joint's cut steps are offered");
    let (problem, disc, joint, scale) = scene("dam_lift_joint.toml", 1, 2.0);
    let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 1e-4 * scale });
    let taken =
        newton_until(&contact, vec![0.0; disc.dofs.n_free], &options, |it| it.probe).expect("the probe is taken");
    assert!(taken.iterations.last().is_some_and(|it| it.full()), "the probe is a full step");
    let n = disc.dofs.n_free;
    let (mut f, mut j, mut jd) = (vec![0.0; n], vec![0.0; contact.pattern().nnz()], vec![0.0; n]);
    contact.evaluate(&taken.x_prev, &mut f, Some(&mut j));
    let step: Vec<f64> = taken.x.iter().zip(&taken.x_prev).map(|(x, p)| x - p).collect();
    contact.pattern().multiply(&j, &step, &mut jd);
    let linearised: Vec<f64> = f.iter().zip(&jd).map(|(f, jd)| f + jd).collect();
    let b = contact.scale();
    println!(
        "probe after {} steps: ‖F_lin‖/‖b‖ = {:.2e}, ‖F(x_prev)‖/‖b‖ = {:.2e}, ‖F(x)‖/‖b‖ = {:.2e}",
        taken.iterations.len(),
        norm(&linearised) / b,
        norm(&f) / b,
        taken.residual / b
    );
    assert!(norm(&linearised) <= 1e-10 * b, "the probe solves the linearised equation");
    assert!(taken.residual > norm(&f), "the line search had cut this step: the full step raised ‖F‖");
}
