//! Verification of frictional Nitsche contact (docs/method.md §1.7).

use crate::common;
use damfem::contact::nitsche::{FaceDisplacement, NitscheParameters};
use damfem::contact::{solve_by_continuation, ContactError, ContactJoint, ContactSolution, Continuation, JointLaw};
use damfem::elasticity::{BodyForce, Dirichlet, Material, Neumann, Problem, Traction};
use damfem::estimate::reference::{sharp_reference, REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS};
use damfem::mesh::structured::{unit_square, BOTTOM, LEFT, RIGHT, TOP};
use damfem::solve::{NewtonError, NewtonOptions};
use std::sync::Arc;

/// The laws of the exact cases: S = 0.02 (Tresca), F = 0.5 (Coulomb), F = 0.3 and c = 0.005
/// (Mohr–Coulomb).
const LAWS: [JointLaw; 3] = [
    JointLaw::Tresca { threshold: 0.02 },
    JointLaw::Coulomb { friction: 0.5 },
    JointLaw::MohrCoulomb { friction: 0.3, cohesion: 0.005 },
];

/// Lamé coefficients of the exact cases.
const LAMBDA: f64 = 1.0;
const MU: f64 = 1.0;

/// The exact solution of the stick–slip case: Ω = (0,1)², Γ_C = {y = 0} on a rigid, flat
/// foundation (gap 0), Γ_D = {y = 1} with u = (a, −b), f = 0, the lateral sides loaded by
/// ±(σ_xx, σ_xy). It sticks, u = (a y, −b y), if μa ≤ S, and slips otherwise,
/// u = ((S/μ) y + a − S/μ, −b y), with σ_xy = min(μa, S) and S the threshold at the contact
/// pressure p_c = (λ + 2μ) b.
fn exact(law: JointLaw, a: f64, b: f64) -> (impl Fn([f64; 2]) -> [f64; 2], f64) {
    let p_c = (LAMBDA + 2.0 * MU) * b;
    let threshold = match law {
        JointLaw::Tresca { threshold } => threshold,
        JointLaw::Coulomb { friction } => friction * p_c,
        JointLaw::MohrCoulomb { friction, cohesion } => cohesion + friction * p_c,
        JointLaw::Frictionless => 0.0,
    };
    let shear = (MU * a).min(threshold);
    let slip = a - shear / MU;
    (move |x: [f64; 2]| [shear / MU * x[1] + slip, -b * x[1]], shear)
}

/// The stick–slip problem on the n × n grid of degree `order`.
fn problem(n: usize, order: usize, a: f64, b: f64, shear: f64) -> Problem {
    let mesh = unit_square(n, order);
    let (sxx, sxy) = (-LAMBDA * b, shear);
    Problem {
        materials: vec![Material::from_lame(LAMBDA, MU); mesh.n_cells()],
        dirichlet: vec![Dirichlet { tag: TOP, fix: [true; 2], value: Arc::new(move |_| [a, -b]) }],
        neumann: vec![
            Neumann { tag: LEFT, traction: Traction::Constant([-sxx, -sxy]) },
            Neumann { tag: RIGHT, traction: Traction::Constant([sxx, sxy]) },
        ],
        body_force: BodyForce::None,
        mesh,
    }
}

/// Stick and slip, exact. Source: the exact solutions above (they lie in P1). Goal: u_h = u
/// to round-off for Tresca, Coulomb and Mohr–Coulomb, p = 1, 2, θ = 1, 0, −1, the plain
/// projection (δ = 0) and a smoothing δ = 10⁻⁴ that the exact tractions stay away from, each
/// reached by δ-continuation from 10⁻² (a third of the contact pressure).
/// Parameters: λ = μ = 1, b = 0.01 (p_c = 0.03), a = 0.01 (stick) and 0.05 (slip); s = 0.02,
/// F = 0.5 (S = 0.015), F = 0.3 with c = 0.005 (S = 0.014); γ₀ = 100, 4 × 4 grid.
#[test]
fn stick_and_slip_are_exact() {
    let b = 0.01;
    for law in LAWS {
        for (case, a) in [("stick", 0.01), ("slip", 0.05)] {
            let (u_exact, shear) = exact(law, a, b);
            assert_eq!(case == "stick", shear == MU * a, "{law:?}: the data make it {case}");
            for (label, problem, solution) in stick_slip_solves(law, (a, b, shear), None) {
                let u = problem.displacement(&problem.discretise(), &solution.x);
                let error = common::max_nodal_error(&problem.mesh.points, &u, &u_exact);
                println!("{case} {label}: {} Newton steps, max nodal error {error:.1e}", solution.newton_steps());
                assert!(error <= 1e-12 * a, "{case} {label}: error {error}");
                let (stick, slip) = (solution.stick_length(), solution.slip_length());
                let expected = if case == "stick" { (1.0, 0.0) } else { (0.0, 1.0) };
                assert!(
                    (stick - expected.0).abs() < 1e-12 && (slip - expected.1).abs() < 1e-12,
                    "{case} {label}: stick {stick}, slip {slip}"
                );
            }
        }
    }
}

