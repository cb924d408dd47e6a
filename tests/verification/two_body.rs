//! Verification of two-body Nitsche contact across a joint (docs/method.md §1.10): the patch test
//! on matching and non-matching sides, the optimal rate on non-matching sides, and the limit
//! of a very stiff foundation.

use crate::common;

use damfem::contact::nitsche::NitscheParameters;
use damfem::contact::projection::Smoothing;
use damfem::contact::{continuation, ContactJoint, ContactProblem, CrackRule, JointLaw, JointLine, Uplift};
use damfem::elasticity::{BodyForce, Dirichlet, Material, Neumann, Problem, Traction, VectorFn};
use damfem::fem::norms::errors;
use damfem::mesh::structured::{rectangle, two_blocks, BOTTOM, JOINT, JOINT_LOWER, LEFT, LOWER, RIGHT, TOP};
use damfem::solve::NewtonOptions;
use std::sync::Arc;

/// The joint between the blocks of [`two_blocks`], the upper block's side the slave.
pub(crate) fn joint(theta: f64) -> ContactJoint {
    let parameters = NitscheParameters { theta, ..crate::nitsche_parameters() };
    ContactJoint::uniform(vec![JOINT], vec![JOINT_LOWER], JointLaw::Frictionless, parameters)
}

/// The materials of the cells of `mesh`: `lower` in the lower block, `upper` in the upper one.
fn materials(mesh: &damfem::mesh::Mesh, lower: Material, upper: Material) -> Vec<Material> {
    mesh.cell_tags.iter().map(|&t| if t == LOWER { lower } else { upper }).collect()
}

/// Newton from u = 0 at δ = 10⁻¹² (relative to the stresses of these cases, ~10⁻²): the
/// free unknowns.
fn solve(problem: &Problem, joint: &ContactJoint) -> Vec<f64> {
    solve_at(problem, joint, 1e-12)
}

