//! Uplift in the joint (docs/method.md §1.8): the pore pressure acts on the effective normal
//! stress, and the crack it fills at the heel is found by a fixed point.

use crate::common;
use damfem::contact::nitsche::NitscheParameters;
use damfem::contact::resultant::JointLine;
use damfem::contact::uplift::Uplift;
use damfem::contact::{solve_by_continuation, ContactJoint, Continuation, JointLaw};
use damfem::elasticity::{BodyForce, Dirichlet, Material, Neumann, Problem, Traction};
use damfem::io::gmsh::{mesh_geo, MeshOptions};
use damfem::mesh::structured::{unit_square, BOTTOM, LEFT, RIGHT, TOP};
use damfem::scene::Scene;
use damfem::solve::NewtonOptions;
use std::sync::Arc;

/// Uniform uplift. Source: docs/method.md §1.8 with p_u constant. Goal: on a block pressed and
/// sheared by its top (u = (a y, −b y), closed and sticking base), a uniform pore pressure
/// lowers the contact pressure by exactly p_u, p_c = (λ + 2μ) b − p_u, and leaves u_h = u: the
/// total normal stress is fixed by the displacement. Checked to round-off for frictionless
/// and Coulomb joints, P1 and P2, θ = 1, 0, −1; the uplift force is p_u |Γ_C|.
/// Parameters: λ = μ = 1, a = b = 0.01, p_u = 0.005 (a sixth of (λ + 2μ) b), F = 0.5 (S = 0.0125
/// > μ a: it sticks), γ₀ = 100, 4 × 4 grid, δ = 0 reached from 10⁻².
#[test]
fn uniform_uplift_lowers_the_contact_pressure_by_exactly_p_u() {
    let (lambda, mu, a, b, p_u) = (1.0, 1.0, 0.01, 0.01, 0.005);
    let uplift = Uplift {
        line: JointLine { heel: [0.0, 0.0], along: [1.0, 0.0], length: 1.0 },
        upstream: p_u,
        downstream: p_u,
        drains: None,
        crack_filled: false,
        crack: 0.0,
    };
    for law in [JointLaw::Frictionless, JointLaw::Coulomb { friction: 0.5 }] {
        let shear = if law.has_friction() { mu * a } else { 0.0 };
        for order in [1, 2] {
            for theta in [1.0, 0.0, -1.0] {
                let mesh = unit_square(4, order);
                let (sxx, sxy) = (-lambda * b, shear);
                let top = if law.has_friction() { [a, -b] } else { [0.0, -b] };
                let problem = Problem {
                    materials: vec![Material::from_lame(lambda, mu); mesh.n_cells()],
                    dirichlet: vec![Dirichlet { tag: TOP, fix: [true; 2], value: Arc::new(move |_| top) }],
                    neumann: vec![
                        Neumann { tag: LEFT, traction: Traction::Constant([-sxx, -sxy]) },
                        Neumann { tag: RIGHT, traction: Traction::Constant([sxx, sxy]) },
                    ],
                    body_force: BodyForce::None,
                    mesh,
                };
                let disc = problem.discretise();
                let parameters = NitscheParameters { theta, ..Default::default() };
                let joint = ContactJoint { tags: vec![BOTTOM], law, parameters, uplift: Some(uplift.clone()) };
                let settings = Continuation { delta: 0.0, delta_start: 1e-2, newton: NewtonOptions::default() };
                let solution =
                    solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("{e}"));
                let u = problem.displacement(&disc, &solution.x);
                let error = common::max_nodal_error(&problem.mesh.points, &u, |x| [top[0] * x[1], top[1] * x[1]]);
                let expected = (lambda + 2.0 * mu) * b - p_u;
                let pressure = solution.faces.iter().map(|f| (f.pressure - expected).abs()).fold(0.0, f64::max);
                println!("{law:?} P{order} θ = {theta:2}: max nodal error {error:.1e}, max |p_c − ((λ+2μ)b − p_u)| {pressure:.1e}");
                assert!(error <= 1e-12 * a, "{law:?} P{order} θ = {theta}: error {error}");
                assert!(pressure <= 1e-12 * expected, "{law:?} P{order} θ = {theta}: pressure off by {pressure}");
                assert!((solution.uplift_force() - p_u).abs() <= 1e-14, "uplift force {}", solution.uplift_force());
            }
        }
    }
}