/// The stick–slip problem of `law` with (a, b, σ_xy) = `data` solved for p = 1, 2, θ = 1, 0, −1
/// and δ = 0, 10⁻⁴ (by δ-continuation from 10⁻²), its friction law measuring slip from the
/// uniform jump (s₀, 0) = `slip_origin` (None: from rest): each solution with its problem and
/// a label.
fn stick_slip_solves(
    law: JointLaw,
    (a, b, shear): (f64, f64, f64),
    slip_origin: Option<f64>,
) -> Vec<(String, Problem, ContactSolution)> {
    let mut solves = Vec::new();
    for order in [1, 2] {
        for theta in [1.0, 0.0, -1.0] {
            for delta in [0.0, 1e-4] {
                let label = format!("{law:?} P{order} θ = {theta:2} δ = {delta:.0e}");
                let problem = problem(4, order, a, b, shear);
                let disc = problem.discretise();
                let parameters = NitscheParameters { theta, ..crate::nitsche_parameters() };
                let origin = slip_origin.map(|s0| (0..problem.mesh.n_points()).flat_map(|_| [s0, 0.0]).collect());
                let joint = ContactJoint {
                    slip_origin: origin,
                    ..ContactJoint::uniform(vec![BOTTOM], Vec::new(), law, parameters)
                };
                let settings = Continuation { delta, delta_start: 1e-2, newton: NewtonOptions::default(), path: None };
                let solution = solve_by_continuation(&problem, &disc, &joint, &settings)
                    .unwrap_or_else(|e| panic!("{label}: {e}"));
                solves.push((label, problem, solution));
            }
        }
    }
    solves
}

/// Slip measured from an origin (docs/method.md §1.11). Source: the stick–slip case above with
/// the friction law on u^t − u^t_0, u_0 = (s₀, 0) everywhere (the jump s₀ along τ = e_x): where
/// it sticks, the base keeps the slip s₀ it had, u = ((a − s₀) y + s₀, −b y) with σ_xy =
/// μ (a − s₀); where it slips, the origin does not matter, u as without one. Goal: u_h = u to
/// round-off for every law, p = 1, 2, θ = 1, 0, −1, δ = 0 and 10⁻⁴, from δ = 10⁻². Parameters:
/// those of `stick_and_slip_are_exact`, s₀ = 0.004 (μ (a − s₀) = 0.006 in stick, 0.046 in
/// slip).
#[test]
fn the_friction_law_measures_slip_from_its_origin() {
    let (b, s0) = (0.01, 0.004);
    for law in LAWS {
        for (case, a) in [("stick", 0.01), ("slip", 0.05)] {
            // a shear strain of 1 slips: its shear is the threshold
            let (_, threshold) = exact(law, 1.0, b);
            let shear = (MU * (a - s0)).min(threshold);
            let sticks = shear < threshold;
            assert_eq!(case == "stick", sticks, "{law:?}: the data make it {case}");
            let u_exact = move |x: [f64; 2]| match sticks {
                true => [(a - s0) * x[1] + s0, -b * x[1]],
                false => [threshold / MU * x[1] + a - threshold / MU, -b * x[1]],
            };
            for (label, problem, solution) in stick_slip_solves(law, (a, b, shear), Some(s0)) {
                let u = problem.displacement(&problem.discretise(), &solution.x);
                let error = common::max_nodal_error(&problem.mesh.points, &u, u_exact);
                println!("{case} {label}: max nodal error {error:.1e}");
                assert!(error <= 1e-12 * a, "{case} {label}: error {error}");
            }
        }
    }
}

/// The weight of the block on the incline [N/m³].
const WEIGHT: f64 = 1e4;

/// A unit square block (E = 10⁶ Pa, ν = 0.2) on an n × n grid of degree `order` under its own
/// weight tilted by α: f = ρg (sin α, −cos α), no Dirichlet condition.
fn incline(alpha: f64, n: usize, order: usize) -> Problem {
    let mesh = unit_square(n, order);
    Problem {
        materials: vec![Material { young: 1e6, poisson: 0.2, density: 1.0 }; mesh.n_cells()],
        dirichlet: vec![],
        neumann: vec![],
        body_force: BodyForce::Field(Arc::new(move |_| [WEIGHT * alpha.sin(), -WEIGHT * alpha.cos()])),
        mesh,
    }
}

/// The Coulomb joint of the block's base.
fn incline_joint(friction: f64) -> ContactJoint {
    ContactJoint::uniform(vec![BOTTOM], Vec::new(), JointLaw::Coulomb { friction }, crate::nitsche_parameters())
}