/// Newton along the δ path from 10⁻³ down to `delta` (0: the plain projection), from u = 0.
fn solve_at(problem: &Problem, joint: &ContactJoint, delta: f64) -> Vec<f64> {
    let disc = problem.discretise();
    let mut contact = ContactProblem::new(problem, &disc, joint, Smoothing { delta });
    let x0 = vec![0.0; disc.dofs.n_free];
    let (x, _) =
        continuation(&mut contact, delta, 1e-3, x0, &NewtonOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    x
}

/// The pressed blocks of the two-body patch test: lower block E₂ = 3, ν₂ = 0.3 on
/// [0,1] × [0,½], upper block E₁ = 1, ν₁ = 0.2, u = 0 at y = 0 and u = (0, −b(1 + tilt x)),
/// b = 10⁻², at y = 1. With tilt = 0 the lateral tractions ±(λ_i ε_yy,i, 0) of uniaxial strain
/// keep ε_xx = 0, and the solution, u = (0, u_y(y)) with ε_yy,i = −p/(λ_i + 2μ_i) and
/// p = b / Σ_i ½/(λ_i + 2μ_i), lies in V_h; otherwise the sides are free. Returns the problem,
/// p and u_y.
pub(crate) fn pressed_blocks(nx: [usize; 2], order: usize, tilt: f64) -> (Problem, f64, impl Fn([f64; 2]) -> f64) {
    let b = 1e-2;
    let (lower, upper) =
        (Material { young: 3.0, poisson: 0.3, density: 0.0 }, Material { young: 1.0, poisson: 0.2, density: 0.0 });
    let ((l2, mu2), (l1, mu1)) = (lower.lame(), upper.lame());
    let (m2, m1) = (l2 + 2.0 * mu2, l1 + 2.0 * mu1);
    let p = b / (0.5 / m2 + 0.5 / m1);
    let (e2, e1) = (-p / m2, -p / m1);
    let exact = move |x: [f64; 2]| if x[1] <= 0.5 { e2 * x[1] } else { 0.5 * e2 + e1 * (x[1] - 0.5) };
    // σ_xx on each block, from the cell's side of y = ½
    let sigma_xx = move |y: f64| if y < 0.5 { l2 * e2 } else { l1 * e1 };
    let side = |sign: f64| -> VectorFn { Arc::new(move |x: [f64; 2]| [sign * sigma_xx(x[1]), 0.0]) };
    let neumann = if tilt == 0.0 {
        vec![
            Neumann { tag: LEFT, traction: Traction::Field(side(-1.0)) },
            Neumann { tag: RIGHT, traction: Traction::Field(side(1.0)) },
        ]
    } else {
        Vec::new()
    };
    let mesh = two_blocks(nx[0], nx[1], 2, 0.5, order);
    let problem = Problem {
        materials: materials(&mesh, lower, upper),
        dirichlet: vec![
            Dirichlet { tag: BOTTOM, fix: [true; 2], value: Arc::new(|_| [0.0; 2]) },
            Dirichlet { tag: TOP, fix: [true; 2], value: Arc::new(move |x| [0.0, -b * (1.0 + tilt * x[0])]) },
        ],
        neumann,
        body_force: BodyForce::None,
        mesh,
    };
    (problem, p, exact)
}

/// Two-body patch test. Source: docs/method.md §1.10: two stacked
/// blocks of different materials pressed together (bonded-equivalent compression).
/// Goal: u_h = u to round-off on matching and on non-matching sides, for θ = 1, 0, −1, P1 and
/// P2: the exact solution lies in V_h on each block and satisfies the Nitsche equations.
/// Parameters: [`pressed_blocks`] without tilt.
#[test]
fn two_body_patch_test_is_exact_on_matching_and_non_matching_sides() {
    for order in [1, 2] {
        for (nx_lower, nx_upper) in [(4, 4), (3, 5)] {
            for theta in [1.0, 0.0, -1.0] {
                let (problem, _, exact) = pressed_blocks([nx_lower, nx_upper], order, 0.0);
                let x = solve(&problem, &joint(theta));
                let u = problem.displacement(&problem.discretise(), &x);
                let error = (problem.mesh.points.iter().zip(&u))
                    .map(|(x, v)| v[0].abs().max((v[1] - exact(*x)).abs()))
                    .fold(0.0, f64::max);
                println!(
                    "P{order}, {nx_lower} | {nx_upper} cells along the joint, θ = {theta}: max nodal error {error:.2e}"
                );
                assert!(error < 1e-12, "P{order} {nx_lower}|{nx_upper} θ = {theta}: error {error:.3e}");
            }
        }
    }
}

/// Uniform uplift across a joint between two bodies. Source: docs/method.md §1.8 and §1.10 (the
/// pore pressure acts on the effective normal stress on both sides of the joint). Goal: the
/// pressed blocks of the patch test with a uniform p_u in the joint keep the same displacement
/// (the total traction −p is set by the data), and the contact pressure of every face drops by
/// exactly p_u, to round-off, P1 and P2, on matching and non-matching sides.
/// Parameters: the data of the patch test; p_u = 0.4 p, no drains, the crack's pressure
/// ignored; θ = 0.
#[test]
fn two_body_uniform_uplift_drops_the_contact_pressure_by_p_u() {
    let p_u = 0.4 * pressed_blocks([1, 1], 1, 0.0).1;
    let uplift = Uplift {
        line: JointLine::new([0.0, 0.5], [1.0, 0.5]),
        upstream: p_u,
        downstream: p_u,
        drains: None,
        rule: CrackRule::Kept { prior: 0.0 },
        crack: 0.0,
    };
    for order in [1, 2] {
        for (nx_lower, nx_upper) in [(4, 4), (3, 5)] {
            let (problem, p, exact) = pressed_blocks([nx_lower, nx_upper], order, 0.0);
            let joint = joint(0.0).with_uplift(uplift.clone());
            let disc = problem.discretise();
            let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 0.0 });
            let x0 = vec![0.0; disc.dofs.n_free];
            let (x, _) =
                continuation(&mut contact, 0.0, 1e-3, x0, &NewtonOptions::default()).unwrap_or_else(|e| panic!("{e}"));
            let u = problem.displacement(&disc, &x);
            let error = (problem.mesh.points.iter().zip(&u))
                .map(|(x, v)| v[0].abs().max((v[1] - exact(*x)).abs()))
                .fold(0.0, f64::max);
            let drop = contact.face_states(&x).iter().map(|f| (f.pressure - (p - p_u)).abs()).fold(0.0, f64::max);
            println!(
                "P{order}, {nx_lower} | {nx_upper} cells along the joint: max nodal error {error:.2e}, \
                 max |p_c − (p − p_u)| {drop:.2e} (p = {p:.4e})"
            );
            assert!(error < 1e-12, "P{order} {nx_lower}|{nx_upper}: error {error:.3e}");
            assert!(drop < 1e-12 * p / 1e-2, "P{order} {nx_lower}|{nx_upper}: p_c off by {drop:.3e}");
        }
    }
}

