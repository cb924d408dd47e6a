//! Verification of frictional Nitsche contact (docs/method.md §1.7).

use damfem::contact::nitsche::NitscheParameters;
use damfem::contact::{solve_by_continuation, ContactJoint, Continuation, JointLaw};
use damfem::elasticity::{BodyForce, Dirichlet, Material, Neumann, Problem, Traction};
use damfem::mesh::structured::{unit_square, BOTTOM, LEFT, RIGHT, TOP};
use damfem::solve::{NewtonError, NewtonOptions};
use std::sync::Arc;

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
    let laws = [
        JointLaw::Tresca { threshold: 0.02 },
        JointLaw::Coulomb { friction: 0.5 },
        JointLaw::MohrCoulomb { friction: 0.3, cohesion: 0.005 },
    ];
    let b = 0.01;
    for law in laws {
        for (case, a) in [("stick", 0.01), ("slip", 0.05)] {
            let (u_exact, shear) = exact(law, a, b);
            assert_eq!(case == "stick", shear == MU * a, "{law:?}: the data make it {case}");
            for order in [1, 2] {
                for theta in [1.0, 0.0, -1.0] {
                    for delta in [0.0, 1e-4] {
                        let problem = problem(4, order, a, b, shear);
                        let disc = problem.discretise();
                        let parameters = NitscheParameters { theta, ..Default::default() };
                        let joint = ContactJoint { tags: vec![BOTTOM], law, parameters };
                        let settings = Continuation { delta, delta_start: 1e-2, newton: NewtonOptions::default() };
                        let solution = solve_by_continuation(&problem, &disc, &joint, &settings)
                            .unwrap_or_else(|e| panic!("{law:?} {case} P{order} θ = {theta} δ = {delta}: {e}"));
                        let u = problem.displacement(&disc, &solution.x);
                        let error = problem
                            .mesh
                            .points
                            .iter()
                            .zip(&u)
                            .map(|(x, v)| {
                                let e = u_exact(*x);
                                (v[0] - e[0]).abs().max((v[1] - e[1]).abs())
                            })
                            .fold(0.0, f64::max);
                        println!(
                            "{law:?} {case} P{order} θ = {theta:2} δ = {delta:.0e}: {} Newton steps, max nodal error {error:.1e}",
                            solution.newton_steps()
                        );
                        assert!(error <= 1e-12 * a, "{law:?} {case} P{order} θ = {theta} δ = {delta}: error {error}");
                        let (stick, slip) = (solution.stick_length(), solution.slip_length());
                        let expected = if case == "stick" { (1.0, 0.0) } else { (0.0, 1.0) };
                        assert!(
                            (stick - expected.0).abs() < 1e-12 && (slip - expected.1).abs() < 1e-12,
                            "{law:?} {case}: stick {stick}, slip {slip}"
                        );
                    }
                }
            }
        }
    }
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
            let weight = 1e4;
            let mesh = unit_square(8, order);
            let problem = Problem {
                materials: vec![Material { young: 1e6, poisson: 0.2, density: 1.0 }; mesh.n_cells()],
                dirichlet: vec![],
                neumann: vec![],
                body_force: BodyForce::Field(Arc::new(move |_| [weight * alpha.sin(), -weight * alpha.cos()])),
                mesh,
            };
            let disc = problem.discretise();
            let joint = ContactJoint {
                tags: vec![BOTTOM],
                law: JointLaw::Coulomb { friction },
                parameters: Default::default(),
            };
            let delta_start = 0.1 * problem.stress_scale(&disc.topology);
            let settings = Continuation { delta: 0.0, delta_start, newton: NewtonOptions::default() };
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
                    assert!((n - weight * alpha.cos()).abs() <= 1e-8 * weight, "P{order} α = {degrees}°: N = {n}");
                    assert!((t + weight * alpha.sin()).abs() <= 1e-8 * weight, "P{order} α = {degrees}°: T = {t}");
                    assert!(solution.stick_length() > 0.0, "P{order} α = {degrees}°: no point sticks");
                }
                (false, Err(error)) => {
                    println!("P{order} α = {degrees}°: no equilibrium: {error}");
                    assert!(
                        matches!(
                            error,
                            NewtonError::NotConverged { .. }
                                | NewtonError::NonFinite { .. }
                                | NewtonError::Solve { .. }
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
    let laws = [
        JointLaw::Tresca { threshold: 0.02 },
        JointLaw::Coulomb { friction: 0.5 },
        JointLaw::MohrCoulomb { friction: 0.3, cohesion: 0.005 },
    ];
    for law in laws {
        for order in [1, 2] {
            for theta in [1.0, 0.0, -1.0] {
                let problem = problem(2, order, 0.05, 0.01, 0.015);
                let disc = problem.discretise();
                let parameters = NitscheParameters { theta, gamma0: 1.0, ..Default::default() };
                let joint = ContactJoint { tags: vec![BOTTOM], law, parameters };
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