/// Block on an incline. Source: Coulomb's law. A unit square block rests with its base on a
/// rigid plane and carries only its own weight, tilted by α against the plane's normal,
/// f = ρg (sin α, −cos α): the plane inclined at α. Goal: with F = tan 30° it sticks at
/// α = 25° (Newton converges; the base does not slide: |u^t| ≤ 10⁻³ max|u|) and cannot hold at
/// α = 35° (no equilibrium: Newton stops with an error instead of an answer). Parameters:
/// E = 10⁶ Pa, ν = 0.2, ρg = 10⁴ N/m³, θ = 0, γ₀ = 100, δ = 0 reached by continuation from
/// 10⁻¹ of the stress scale (at u = 0 the plain projection gives no contact stiffness, and
/// no Dirichlet condition holds the block), P1 and P2, 8 × 8 grid.
#[test]
fn block_on_an_incline_sticks_below_the_friction_angle_and_slides_above() {
    let friction = 30f64.to_radians().tan();
    for order in [1, 2] {
        for (degrees, sticks) in [(25.0, true), (35.0, false)] {
            let alpha = f64::to_radians(degrees);
            let problem = incline(alpha, 8, order);
            let disc = problem.discretise();
            let joint = incline_joint(friction);
            let delta_start = 0.1 * problem.stress_scale(&disc.topology);
            let settings = Continuation { delta: 0.0, delta_start, newton: NewtonOptions::default(), path: None };
            let result = solve_by_continuation(&problem, &disc, &joint, &settings);
            match (sticks, result) {
                (true, Ok(solution)) => {
                    let (n, t) = (solution.normal_force(), solution.tangential_force());
                    println!(
                        "P{order} α = {degrees}°: holds, {} Newton steps, N = {n:.6e}, T = {t:.6e}, stick {:.3}, slip {:.3}",
                        solution.newton_steps(),
                        solution.stick_length(),
                        solution.slip_length()
                    );
                    // ∫_Γ_C t + ∫_Ω f = 0 for the weight W = ρg |Ω|: N = W cos α, T = −W sin α
                    assert!((n - WEIGHT * alpha.cos()).abs() <= 1e-8 * WEIGHT, "P{order} α = {degrees}°: N = {n}");
                    assert!((t + WEIGHT * alpha.sin()).abs() <= 1e-8 * WEIGHT, "P{order} α = {degrees}°: T = {t}");
                    assert!(solution.stick_length() > 0.0, "P{order} α = {degrees}°: no point sticks");
                }
                (false, Err(error)) => {
                    println!("P{order} α = {degrees}°: no equilibrium: {error}");
                    assert!(
                        matches!(
                            error,
                            ContactError::Newton(
                                NewtonError::NotConverged { .. }
                                    | NewtonError::NonFinite { .. }
                                    | NewtonError::Solve { .. }
                            )
                        ),
                        "{error}"
                    );
                }
                (true, Err(error)) => panic!("P{order} α = {degrees}° must stick: {error}"),
                (false, Ok(solution)) => panic!(
                    "P{order} α = {degrees}° cannot hold, yet Newton converged ({} steps, slip length {})",
                    solution.newton_steps(),
                    solution.slip_length()
                ),
            }
        }
    }
}

/// An open joint that the smoothing alone carries is no equilibrium (docs/method.md §1.11).
/// Source: the block on a flat base (α = 0) presses with p_c = ρg = 10⁴ Pa; the smoothing
/// q(P) = −(P − δ)²/(4δ) carries it at P = δ − 2√(δ p_c) > 0 for δ > 4 p_c, the whole joint
/// open. Goal: at δ = 10⁶ Pa the solve is [`ContactError::LiftOff`] (nothing but the joint
/// holds the block, none of it in contact); at δ = 10² Pa the block stands on its whole base.
/// Parameters: those of the incline, P1, 4 × 4 grid, F = tan 30°.
#[test]
fn a_joint_that_only_the_smoothing_carries_is_no_equilibrium() {
    let problem = incline(0.0, 4, 1);
    let disc = problem.discretise();
    let joint = incline_joint(30f64.to_radians().tan());
    let solve = |delta: f64| {
        let settings = Continuation { delta, delta_start: delta, newton: NewtonOptions::default(), path: None };
        solve_by_continuation(&problem, &disc, &joint, &settings)
    };
    match solve(1e6) {
        Err(ContactError::LiftOff { contact_length, joint_length, .. }) => {
            println!("δ = 1e6: {contact_length} m of {joint_length} m in contact");
            assert!(contact_length < 0.02 * joint_length && (joint_length - 1.0).abs() < 1e-12);
        }
        other => panic!("δ = 1e6 must lift off: {:?}", other.map(|s| s.contact_length())),
    }
    let standing = solve(1e2).expect("δ = 1e2");
    assert!((standing.contact_length() - 1.0).abs() < 1e-12, "contact length {}", standing.contact_length());
}