/// Stick and slip across a frictional joint between two blocks. Source: docs/method.md §1.10
/// with §1.7 (the stick and slip cases of a rigid foundation, the foundation made a second
/// block). Goal: u_h = u to round-off, P1 and P2, matching and non-matching sides: in stick with
/// the upper block held by the joint alone (K singular: the sparse LU path), in slip with the
/// upper block pressed and sheared at its top (the Schur path).
/// Parameters: the blocks of the patch test; the layer strains ε_yy,i = −p/(λ_i+2μ_i) and shears
/// γ_i = σ_xy/μ_i, lateral tractions ±(σ_xx,i, σ_xy) that keep ε_xx = 0.
/// Stick: Tresca s = 0.6·10⁻², top traction (σ_xy, −p) = (0.3, −1)·10⁻²; u = (γ₂ y, ε₂ y) below
/// and continuous above. Slip: Coulomb F = 0.3, top u = (b, −b), b = 10⁻²; p = b / Σ_i
/// ½/(λ_i+2μ_i), σ_xy = F p, and the upper block slips by b − (γ₁ + γ₂)/2 (0.146 b).
#[test]
fn two_body_stick_and_slip_are_exact() {
    let (lower, upper) =
        (Material { young: 3.0, poisson: 0.3, density: 0.0 }, Material { young: 1.0, poisson: 0.2, density: 0.0 });
    let ((l2, mu2), (l1, mu1)) = (lower.lame(), upper.lame());
    let (m2, m1) = (l2 + 2.0 * mu2, l1 + 2.0 * mu1);
    let b = 1e-2;
    for stick in [true, false] {
        let (law, p, shear) = if stick {
            (JointLaw::Tresca { threshold: 0.6 * b }, b, 0.3 * b)
        } else {
            let p = b / (0.5 / m2 + 0.5 / m1);
            (JointLaw::Coulomb { friction: 0.3 }, p, 0.3 * p)
        };
        let (e2, e1, g2, g1) = (-p / m2, -p / m1, shear / mu2, shear / mu1);
        let slip = if stick { 0.0 } else { b - 0.5 * (g1 + g2) };
        // the exact displacement of a node of the lower (false) or upper (true) block
        let exact = move |x: [f64; 2], above: bool| {
            let (y, q) = (x[1].min(0.5), (x[1] - 0.5).max(0.0));
            [g2 * y + g1 * q + if above { slip } else { 0.0 }, e2 * y + e1 * q]
        };
        let sigma_xx = move |y: f64| if y < 0.5 { l2 * e2 } else { l1 * e1 };
        let side = |sign: f64| -> VectorFn { Arc::new(move |x: [f64; 2]| [sign * sigma_xx(x[1]), sign * shear]) };
        for order in [1, 2] {
            for (nx_lower, nx_upper) in [(4, 4), (3, 5)] {
                let mesh = two_blocks(nx_lower, nx_upper, 2, 0.5, order);
                let fixed = Dirichlet { tag: BOTTOM, fix: [true; 2], value: Arc::new(|_| [0.0; 2]) };
                let mut neumann = vec![
                    Neumann { tag: LEFT, traction: Traction::Field(side(-1.0)) },
                    Neumann { tag: RIGHT, traction: Traction::Field(side(1.0)) },
                ];
                let mut dirichlet = vec![fixed];
                if stick {
                    neumann.push(Neumann { tag: TOP, traction: Traction::Constant([shear, -p]) });
                } else {
                    dirichlet.push(Dirichlet { tag: TOP, fix: [true; 2], value: Arc::new(move |_| [b, -b]) });
                }
                let problem = Problem {
                    materials: materials(&mesh, lower, upper),
                    dirichlet,
                    neumann,
                    body_force: BodyForce::None,
                    mesh,
                };
                let x = solve_at(
                    &problem,
                    &ContactJoint::uniform(vec![JOINT], vec![JOINT_LOWER], law, crate::nitsche_parameters()),
                    0.0,
                );
                let u = problem.displacement(&problem.discretise(), &x);
                let mesh = &problem.mesh;
                let mut above = vec![false; mesh.n_points()];
                for c in (0..mesh.n_cells()).filter(|&c| mesh.cell_tags[c] != LOWER) {
                    mesh.cell(c).iter().for_each(|&n| above[n] = true);
                }
                let error = (0..mesh.n_points())
                    .map(|n| {
                        let e = exact(mesh.points[n], above[n]);
                        (u[n][0] - e[0]).abs().max((u[n][1] - e[1]).abs())
                    })
                    .fold(0.0, f64::max);
                let case = if stick { "stick" } else { "slip" };
                println!(
                    "{case}, P{order}, {nx_lower} | {nx_upper} cells along the joint: max nodal error {error:.2e}"
                );
                assert!(error < 1e-13, "{case} P{order} {nx_lower}|{nx_upper}: error {error:.3e}");
            }
        }
    }
}