/// The dam with uplift. Source: geo/scene_a_uplift.toml (Scene A held by Coulomb friction,
/// reservoir at 45 m, drains 5 m from the heel, the crack filled with reservoir pressure).
/// Goal: global equilibrium with the uplift, N + U = W (the weight) and T = −the thrust
/// ρ_w g H_w²/2, to 10⁻⁸, so that FS_LE = F (W − U)/T; the crack–uplift fixed point settles with a crack at the heel; the
/// estimator with uplift is equilibrated to round-off and bounds the dual-norm reference
/// (the uplift enters both as the Γ_C traction −p_u ν). Parameters: P1 and P2, the file's mesh
/// sizes × 2; the reference on the mesh refined once.
#[test]
fn the_dam_with_uplift_balances_weight_thrust_and_uplift() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("geo/scene_a_uplift.toml");
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let weight = 2400.0 * 9.81 * (40.0 + 5.0) / 2.0 * 50.0;
    let thrust = 1000.0 * 9.81 * 45.0 * 45.0 / 2.0;
    for order in [1, 2] {
        let m = &scene.mesh;
        let options =
            MeshOptions { order, size_factor: 2.0, size_min: m.size_min, size_max: m.size_max, algorithm: m.algorithm };
        let mesh = mesh_geo(&scene.geometry, &options, false, false).unwrap_or_else(|e| panic!("{e}"));
        let (problem, joint) = scene.problem(mesh).unwrap_or_else(|e| panic!("{e}"));
        let joint = joint.expect("a joint");
        let disc = problem.discretise();
        let solution = solve_by_continuation(&problem, &disc, &joint, &scene.continuation(&problem, &disc.topology))
            .unwrap_or_else(|e| panic!("{e}"));
        let (n, t, u) = (solution.normal_force(), solution.tangential_force(), solution.uplift_force());
        let crack = solution.crack.expect("the crack is iterated");
        let state = solution.linearisation(&problem, &disc);
        let e = damfem::estimate::estimate_iterate(&problem, &disc, &solution.x, Some(&state))
            .unwrap_or_else(|e| panic!("{e}"));
        let u_h = problem.displacement(&disc, &solution.x);
        // the residual of the problem that was solved: with the crack the fixed point found
        let solved = ContactJoint { uplift: solution.nitsche.uplift.clone(), ..joint.clone() };
        let reference = damfem::verify::dual_norm::residual_dual_norm(&problem, &u_h, Some(&solved), 1)
            .unwrap_or_else(|e| panic!("{e}"));
        let (eta, worst) = (e.estimators.global().tot, e.equilibration.worst(order));
        println!(
            "P{order}: N {n:.6e} U {u:.6e} (N + U − W = {:.1e}), T {t:.6e}; crack {:.3} m after {} solves; eta_tot {eta:.4e}, reference {reference:.4e}, worst check {worst:.1e}",
            n + u - weight,
            crack.length,
            crack.iterations
        );
        assert!((n + u - weight).abs() <= 1e-8 * weight, "P{order}: N + U = {} against W = {weight}", n + u);
        assert!((t + thrust).abs() <= 1e-8 * thrust, "P{order}: T = {t} against the thrust {thrust}");
        // c = 0 on a horizontal joint: FS_LE = F N / T with N = W − U
        let fs = solution.sliding_safety_factor().expect("a frictional joint");
        let expected = 0.8391 * (weight - u) / thrust;
        assert!((fs - expected).abs() <= 1e-8 * expected, "P{order}: FS_LE {fs} against {expected}");
        assert!(crack.length > 0.0 && crack.change <= 1e-6 * 40.0, "P{order}: {crack:?}");
        assert!(worst < 1e-10, "P{order}: equilibration {worst:e}");
        assert!(eta >= reference, "P{order}: eta_tot {eta} below the reference {reference}");
    }
}

/// Strength reduction against the exact answer. Source: docs/method.md §1.7 (equilibrium of a
/// body held by a horizontal joint on a rigid foundation, c = 0): the joint holds the dam with
/// F/k exactly while k ≤ F N / T, N = W − U. Goal: FS_SR's bracket contains F (W − U)/T and is
/// within 0.5 % of it, with and without uplift, on two meshes and both degrees. Parameters:
/// geo/scene_a_uplift.toml with crack = "ignore" (U of the uncracked diagram), and without its
/// [uplift] table (U = 0), mesh sizes × 2 and × 4, P1 and P2, bisection to 0.2 %.
#[test]
fn strength_reduction_finds_the_exact_sliding_factor() {
    use damfem::contact::strength_reduction;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("geo/scene_a_uplift.toml");
    let mut with_uplift = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    with_uplift.uplift.as_mut().expect("[uplift]").crack = damfem::scene::CrackKind::Ignore;
    let mut without_uplift = with_uplift.clone();
    without_uplift.uplift = None;
    let weight = 2400.0 * 9.81 * (40.0 + 5.0) / 2.0 * 50.0;
    let thrust = 1000.0 * 9.81 * 45.0 * 45.0 / 2.0;
    for scene in [with_uplift, without_uplift] {
        for order in [1, 2] {
            for size_factor in [4.0, 2.0] {
                let m = &scene.mesh;
                let options = MeshOptions {
                    order,
                    size_factor,
                    size_min: m.size_min,
                    size_max: m.size_max,
                    algorithm: m.algorithm,
                };
                let mesh = mesh_geo(&scene.geometry, &options, false, false).unwrap_or_else(|e| panic!("{e}"));
                let (problem, joint) = scene.problem(mesh).unwrap_or_else(|e| panic!("{e}"));
                let joint = joint.expect("a joint");
                let uplift = joint.uplift.as_ref().map_or(0.0, |up| up.force(0.0));
                let disc = problem.discretise();
                let settings = scene.continuation(&problem, &disc.topology);
                let sr = strength_reduction(&problem, &disc, &joint, &settings, 2e-3).unwrap_or_else(|e| panic!("{e}"));
                let exact = 0.8391 * (weight - uplift) / thrust;
                println!(
                    "U = {uplift:.4e}, P{order} size {size_factor}: FS_SR in [{:.4}, {:.4}] after {} solves; F (W − U)/T = {exact:.4}",
                    sr.held, sr.failed, sr.solves
                );
                assert!(
                    sr.held <= exact * (1.0 + 1e-9) && sr.failed >= exact * (1.0 - 1e-9),
                    "P{order}: bracket {sr:?} misses {exact}"
                );
                assert!(sr.held >= 0.995 * exact, "P{order}: FS_SR {} more than 0.5 % below {exact}", sr.held);
            }
        }
    }
}