/// The generalised Jacobian. Source: docs/method.md §1.7 (the derivative of Π_S(P^t) in P^t and,
/// through Coulomb's threshold, in P^n). Goal: away from kinks the Jacobian of the contact
/// problem equals central differences of its residual, for every law, θ = 1, 0, −1, P1 and
/// P2, with the smoothing δ > 0. Parameters: the stick–slip problem (slip data), a seeded
/// random displacement of size 10⁻², δ = 10⁻³, differences of step 10⁻⁷.
#[test]
fn the_jacobian_is_the_derivative_of_the_residual() {
    use damfem::contact::projection::Smoothing;
    use damfem::contact::ContactProblem;
    use damfem::solve::NonlinearSystem;
    use damfem::verify::rng::Rng;
    for law in LAWS {
        for order in [1, 2] {
            for theta in [1.0, 0.0, -1.0] {
                let problem = problem(2, order, 0.05, 0.01, 0.015);
                let disc = problem.discretise();
                let parameters = NitscheParameters { theta, gamma0: 1.0, ..crate::nitsche_parameters() };
                let joint = ContactJoint::uniform(vec![BOTTOM], Vec::new(), law, parameters);
                let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 1e-3 });
                let n = disc.dofs.n_free;
                let mut rng = Rng::new(17);
                let x: Vec<f64> = (0..n).map(|_| 1e-2 * rng.symmetric()).collect();
                let (mut r, mut j) = (vec![0.0; n], vec![0.0; disc.pattern.nnz()]);
                contact.evaluate(&x, &mut r, Some(&mut j));
                let h = 1e-7;
                let mut worst: f64 = 0.0;
                let scale = j.iter().map(|v| v.abs()).fold(0.0, f64::max);
                for c in 0..n {
                    let mut unit = vec![0.0; n];
                    unit[c] = 1.0;
                    let mut column = vec![0.0; n];
                    disc.pattern.multiply(&j, &unit, &mut column);
                    let (mut plus, mut minus) = (x.clone(), x.clone());
                    plus[c] += h;
                    minus[c] -= h;
                    let (mut r_plus, mut r_minus) = (vec![0.0; n], vec![0.0; n]);
                    contact.evaluate(&plus, &mut r_plus, None);
                    contact.evaluate(&minus, &mut r_minus, None);
                    for row in 0..n {
                        let fd = (r_plus[row] - r_minus[row]) / (2.0 * h);
                        worst = worst.max((fd - column[row]).abs());
                    }
                }
                println!("{law:?} P{order} θ = {theta:2}: max |J − J_fd| = {worst:.2e} of max |J| = {scale:.2e}");
                assert!(worst <= 1e-5 * scale, "{law:?} P{order} θ = {theta}: {worst} against {scale}");
            }
        }
    }
}

/// What the estimator says of the contact iterate `x` (with the linearisation point of `state`),
/// and, if asked, the sharp dual-norm reference of its residual.
fn estimate_and_reference(
    problem: &Problem,
    disc: &damfem::elasticity::Discretisation,
    joint: &ContactJoint,
    x: &[f64],
    state: &damfem::contact::Linearisation,
    with_reference: bool,
) -> (damfem::estimate::Estimate, Option<f64>) {
    let e = damfem::estimate::estimate_iterate(problem, disc, x, Some(state)).unwrap_or_else(|e| panic!("{e}"));
    let u = problem.displacement(disc, x);
    let reference = with_reference.then(|| {
        let r = sharp_reference(problem, &u, Some(joint), REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS);
        r.unwrap_or_else(|e| panic!("{e}")).norm()
    });
    (e, reference)
}

/// The estimator at the exact stick and slip solutions. Source: docs/method.md §1.7 and §4
/// (the Γ_C traction of the patch problems is the whole vector t^n ν + t^t τ). Goal: with θ = 0
/// and u_h = u, the reconstruction is equilibrated to round-off (every check, the tangential
/// traces included) and η_osc, η_flux, η_Neu and η_disc vanish to round-off, for Tresca,
/// Coulomb and Mohr–Coulomb, P1 and P2. Parameters: as `stick_and_slip_are_exact`, θ = 0,
/// δ = 0, the stress scale μa = 10⁻²; round-off asserted as 10⁻¹² of it.
#[test]
fn the_estimator_vanishes_at_the_exact_stick_and_slip_solutions() {
    let b = 0.01;
    for law in LAWS {
        for (case, a) in [("stick", 0.01), ("slip", 0.05)] {
            let (_, shear) = exact(law, a, b);
            for order in [1, 2] {
                let problem = problem(4, order, a, b, shear);
                let disc = problem.discretise();
                let joint = ContactJoint::uniform(vec![BOTTOM], Vec::new(), law, crate::nitsche_parameters());
                let settings =
                    Continuation { delta: 0.0, delta_start: 1e-2, newton: NewtonOptions::default(), path: None };
                let solution = solve_by_continuation(&problem, &disc, &joint, &settings).expect("Newton converges");
                let state = solution.linearisation(&problem, &disc);
                let (e, _) = estimate_and_reference(&problem, &disc, &joint, &solution.x, &state, false);
                let g = e.estimators.global();
                let worst = e.equilibration.worst(order);
                println!(
                    "{law:?} {case} P{order}: osc {:.1e} flux {:.1e} Neu {:.1e} disc {:.1e} reg {:.1e} lin {:.1e}; worst check {worst:.1e}",
                    g.osc, g.flux, g.neu, g.disc, g.reg, g.lin
                );
                assert!(worst < 1e-10, "{law:?} {case} P{order}: {:?}", e.equilibration);
                for (name, eta) in [("osc", g.osc), ("flux", g.flux), ("Neu", g.neu), ("disc", g.disc)] {
                    assert!(eta <= 1e-12 * MU * 0.01, "{law:?} {case} P{order}: eta_{name} = {eta:e}");
                }
            }
        }
    }
}