/// A smooth solution closed across the joint: u = (c sin πx q², v(y) + d cos πx q²), q = y − ½,
/// v(y) = −a sin y. At y = ½, σ_xy = 0 (frictionless) and σ_yy = (λ+2μ) v'(½) < 0 (pressed),
/// and [u] = 0. Returns u, ∇u, σ and f = −∇·σ for the Lamé coefficients (λ, μ).
struct Smooth {
    lambda: f64,
    mu: f64,
}

impl Smooth {
    const A: f64 = 1e-2;
    const C: f64 = 5e-3;
    const D: f64 = 5e-3;

    fn u(x: [f64; 2]) -> [f64; 2] {
        let (s, c, q) = Self::trig(x);
        [Self::C * s * q * q, -Self::A * x[1].sin() + Self::D * c * q * q]
    }

    fn trig(x: [f64; 2]) -> (f64, f64, f64) {
        let pi = std::f64::consts::PI;
        ((pi * x[0]).sin(), (pi * x[0]).cos(), x[1] - 0.5)
    }

    /// ∂_j u_i at [i][j].
    fn grad(x: [f64; 2]) -> [[f64; 2]; 2] {
        let pi = std::f64::consts::PI;
        let (s, c, q) = Self::trig(x);
        let (cc, d, a) = (Self::C, Self::D, Self::A);
        [[cc * pi * c * q * q, 2.0 * cc * s * q], [-d * pi * s * q * q, -a * x[1].cos() + 2.0 * d * c * q]]
    }

    fn sigma(&self, x: [f64; 2]) -> [[f64; 2]; 2] {
        let g = Self::grad(x);
        let div = g[0][0] + g[1][1];
        let shear = self.mu * (g[0][1] + g[1][0]);
        [[self.lambda * div + 2.0 * self.mu * g[0][0], shear], [shear, self.lambda * div + 2.0 * self.mu * g[1][1]]]
    }

    /// f = −∇·σ, differentiated by hand from `grad`.
    fn f(&self, x: [f64; 2]) -> [f64; 2] {
        let pi = std::f64::consts::PI;
        let (s, c, q) = Self::trig(x);
        let (cc, d, a, l, m) = (Self::C, Self::D, Self::A, self.lambda, self.mu);
        let fx = (l + 2.0 * m) * (-cc * pi * pi * s * q * q)
            + l * (-2.0 * d * pi * s * q)
            + m * (2.0 * cc * s - 2.0 * d * pi * s * q);
        let fy = m * (2.0 * cc * pi * c * q - d * pi * pi * c * q * q)
            + l * (2.0 * cc * pi * c * q)
            + (l + 2.0 * m) * (a * x[1].sin() + 2.0 * d * c);
        [-fx, -fy]
    }
}

/// Two-body convergence on non-matching sides. Source: docs/method.md §1.10.
/// Goal: the L² and H¹ errors of the smooth closed solution of [`Smooth`] converge at the optimal
/// rates p + 1 and p when the joint's two sides have 2n and 3n faces.
/// Parameters: E = 1, ν = 0.2 in both blocks, γ₀ = 100, θ = 0; exact Dirichlet data at y = 0
/// and y = 1, exact tractions on x = 0 and x = 1; P1 on n = 4 … 32, P2 on n = 2 … 16.
#[test]
fn two_body_non_matching_sides_converge_at_the_optimal_rate() {
    let material = Material { young: 1.0, poisson: 0.2, density: 0.0 };
    let (lambda, mu) = material.lame();
    let exact = Arc::new(Smooth { lambda, mu });
    for (order, sizes) in [(1, [4, 8, 16, 32]), (2, [2, 4, 8, 16])] {
        let (mut h, mut l2, mut h1) = (Vec::new(), Vec::new(), Vec::new());
        for n in sizes {
            let mesh = two_blocks(2 * n, 3 * n, 2 * n, 0.5, order);
            let traction = |sign: f64| -> VectorFn {
                let e = exact.clone();
                Arc::new(move |x: [f64; 2]| e.sigma(x)[0].map(|s| sign * s))
            };
            let body = exact.clone();
            let problem = Problem {
                materials: vec![material; mesh.n_cells()],
                dirichlet: [BOTTOM, TOP]
                    .map(|tag| Dirichlet { tag, fix: [true; 2], value: Arc::new(Smooth::u) })
                    .to_vec(),
                neumann: vec![
                    Neumann { tag: LEFT, traction: Traction::Field(traction(-1.0)) },
                    Neumann { tag: RIGHT, traction: Traction::Field(traction(1.0)) },
                ],
                body_force: BodyForce::Field(Arc::new(move |x| body.f(x))),
                mesh,
            };
            let x = solve(&problem, &joint(0.0));
            let u = problem.displacement(&problem.discretise(), &x);
            let (e0, e1) = errors(&problem.mesh, &u, Smooth::u, Smooth::grad);
            println!("P{order}, n = {n} (2n | 3n faces along the joint): |e|_L2 = {e0:.3e}, |e|_H1 = {e1:.3e}");
            h.push(1.0 / n as f64);
            l2.push(e0);
            h1.push(e1);
        }
        let (rate0, rate1) = (common::fitted_rate(&h, &l2), common::fitted_rate(&h, &h1));
        println!("P{order}: fitted rates L2 {rate0:.3}, H1 {rate1:.3}");
        let p = order as f64;
        assert!(rate1 >= p - 0.1, "P{order} H1 rate {rate1:.3} < {}", p - 0.1);
        assert!(rate0 >= p + 1.0 - 0.2, "P{order} L2 rate {rate0:.3} < {}", p + 0.8);
    }
}