/// The bound with friction. Source: docs/method.md §5.2 with the Γ_C traction of §1.7. Goal:
/// on the block on the incline (it holds at α = 25°, with open, stick and slip zones), at every
/// full Newton step of the solve and at convergence, the reconstruction is equilibrated to
/// round-off and η_tot ≥ the dual norm of the residual, computed independently by the sharp
/// reference (a Riesz representative on refined meshes), which is a lower bound of that norm.
/// Parameters: as the block test, Coulomb F = tan 30°, θ = 0, Newton from u = 0 at δ = 10⁻¹ ×
/// the stress scale, then at 10⁻⁴ × it; 4 × 4 grid, P1 and P2.
#[test]
fn eta_tot_bounds_the_residual_with_friction() {
    let friction = 30f64.to_radians().tan();
    let alpha = 25f64.to_radians();
    for order in [1, 2] {
        let problem = incline(alpha, 4, order);
        let disc = problem.discretise();
        let scale = problem.stress_scale(&disc.topology);
        let (_, steps) =
            crate::full_steps::full_steps(&problem, &disc, &incline_joint(friction), &[0.1 * scale, 1e-4 * scale]);
        crate::full_steps::assert_bounds(&format!("P{order}"), &steps);
    }
}

/// A tampered tangential traction fails the checks. Source: docs/method.md §4 (the Γ_C trace of
/// σ_h is the projected traction). Goal: a reconstruction made for Coulomb F = tan 30° and
/// checked against the traction of F × 1.1 (the tangential traction changed, the normal one
/// not) shows a contact-trace violation far above round-off, while the matching check passes.
/// Parameters: the block on the incline at α = 25°, P2, 4 × 4 grid, δ = 0.
#[test]
fn a_tampered_tangential_traction_fails_the_checks() {
    use damfem::contact::nitsche::Nitsche;
    use damfem::contact::Linearisation;
    use damfem::estimate::checks::check;
    use damfem::estimate::reconstruction::reconstruct;
    let friction = 30f64.to_radians().tan();
    let alpha = 25f64.to_radians();
    let problem = incline(alpha, 4, 2);
    let disc = problem.discretise();
    let joint = incline_joint(friction);
    let settings = Continuation {
        delta: 0.0,
        delta_start: 0.1 * problem.stress_scale(&disc.topology),
        newton: NewtonOptions::default(),
        path: None,
    };
    let solution = solve_by_continuation(&problem, &disc, &joint, &settings).expect("Newton converges");
    let u = problem.displacement(&disc, &solution.x).into();
    let state = solution.linearisation(&problem, &disc);
    let rec = reconstruct(&problem, &disc.topology, &u, Some(&state)).expect("reconstruction");
    let honest = check(&problem, &disc.topology, &u, &rec, Some(&state)).contact;
    let tampered_joint = ContactJoint::uniform(
        joint.tags.clone(),
        Vec::new(),
        JointLaw::Coulomb { friction: 1.1 * friction },
        joint.laws[0].parameters,
    );
    let tampered_nitsche = Nitsche::new(&problem.mesh, &disc.topology, &problem.materials, &tampered_joint);
    let tampered = Linearisation { nitsche: &tampered_nitsche, ..state };
    let violated = check(&problem, &disc.topology, &u, &rec, Some(&tampered)).contact;
    println!("contact trace check: {honest:.1e} honest, {violated:.1e} with F × 1.1");
    assert!(honest < 1e-10, "{honest:e}");
    assert!(violated > 1e-3, "{violated:e}");
}