/// The two-body solution tends to the rigid-foundation one. Source: docs/method.md §1.10 (the
/// consistency check). Goal: as the lower block's modulus E₂ grows, the upper block's
/// displacement tends to that of the same block on a rigid foundation, at the rate E₂⁻¹ (the
/// foundation's compliance).
/// Parameters: upper block [0,1] × [½,1], E₁ = 1, ν₁ = 0.2, pressed at its top by
/// u = (0, −b (1 − x)), b = 10⁻², so that its right part lifts off; lower block ν₂ = 0.2,
/// E₂ = 10², 10³, 10⁴, fixed at y = 0; P2, 8 × 4 cells per block, γ₀ = 100, θ = 0.
#[test]
fn a_very_stiff_foundation_tends_to_the_rigid_one() {
    let b = 1e-2;
    let (order, n) = (2, 8);
    let upper = Material { young: 1.0, poisson: 0.2, density: 0.0 };
    let press: damfem::elasticity::VectorFn = Arc::new(move |x: [f64; 2]| [0.0, -b * (1.0 - x[0])]);
    let rigid = {
        let mesh = rectangle(0.0, 1.0, 0.5, 1.0, n, n / 2, order);
        let problem = Problem {
            materials: vec![upper; mesh.n_cells()],
            dirichlet: vec![Dirichlet { tag: TOP, fix: [true; 2], value: press.clone() }],
            neumann: vec![],
            body_force: BodyForce::None,
            mesh,
        };
        let joint = ContactJoint::frictionless(vec![BOTTOM], crate::nitsche_parameters());
        problem.displacement(&problem.discretise(), &solve(&problem, &joint))
    };
    let (mut compliance, mut difference) = (Vec::new(), Vec::new());
    for young in [1e2, 1e3, 1e4] {
        let mesh = two_blocks(n, n, n / 2, 0.5, order);
        let offset = mesh.n_points() - rigid.len();
        let lower = Material { young, ..upper };
        let problem = Problem {
            materials: materials(&mesh, lower, upper),
            dirichlet: vec![
                Dirichlet { tag: BOTTOM, fix: [true; 2], value: Arc::new(|_| [0.0; 2]) },
                Dirichlet { tag: TOP, fix: [true; 2], value: press.clone() },
            ],
            neumann: vec![],
            body_force: BodyForce::None,
            mesh,
        };
        let u = problem.displacement(&problem.discretise(), &solve(&problem, &joint(0.0)));
        let max = (u[offset..].iter().zip(&rigid)).map(|(a, r)| (a[0] - r[0]).hypot(a[1] - r[1])).fold(0.0, f64::max);
        println!("E2/E1 = {young:.0e}: max |u − u_rigid| over the upper block = {max:.3e} (b = {b:.0e})");
        compliance.push(1.0 / young);
        difference.push(max);
    }
    let rate = common::fitted_rate(&compliance, &difference);
    println!("fitted rate in 1/E2: {rate:.3}");
    assert!(difference[2] < 1e-3 * b, "the stiffest foundation is {:.3e} from the rigid one", difference[2]);
    assert!((rate - 1.0).abs() < 0.1, "rate {rate:.3} in 1/E2, expected 1");
}

/// A closed, sticking joint tends to the bonded interface. Source: docs/method.md §1.10 (the
/// consistency check: a bonded interface against a joint that stays closed and sticks).
/// Goal: the blocks joined by a Tresca joint that stays closed and sticks everywhere, and the
/// same blocks bonded (one conforming mesh), have displacements that differ by O(1/γ₀): on a
/// closed, sticking joint the θ = 0 Nitsche terms are (σ(u_h¹)n¹ − γ[u_h], [v_h]), whose
/// restriction to continuous v_h is the bonded problem, so the difference e = u_γ − u_bonded
/// solves a problem whose only datum is the defect σ(u_bonded¹)n¹ − (the bonded discrete
/// traction), of the order of the discretisation error of the flux, divided by γ.
/// Parameters: the blocks of the patch test (E₂ = 3, ν₂ = 0.3 below, E₁ = 1, ν₁ = 0.2 above),
/// 8 × 4 cells each, matching sides, fixed at y = 0, sides free, a top traction
/// (0.2, −(1 + x)) × 10⁻², so that the joint is pressed everywhere and sheared; Tresca
/// s = 1, a hundred times the load (a Coulomb joint slips at the free ends of the joint, where
/// the normal stress of the bonded blocks vanishes); θ = 0, γ₀ = 10², 10³, 10⁴; P1 and P2.
#[test]
fn a_closed_sticking_joint_tends_to_the_bonded_interface() {
    let (lower, upper) =
        (Material { young: 3.0, poisson: 0.3, density: 0.0 }, Material { young: 1.0, poisson: 0.2, density: 0.0 });
    let load: VectorFn = Arc::new(|x: [f64; 2]| [0.2e-2, -1e-2 * (1.0 + x[0])]);
    let problem = |mesh: damfem::mesh::Mesh| Problem {
        materials: mesh.cell_tags.iter().map(|_| upper).collect(),
        dirichlet: vec![Dirichlet { tag: BOTTOM, fix: [true; 2], value: Arc::new(|_| [0.0; 2]) }],
        neumann: vec![Neumann { tag: TOP, traction: Traction::Field(load.clone()) }],
        body_force: BodyForce::None,
        mesh,
    };
    let (n, ny) = (8, 4);
    let key = |x: [f64; 2]| ((x[0] * 1e9).round() as i64, (x[1] * 1e9).round() as i64);
    for order in [1, 2] {
        let bonded = {
            let mesh = rectangle(0.0, 1.0, 0.0, 1.0, n, 2 * ny, order);
            let below: Vec<bool> = (0..mesh.n_cells()).map(|c| mesh.cell_centroid(c)[1] < 0.5).collect();
            let mut problem = problem(mesh);
            problem.materials = below.iter().map(|&b| if b { lower } else { upper }).collect();
            let disc = problem.discretise();
            let u = problem.displacement(&disc, &problem.solve_linear(&disc).unwrap());
            let at: std::collections::HashMap<_, _> =
                problem.mesh.points.iter().zip(u).map(|(x, u)| (key(*x), u)).collect();
            at
        };
        let scale = bonded.values().map(|u| u[0].hypot(u[1])).fold(0.0, f64::max);
        let (mut inverse, mut difference) = (Vec::new(), Vec::new());
        for gamma0 in [1e2, 1e3, 1e4] {
            let mut problem = problem(two_blocks(n, n, ny, 0.5, order));
            problem.materials = materials(&problem.mesh, lower, upper);
            let parameters = NitscheParameters { gamma0, ..crate::nitsche_parameters() };
            let joint =
                ContactJoint::uniform(vec![JOINT], vec![JOINT_LOWER], JointLaw::Tresca { threshold: 1.0 }, parameters);
            let disc = problem.discretise();
            let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 0.0 });
            let x0 = vec![0.0; disc.dofs.n_free];
            let (x, _) =
                continuation(&mut contact, 0.0, 1e-3, x0, &NewtonOptions::default()).unwrap_or_else(|e| panic!("{e}"));
            let faces = contact.face_states(&x);
            let (closed, stick) = faces.iter().fold((0.0, 0.0), |(c, s), f| (c + f.contact_length, s + f.stick_length));
            assert!((closed - 1.0).abs() < 1e-12 && (stick - 1.0).abs() < 1e-12, "closed {closed}, stick {stick}");
            let u = problem.displacement(&disc, &x);
            let max = (problem.mesh.points.iter().zip(&u))
                .map(|(x, u)| {
                    let b = bonded[&key(*x)];
                    (u[0] - b[0]).hypot(u[1] - b[1])
                })
                .fold(0.0, f64::max);
            println!(
                "P{order}, γ₀ = {gamma0:.0e}: max |u − u_bonded| = {max:.3e} ({:.2e} of max |u_bonded| = {scale:.3e})",
                max / scale
            );
            inverse.push(1.0 / gamma0);
            difference.push(max);
        }
        let rate = common::fitted_rate(&inverse, &difference);
        println!("P{order}: fitted rate in 1/γ₀: {rate:.3}");
        assert!((rate - 1.0).abs() < 0.1, "P{order}: rate {rate:.3} in 1/γ₀, expected 1");
        assert!(
            difference[0] < 1e-3 * scale,
            "P{order}: at γ₀ = 100 the joint is {:.3e} from the bonded",
            difference[0]
        );
    }
}