/// The bound on the frictional dam. Source: geo/scene_a_friction.toml (Scene A held by Coulomb
/// friction alone, F = tan 40°), solved as `damfem solve` does (its δ-continuation from 0.1 × the
/// stress scale to 10⁻⁴ × it). Goal: the reconstruction is equilibrated to round-off and
/// η_tot ≥ the sharp dual-norm reference at the solution. Parameters: P1
/// and P2, the file's mesh sizes × 2.
#[test]
fn eta_tot_bounds_the_residual_on_the_frictional_dam() {
    use damfem::scene::Scene;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("geo/scene_a_friction.toml");
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    for order in [1, 2] {
        let mesh = common::mesh_scene(&scene, order, 2.0 * scene.mesh.size_factor);
        let (problem, joint) = scene.problem(mesh).unwrap_or_else(|e| panic!("{e}"));
        let joint = joint.expect("a joint");
        let disc = problem.discretise();
        let settings = scene.continuation(&problem, &disc.topology);
        let solution = solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("{e}"));
        let state = solution.linearisation(&problem, &disc);
        let (e, reference) = estimate_and_reference(&problem, &disc, &joint, &solution.x, &state, true);
        let (g, reference, worst) = (e.estimators.global(), reference.unwrap(), e.equilibration.worst(order));
        println!(
            "P{order}: {} cells, stick {:.2} m, slip {:.2} m; eta_tot {:.4e} (osc {:.2e} flux {:.2e} Neu {:.2e} disc {:.2e} reg {:.2e} lin {:.2e}), reference {reference:.4e}, I_eff {:.3}; worst check {worst:.1e}",
            problem.mesh.n_cells(), solution.stick_length(), solution.slip_length(), g.tot, g.osc, g.flux, g.neu, g.disc, g.reg, g.lin, g.tot / reference
        );
        assert!(worst < 1e-10, "P{order}: equilibration {worst:e}");
        assert!(g.tot >= reference, "P{order}: eta_tot {} below the reference {reference}", g.tot);
    }
}

/// A manufactured Coulomb problem with a stick–slip transition inside Γ_C (docs/method.md
/// §1.7): on Ω = (0,1)², u = (φ(x) + y h(x), −b y) with φ = c (x − ½)₊³ and h = (F/μ) p_c ρ,
/// p_c = (λ + 2μ) b − λ φ' the contact pressure on y = 0 and ρ = 1 − κ (½ − x)₊³. The base
/// is closed (u^n = 0, p_c > 0); it sticks on x < ½ (u^t = φ = 0, |σ^t| = F p_c ρ < F p_c) and
/// slips on x > ½ (u^t = φ > 0, σ^t = −μ h = −F p_c). u is C² across x = ½.
mod manufactured {
    use super::{LAMBDA, MU};
    pub const B: f64 = 0.1;
    pub const C: f64 = 0.1;
    pub const KAPPA: f64 = 4.0;
    pub const F: f64 = 0.5;

    /// φ and its first three derivatives.
    fn phi(x: f64) -> [f64; 4] {
        let s = (x - 0.5).max(0.0);
        let step = if x > 0.5 { 1.0 } else { 0.0 };
        [C * s.powi(3), 3.0 * C * s * s, 6.0 * C * s, 6.0 * C * step]
    }

    /// h and its first two derivatives.
    fn h(x: f64) -> [f64; 3] {
        let [_, d1, d2, d3] = phi(x);
        let p = [(LAMBDA + 2.0 * MU) * B - LAMBDA * d1, -LAMBDA * d2, -LAMBDA * d3];
        let s = (0.5 - x).max(0.0);
        let rho = [1.0 - KAPPA * s.powi(3), 3.0 * KAPPA * s * s, -6.0 * KAPPA * s];
        let k = F / MU;
        [
            k * p[0] * rho[0],
            k * (p[1] * rho[0] + p[0] * rho[1]),
            k * (p[2] * rho[0] + 2.0 * p[1] * rho[1] + p[0] * rho[2]),
        ]
    }

    pub fn u(x: [f64; 2]) -> [f64; 2] {
        [phi(x[0])[0] + x[1] * h(x[0])[0], -B * x[1]]
    }

    pub fn grad_u(x: [f64; 2]) -> [[f64; 2]; 2] {
        let (p, hh) = (phi(x[0]), h(x[0]));
        [[p[1] + x[1] * hh[1], hh[0]], [0.0, -B]]
    }

    /// (σ_xx, σ_yy, σ_xy).
    pub fn sigma(x: [f64; 2]) -> [f64; 3] {
        let g = grad_u(x);
        let div = g[0][0] + g[1][1];
        [LAMBDA * div + 2.0 * MU * g[0][0], LAMBDA * div + 2.0 * MU * g[1][1], MU * (g[0][1] + g[1][0])]
    }

    /// f = −∇·σ = (−(λ + 2μ)(φ'' + y h''), −(λ + μ) h').
    pub fn f(x: [f64; 2]) -> [f64; 2] {
        let (p, hh) = (phi(x[0]), h(x[0]));
        [-(LAMBDA + 2.0 * MU) * (p[2] + x[1] * hh[2]), -(LAMBDA + MU) * hh[1]]
    }
}

/// (h, H¹ error, stick length, slip length) of the manufactured problem on an n × n grid.
fn solve_manufactured(n: usize, order: usize) -> (f64, f64, f64, f64) {
    use damfem::fem::norms::errors;
    use manufactured as m;
    let mesh = unit_square(n, order);
    let side = |sign: f64| {
        Traction::Field(Arc::new(move |x| {
            let s = m::sigma(x);
            [sign * s[0], sign * s[2]]
        }))
    };
    let problem = Problem {
        materials: vec![Material::from_lame(LAMBDA, MU); mesh.n_cells()],
        dirichlet: vec![Dirichlet { tag: TOP, fix: [true; 2], value: Arc::new(m::u) }],
        neumann: vec![Neumann { tag: LEFT, traction: side(-1.0) }, Neumann { tag: RIGHT, traction: side(1.0) }],
        body_force: BodyForce::Field(Arc::new(m::f)),
        mesh,
    };
    let disc = problem.discretise();
    let joint = ContactJoint::uniform(
        vec![BOTTOM],
        Vec::new(),
        JointLaw::Coulomb { friction: m::F },
        crate::nitsche_parameters(),
    );
    let settings = Continuation { delta: 0.0, delta_start: 0.1, newton: NewtonOptions::default(), path: None };
    let solution =
        solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("n = {n} P{order}: {e}"));
    let u = problem.displacement(&disc, &solution.x);
    let (_, h1) = errors(&problem.mesh, &u, m::u, m::grad_u);
    (1.0 / n as f64, h1, solution.stick_length(), solution.slip_length())
}

/// Rates with a stick–slip transition. Source: the manufactured solution above. Goal: the H¹
/// error of u_h converges at the optimal rates h^p (measured 0.998 and 1.984), and the stick
/// and slip zones converge to [0, ½] and [½, 1]. Parameters: λ = μ = 1, b = 0.1, c = 0.1, κ = 4, F = 0.5, θ = 0, γ₀ = 100,
/// δ = 0 reached from 0.1; P1 on n = 8 … 64, P2 on n = 4 … 32; rates fitted over the four meshes.
#[test]
fn h1_rates_with_a_stick_slip_transition() {
    for (order, sizes, min_rate) in [(1, [8, 16, 32, 64], 0.95), (2, [4, 8, 16, 32], 1.9)] {
        let runs: Vec<_> = sizes.iter().map(|&n| solve_manufactured(n, order)).collect();
        for r in &runs {
            println!("P{order} h = {:.4}: |e|_H1 = {:.3e}, stick {:.4}, slip {:.4}", r.0, r.1, r.2, r.3);
        }
        // the stick margin F p_c κ (½ − x)³ is cubic at the transition, so the zones converge
        // more slowly than u_h; measured errors 0.29 … 0.004 (P1) and 0.18 … 0.025 (P2)
        let zone: Vec<f64> = runs.iter().map(|r| (r.2 - 0.5).abs().max((r.3 - 0.5).abs())).collect();
        assert!(zone.windows(2).all(|w| w[1] <= 0.6 * w[0]) && zone[3] <= 0.03, "P{order}: zone errors {zone:?}");
        let h: Vec<f64> = runs.iter().map(|r| r.0).collect();
        let e: Vec<f64> = runs.iter().map(|r| r.1).collect();
        let rate = damfem::adapt::history::loglog_slope(&h.iter().copied().zip(e.iter().copied()).collect::<Vec<_>>());
        println!("P{order}: fitted H1 rate {rate:.3}");
        assert!(rate >= min_rate, "P{order}: H1 rate {rate} < {min_rate}");
    }
}

/// The local displacement of the cell that owns contact face k.
fn face_local(contact: &damfem::contact::ContactProblem, k: usize, u_full: &[f64]) -> Vec<f64> {
    let mut dofs = Vec::new();
    damfem::fem::sparse::vector_dofs(contact.problem.mesh.cell(contact.nitsche.faces[k].cell), &mut dofs);
    dofs.iter().map(|&g| u_full[g]).collect()
}

/// −∫_F t_lin · φ_i on face k over `rule` (θ = 0): the linearised traction t(u_prev) +
/// t'(u_prev) w tested by the local basis, w = u − u_prev the increment `step`.
fn linearised_face_residual(
    nitsche: &damfem::contact::nitsche::Nitsche,
    smoothing: damfem::contact::projection::Smoothing,
    k: usize,
    (u_prev, step): (&FaceDisplacement, &FaceDisplacement),
    rule: &[(f64, f64)],
) -> Vec<f64> {
    let mut out = vec![0.0; nitsche.n_local()];
    for &(s, w) in rule {
        let point = nitsche.point(k, s);
        let t = nitsche.linearised_traction(k, &point, u_prev, step, smoothing);
        for (i, r) in out.iter_mut().enumerate() {
            // φ_i e_a = (φ_i e_a · ν) ν + (φ_i e_a · τ) τ
            let nu = nitsche.faces[k].direction;
            let (t_n, t_t) = (t[0] * nu[0] + t[1] * nu[1], t[1] * nu[0] - t[0] * nu[1]);
            *r -= (t_n * point.u_n[i] + t_t * point.u_t[i]) * w;
        }
    }
    out
}

/// Newton's face integrals are exact where the normal traction and the clamp are both smoothed.
/// Source: docs/method.md §1.6 and §5.2: the reconstruction integrates the linearised traction
/// on its own split of each face (at the kinks of u^{k−1} and of u^k), so the bound needs the
/// same integrals as the Newton step, which splits at the kinks of u^{k−1} only. Goal: on every
/// contact face, R_F(u^{k−1}) + J_F(u^{k−1})(u^k − u^{k−1}) equals −∫_F t_lin · φ_i computed
/// with every piece between the cuts of both iterates cut again into 32, to 10⁻¹² of its
/// largest entry, and so does the linearised face residual of the refinement round
/// (`Nitsche::linearised_face_terms`, from P_γ(u^{k−1}) and the increment), for every law, P1 and P2, at points where |P_γ| < δ and |S ∓ P^t| < δ
/// (there Coulomb's tangential traction has degree 4p along the face). Parameters: the
/// stick–slip problem (slip data) on a 4 × 4 grid, θ = 0, γ₀ = 1, u^{k−1} a seeded random
/// displacement of size 10⁻², δ = max |P_γ(u^{k−1})|, u^k − u^{k−1} another random field.
#[test]
fn the_face_integrals_are_exact_where_both_projections_are_smoothed() {
    use damfem::contact::projection::Smoothing;
    use damfem::contact::ContactProblem;
    use damfem::verify::rng::Rng;
    for law in LAWS {
        for order in [1, 2] {
            let problem = problem(4, order, 0.05, 0.01, 0.015);
            let disc = problem.discretise();
            let parameters = NitscheParameters { gamma0: 1.0, ..crate::nitsche_parameters() };
            let joint = ContactJoint::uniform(vec![BOTTOM], Vec::new(), law, parameters);
            let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 1.0 });
            let mut rng = Rng::new(17);
            let mut random = || (0..disc.dofs.n_free).map(|_| 1e-2 * rng.symmetric()).collect::<Vec<f64>>();
            let (x_prev, x) = (random(), random());
            contact.set_delta(contact.max_abs_p_gamma(&x_prev));
            let (nitsche, smoothing) = (&contact.nitsche, contact.smoothing);
            let (u_full, u_prev_full) = (disc.dofs.expand(&x), disc.dofs.expand(&x_prev));
            let (mut both, mut worst) = (0, 0.0f64);
            let n = nitsche.n_local();
            for k in 0..nitsche.faces.len() {
                let (values, values_prev) = (face_local(&contact, k, &u_full), face_local(&contact, k, &u_prev_full));
                let (u, u_prev) = (nitsche.local(k, &values, None), nitsche.local(k, &values_prev, None));
                let step = nitsche.increment(k, &values, None, &values_prev);
                let (mut r, mut j) = (vec![0.0; n], vec![0.0; n * n]);
                nitsche.face_terms(k, &u_prev, smoothing, false, &mut r, Some(&mut j));
                let newton: Vec<f64> = (0..n)
                    .map(|i| r[i] + (0..n).map(|c| j[i * n + c] * (values[c] - values_prev[c])).sum::<f64>())
                    .collect();
                let mut refinement = vec![0.0; n];
                nitsche.linearised_face_terms(k, &u_prev, &u, &step, smoothing, &mut refinement);
                let mut cuts = nitsche.kinks(k, &u, smoothing);
                cuts.extend(nitsche.kinks(k, &u_prev, smoothing));
                cuts.sort_by(f64::total_cmp);
                let fine: Vec<f64> = cuts
                    .windows(2)
                    .flat_map(|w| (0..32).map(move |i| w[0] + (w[1] - w[0]) * i as f64 / 32.0))
                    .collect();
                let fine = [fine, vec![1.0]].concat();
                let reference =
                    linearised_face_residual(nitsche, smoothing, k, (&u_prev, &step), &nitsche.split_rule(k, &fine));
                let size = reference.iter().map(|v| v.abs()).fold(0.0, f64::max);
                for computed in [&newton, &refinement] {
                    let error = computed.iter().zip(&reference).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                    worst = worst.max(error / size);
                }
                for (s, _) in nitsche.quadrature(k, &u_prev, smoothing) {
                    let point = nitsche.point(k, s);
                    let p_n = nitsche.p_gamma(k, &point, &u_prev);
                    let (p_t, t) =
                        (nitsche.p_tangential(k, &point, &u_prev), nitsche.tangential(k, &point, &u_prev, smoothing));
                    let clamped =
                        (t.threshold - p_t).abs() < smoothing.delta || (p_t + t.threshold).abs() < smoothing.delta;
                    both += usize::from(p_n.abs() < smoothing.delta && clamped);
                }
            }
            println!("{law:?} P{order}: {both} points with both smoothed, largest relative difference {worst:.1e}");
            assert!(both > 0, "{law:?} P{order}: no point where both projections are smoothed");
            assert!(worst <= 1e-12, "{law:?} P{order}: Newton's face integrals differ by {worst:e}");
        }
    }
}
