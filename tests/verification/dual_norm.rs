//! Verification of the dual norm of the residual (docs/method.md §2) computed by
//! `damfem::estimate::reference`: the reference "true error" of the a posteriori estimator
//! tests. Every test checks the tool against something it does not compute itself: exact
//! solutions, Galerkin orthogonality of the project's solvers, and two-sided bounds by
//! independently integrated norms of known errors.

use crate::common;

use damfem::verify::v3;

use damfem::contact::nitsche::NitscheParameters;
use damfem::contact::projection::Smoothing;
use damfem::contact::{continuation, ContactJoint, ContactProblem};
use damfem::elasticity::kernels::{displacement_gradient, stress};
use damfem::elasticity::{BodyForce, Dirichlet, Material, Neumann, Problem, Traction, VectorFn};
use damfem::estimate::reference::{residual_dual_norm, residual_riesz};
use damfem::fem::norms::errors;
use damfem::fem::quadrature::gauss_segment;
use damfem::fem::tabulate::Tabulation;
use damfem::geometry::AffineMap;
use damfem::mesh::midpoints::elevate_to_p2;
use damfem::mesh::structured::{rectangle, unit_square, BOTTOM, LEFT, RIGHT, TOP};
use damfem::mesh::{Mesh, Topology};
use damfem::solve::{newton, Cholesky, NewtonOptions};
use std::sync::Arc;

// ---------------------------------------------------------------------------------------
// helpers

/// The displacement of the free unknowns of a linear problem, by the project's solver.
fn solve_linear(problem: &Problem) -> Vec<[f64; 2]> {
    let disc = problem.discretise();
    let system = problem.assemble(&disc);
    let x = Cholesky::analyse(&disc.pattern).unwrap().solve(&disc.pattern, &system.values, &system.rhs).unwrap();
    problem.displacement(&disc, &x)
}

/// ξ with x = v0 + J ξ in the cell of `map`.
fn reference_point(map: &AffineMap, x: [f64; 2]) -> [f64; 2] {
    let j = map.jacobian;
    let d = [x[0] - map.origin[0], x[1] - map.origin[1]];
    [(j[1][1] * d[0] - j[0][1] * d[1]) / map.det, (-j[1][0] * d[0] + j[0][0] * d[1]) / map.det]
}

/// In-plane stress as a 2 × 2 tensor from a displacement gradient.
fn stress_tensor(grad: [[f64; 2]; 2], lambda: f64, mu: f64) -> [[f64; 2]; 2] {
    let [xx, yy, xy, _] = stress(grad, lambda, mu);
    [[xx, xy], [xy, yy]]
}

fn frobenius2(a: [[f64; 2]; 2]) -> f64 {
    a.iter().flatten().map(|v| v * v).sum()
}

/// ‖σ(u) − σ(u_h)‖_{L²(Ω)} (in-plane Frobenius norm) with a rule of degree 2p + 8.
/// `grad_u` is the exact gradient (∂_j u_i at [i][j]).
fn stress_error(problem: &Problem, u_h: &[[f64; 2]], grad_u: impl Fn([f64; 2]) -> [[f64; 2]; 2]) -> f64 {
    let mesh = &problem.mesh;
    let tab = Tabulation::new(mesh.order, 2 * mesh.order + 8);
    let mut scratch = [[0.0; 2]; 6];
    let mut sum = 0.0;
    for c in 0..mesh.n_cells() {
        let map = AffineMap::new(mesh.cell_vertices(c));
        let u: Vec<[f64; 2]> = mesh.cell(c).iter().map(|&n| u_h[n]).collect();
        let (lambda, mu) = problem.materials[c].lame();
        for q in 0..tab.n_points() {
            let x = map.to_physical(tab.points[q]);
            let gh = displacement_gradient(&map, mesh.order, tab.points[q], &u, &mut scratch[..u.len()]);
            let (s, sh) = (stress_tensor(grad_u(x), lambda, mu), stress_tensor(gh, lambda, mu));
            let diff = [[s[0][0] - sh[0][0], s[0][1] - sh[0][1]], [s[1][0] - sh[1][0], s[1][1] - sh[1][1]]];
            sum += tab.weights[q] * map.det.abs() * frobenius2(diff);
        }
    }
    sum.sqrt()
}

/// For a discrete field w: (a(w, w), ‖∇w‖², ‖σ(w)‖²), integrated exactly.
fn energies(problem: &Problem, w: &[[f64; 2]]) -> (f64, f64, f64) {
    let mesh = &problem.mesh;
    let tab = Tabulation::new(mesh.order, 2 * mesh.order);
    let mut scratch = [[0.0; 2]; 6];
    let (mut energy, mut grad2, mut sigma2) = (0.0, 0.0, 0.0);
    for c in 0..mesh.n_cells() {
        let map = AffineMap::new(mesh.cell_vertices(c));
        let u: Vec<[f64; 2]> = mesh.cell(c).iter().map(|&n| w[n]).collect();
        let (lambda, mu) = problem.materials[c].lame();
        for q in 0..tab.n_points() {
            let weight = tab.weights[q] * map.det.abs();
            let g = displacement_gradient(&map, mesh.order, tab.points[q], &u, &mut scratch[..u.len()]);
            let s = stress_tensor(g, lambda, mu);
            let eps = [[g[0][0], 0.5 * (g[0][1] + g[1][0])], [0.5 * (g[0][1] + g[1][0]), g[1][1]]];
            energy += weight * (0..4).map(|k| s[k / 2][k % 2] * eps[k / 2][k % 2]).sum::<f64>();
            grad2 += weight * frobenius2(g);
            sigma2 += weight * frobenius2(s);
        }
    }
    (energy, grad2, sigma2)
}

/// The unit square's structured mesh with interior nodes moved (P1, elevated for P2), so
/// that no cell is a right triangle.
fn distorted_rectangle(x1: f64, y1: f64, nx: usize, ny: usize, order: usize) -> Mesh {
    let mut mesh = rectangle(0.0, x1, 0.0, y1, nx, ny, 1);
    let (hx, hy) = (x1 / nx as f64, y1 / ny as f64);
    for p in mesh.points.iter_mut() {
        if p[0] > 0.0 && p[0] < x1 && p[1] > 0.0 && p[1] < y1 {
            let (s, t) = (p[0] / x1, p[1] / y1);
            p[0] += 0.2 * hx * (7.0 * t + 3.0 * s).sin();
            p[1] += 0.2 * hy * (5.0 * s - 2.0 * t).cos();
        }
    }
    if order == 2 {
        elevate_to_p2(&mesh)
    } else {
        mesh
    }
}

/// Deterministic pseudo-random numbers in [−1, 1).
fn pseudo_random(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

// ---------------------------------------------------------------------------------------
// V1: manufactured elasticity solution (docs/method.md §7, src/verify/v1.rs)

mod v1 {
    use super::*;
    pub use damfem::verify::v1::{exact as u, exact_gradient as grad_u};

    /// V1 on the n × n unit square of degree p, clamped to the exact u on all of ∂Ω.
    pub fn problem(n: usize, p: usize) -> Problem {
        damfem::verify::v1::problem(unit_square(n, p), &[BOTTOM, RIGHT, TOP, LEFT])
    }

    /// Nodal interpolant of the exact u.
    pub fn interpolant(problem: &Problem) -> Vec<[f64; 2]> {
        problem.mesh.points.iter().map(|&x| u(x)).collect()
    }
}

/// Consistency. Source: V1 (docs/method.md §7), μ = λ = 1, Dirichlet on all of ∂Ω.
/// u_h = the nodal interpolant I_h u of the exact solution is not the discrete solution, so
/// its residual ⟨R(I_h u), v⟩ = (σ(u − I_h u), ε(v)) does not vanish; it must converge to zero
/// like the H¹ interpolation error, h^p (fitted slope within ±0.15), and stay below the
/// independent bound ‖σ(u − I_h u)‖_{L²}.
#[test]
fn interpolant_residual_converges_at_rate_p() {
    for (p, sizes) in [(1, [4, 8, 16, 32]), (2, [2, 4, 8, 16])] {
        let mut h = Vec::new();
        let mut norms = Vec::new();
        for n in sizes {
            let problem = v1::problem(n, p);
            let u_h = v1::interpolant(&problem);
            let dual = residual_dual_norm(&problem, &u_h, None, 2).unwrap();
            let bound = stress_error(&problem, &u_h, v1::grad_u);
            println!("P{p} n = {n:3}: ‖R(I_h u)‖ ≥ {dual:.4e}, ‖σ(u − I_h u)‖ = {bound:.4e}");
            assert!(dual > 0.0 && dual <= bound * (1.0 + 1e-8), "P{p} n = {n}: {dual} vs bound {bound}");
            h.push(1.0 / n as f64);
            norms.push(dual);
        }
        let rate = common::fitted_rate(&h, &norms);
        println!("P{p}: fitted rate {rate:.3}");
        assert!((rate - p as f64).abs() <= 0.15, "P{p} rate {rate}");
    }
}

/// Exactness and a two-sided bound. Source: a polynomial solution of degree p (linear for
/// P1, quadratic for P2) on a distorted 4 × 5 mesh of a 40 × 50 rectangle with dam-like
/// concrete (E = 30 GPa, ν = 0.2): f = −∇·σ(u) (constant), clamped on the left (u exact),
/// roller on the bottom (u_y exact, traction σ(u)n for the free x component), tractions
/// σ(u)n on the right and top.
/// (a) u_h = u (exactly representable): ‖R(u_h)‖ ≤ 10⁻¹¹ ‖σ(u)‖_{L²} (round-off).
/// (b) u_h = u − e with e a pseudo-random field of the coarse space vanishing on the fixed
///     components: ⟨R(u_h), v⟩ = a(e, v), and since e ∈ V_fine,
///     a(e, e)/‖∇e‖ ≤ ‖r‖_{C,h} ≤ ‖σ(e)‖_{L²}, both bounds integrated independently here.
#[test]
fn polynomial_solution_exact_and_perturbed() {
    let material = Material { young: 3e10, poisson: 0.2, density: 0.0 };
    let (lambda, mu) = material.lame();
    for p in [1, 2] {
        // u = A x + c + quadratic terms (P2 only); displacements of a few millimetres
        let q = if p == 2 { 1.0 } else { 0.0 };
        let (a1, a2, a3, b1, b2, b3) = (2e-6 * q, -1e-6 * q, 3e-6 * q, -1.5e-6 * q, 2.5e-6 * q, 1e-6 * q);
        let u = move |x: [f64; 2]| {
            let (s, t) = (x[0], x[1]);
            [
                1e-3 + 1e-4 * s - 2e-4 * t + a1 * s * s + a2 * s * t + a3 * t * t,
                -2e-3 + 3e-5 * s + 5e-5 * t + b1 * s * s + b2 * s * t + b3 * t * t,
            ]
        };
        let grad_u = move |x: [f64; 2]| {
            let (s, t) = (x[0], x[1]);
            [
                [1e-4 + 2.0 * a1 * s + a2 * t, -2e-4 + a2 * s + 2.0 * a3 * t],
                [3e-5 + 2.0 * b1 * s + b2 * t, 5e-5 + b2 * s + 2.0 * b3 * t],
            ]
        };
        // −∇·σ = −(μ Δu + (λ + μ) ∇ div u)
        let f = [
            -(mu * (2.0 * a1 + 2.0 * a3) + (lambda + mu) * (2.0 * a1 + b2)),
            -(mu * (2.0 * b1 + 2.0 * b3) + (lambda + mu) * (a2 + 2.0 * b3)),
        ];
        let traction = |normal: [f64; 2]| -> Traction {
            Traction::Field(Arc::new(move |x| {
                let s = stress_tensor(grad_u(x), lambda, mu);
                [s[0][0] * normal[0] + s[0][1] * normal[1], s[1][0] * normal[0] + s[1][1] * normal[1]]
            }))
        };
        let mesh = distorted_rectangle(40.0, 50.0, 4, 5, p);
        let value: VectorFn = Arc::new(u);
        let problem = Problem {
            materials: vec![material; mesh.n_cells()],
            dirichlet: vec![
                Dirichlet { tag: LEFT, fix: [true; 2], value: value.clone() },
                Dirichlet { tag: BOTTOM, fix: [false, true], value },
            ],
            neumann: vec![
                Neumann { tag: BOTTOM, traction: traction([0.0, -1.0]) },
                Neumann { tag: RIGHT, traction: traction([1.0, 0.0]) },
                Neumann { tag: TOP, traction: traction([0.0, 1.0]) },
            ],
            body_force: BodyForce::Field(Arc::new(move |_| f)),
            mesh,
        };
        let exact: Vec<[f64; 2]> = problem.mesh.points.iter().map(|&x| u(x)).collect();
        let zero = vec![[0.0; 2]; exact.len()];
        let scale = stress_error(&problem, &zero, grad_u); // ‖σ(u)‖
        let dual = residual_dual_norm(&problem, &exact, None, 2).unwrap();
        println!("P{p}: u_h = u: ‖r‖ = {dual:.3e}, ‖σ(u)‖ = {scale:.3e}, ratio {:.2e}", dual / scale);
        assert!(dual <= 1e-11 * scale, "P{p}: residual of the exact solution {dual} (‖σ(u)‖ = {scale})");

        // e: pseudo-random nodal values, zero on the fixed components of Γ_D
        let mut fixed = vec![[false; 2]; exact.len()];
        for f in 0..problem.mesh.n_facets() {
            for &n in problem.mesh.facet(f) {
                match problem.mesh.facet_tags[f] {
                    LEFT => fixed[n] = [true; 2],
                    BOTTOM => fixed[n][1] = true,
                    _ => {}
                }
            }
        }
        let mut random = pseudo_random(7 + p as u64);
        let e: Vec<[f64; 2]> =
            fixed.iter().map(|fx| [0, 1].map(|a| if fx[a] { 0.0 } else { 1e-4 * random() })).collect();
        let u_h: Vec<[f64; 2]> = exact.iter().zip(&e).map(|(u, e)| [u[0] - e[0], u[1] - e[1]]).collect();
        let riesz = residual_riesz(&problem, &u_h, None, 2).unwrap();
        let (energy, grad2, sigma2) = energies(&problem, &e);
        let (lower, upper) = (energy / grad2.sqrt(), sigma2.sqrt());
        println!("P{p}: u_h = u − e: a(e,e)/‖∇e‖ = {lower:.6e} ≤ ‖r‖ = {:.6e} ≤ ‖σ(e)‖ = {upper:.6e}", riesz.norm);
        assert!(lower <= riesz.norm * (1.0 + 1e-8), "P{p}: lower bound {lower} > {}", riesz.norm);
        assert!(riesz.norm <= upper * (1.0 + 1e-8), "P{p}: {} > upper bound {upper}", riesz.norm);
        // the cell contributions add up to ‖r‖²
        let sum: f64 = riesz.cell_contributions.iter().sum();
        assert!(
            (sum - riesz.norm.powi(2)).abs() <= 1e-10 * riesz.norm.powi(2),
            "Σ cells {sum} vs {}",
            riesz.norm.powi(2)
        );
    }
}

/// Galerkin orthogonality. Source: a P2 cantilever 4 × 1 (E = 30 GPa, ν = 0.2,
/// ρ = 2400 kg/m³ under gravity), clamped on the left, hydrostatic pressure on the right
/// with the water level at a mesh node (y = 0.5), a constant traction on the top, all
/// integrated exactly by the solver. With levels = 0 the fine space is the coarse P2 space,
/// on which the residual of the Galerkin solution vanishes: ‖r‖ ≤ 10⁻⁹ × its value on the
/// twice refined space. For P1, levels = 0 already tests with P2 functions, so the value is
/// a sizeable part of the refined one.
#[test]
fn galerkin_solution_has_no_residual_on_its_own_space() {
    for p in [2, 1] {
        let mesh = rectangle(0.0, 4.0, 0.0, 1.0, 8, 2, p);
        let problem = Problem {
            materials: vec![Material { young: 3e10, poisson: 0.2, density: 2400.0 }; mesh.n_cells()],
            dirichlet: vec![Dirichlet { tag: LEFT, fix: [true; 2], value: Arc::new(|_| [0.0; 2]) }],
            neumann: vec![
                Neumann { tag: RIGHT, traction: Traction::Hydrostatic { density: 1000.0, gravity: 9.81, level: 0.5 } },
                Neumann { tag: TOP, traction: Traction::Constant([2e3, -1e4]) },
            ],
            body_force: BodyForce::Acceleration([0.0, -9.81]),
            mesh,
        };
        let u_h = solve_linear(&problem);
        let own = residual_dual_norm(&problem, &u_h, None, 0).unwrap();
        let refined = residual_dual_norm(&problem, &u_h, None, 2).unwrap();
        println!("P{p}: ‖r‖ on levels 0: {own:.3e}, on levels 2: {refined:.3e}");
        if p == 2 {
            assert!(own <= 1e-9 * refined, "P2: residual on the coarse space {own} vs {refined}");
        } else {
            assert!(own >= 0.1 * refined && own <= refined, "P1: {own} vs {refined}");
        }
    }
}

/// Lower bound growing with the fine space. Source: the P1 solution of V1 on an 8 × 8 mesh.
/// The spaces of levels 0 ⊂ 1 ⊂ 2 ⊂ 3 are nested, so ‖r‖ is nondecreasing in the levels and
/// saturates (the last increment is below 5 %).
#[test]
fn lower_bound_is_monotone_in_the_levels() {
    let problem = v1::problem(8, 1);
    let u_h = solve_linear(&problem);
    let norms: Vec<f64> = (0..=3).map(|l| residual_dual_norm(&problem, &u_h, None, l).unwrap()).collect();
    println!("‖r‖ for levels 0..3: {norms:?}");
    for w in norms.windows(2) {
        assert!(w[1] >= w[0] * (1.0 - 1e-12), "not monotone: {norms:?}");
    }
    assert!(norms[3] - norms[2] <= 0.05 * norms[3], "no saturation: {norms:?}");
}

/// Lower bound and convergence. Source: V1, Galerkin solutions of the project's solver,
/// P1 on n = 8…64 and P2 on n = 4…32, levels = 2. Since ⟨R(u_h), v⟩ = (σ(u) − σ(u_h), ε(v))
/// and ‖ε(v)‖ ≤ ‖∇v‖ = ‖v‖_{C,h}, ‖r‖ ≤ ‖R(u_h)‖ ≤ ‖σ(u) − σ(u_h)‖_{L²} (asserted, integrated
/// independently); the fitted rate of ‖r‖ is p within ±0.15.
#[test]
fn galerkin_solution_bounded_by_stress_error_and_converges() {
    for (p, sizes) in [(1, [8, 16, 32, 64]), (2, [4, 8, 16, 32])] {
        let mut h = Vec::new();
        let mut norms = Vec::new();
        for n in sizes {
            let problem = v1::problem(n, p);
            let u_h = solve_linear(&problem);
            let start = std::time::Instant::now();
            let riesz = residual_riesz(&problem, &u_h, None, 2).unwrap();
            let time = start.elapsed().as_secs_f64();
            let bound = stress_error(&problem, &u_h, v1::grad_u);
            let (_, h1) = errors(&problem.mesh, &u_h, v1::u, v1::grad_u);
            println!(
                "P{p} n = {n:3}: ‖r‖ = {:.4e} ≤ ‖σ(u − u_h)‖ = {bound:.4e} (ratio {:.3}); |u − u_h|_H1 = {h1:.4e}; \
                 {} unknowns, {time:.2} s",
                riesz.norm,
                riesz.norm / bound,
                riesz.n_unknowns
            );
            assert!(riesz.norm <= bound * (1.0 + 1e-8), "P{p} n = {n}: {} > {bound}", riesz.norm);
            assert!(riesz.norm >= 0.1 * bound, "P{p} n = {n}: {} far below {bound}", riesz.norm);
            h.push(1.0 / n as f64);
            norms.push(riesz.norm);
        }
        let rate = common::fitted_rate(&h, &norms);
        println!("P{p}: fitted rate {rate:.3}");
        assert!((rate - p as f64).abs() <= 0.15, "P{p} rate {rate}");
    }
}

// ---------------------------------------------------------------------------------------
// contact

/// V2 patch test with the project's Nitsche solver. Source: docs/method.md §7 V2 and
/// tests/verification/contact.rs: unit square (E = 1, ν = 0) on 4 × 4 cells, Γ_C = {y = 0}, top moved by
/// (0, d), f = 0. Returns the nodal solution and the problem.
fn v2_solution(order: usize, theta: f64, top_uy: f64) -> (Problem, Vec<[f64; 2]>) {
    let mesh = unit_square(4, order);
    let problem = Problem {
        materials: vec![Material { young: 1.0, poisson: 0.0, density: 0.0 }; mesh.n_cells()],
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
    (problem, u)
}

/// Contact patch test. Source: V2. Pressed down (d = −10⁻²) the discrete solution is the
/// exact u = (0, d y) in full contact, so its residual (exact projection, γ₀ = 100) is
/// round-off: ‖r‖ ≤ 10⁻¹⁰ |d| (the stress scale |σ| = |d| E on a unit domain). Pulled up
/// (d = +10⁻²) it is a stress-free translation with P_γ > 0: residual round-off too.
/// All three θ, P1 and P2.
#[test]
fn contact_patch_test_has_round_off_residual() {
    let data = ContactJoint::frictionless(vec![BOTTOM], crate::nitsche_parameters());
    for order in [1, 2] {
        for theta in [1.0, 0.0, -1.0] {
            for d in [-1e-2, 1e-2] {
                let (problem, u) = v2_solution(order, theta, d);
                let riesz = residual_riesz(&problem, &u, Some(&data), 2).unwrap();
                println!("P{order} θ = {theta:2} d = {d:+}: ‖r‖ = {:.2e}", riesz.norm);
                assert!(riesz.norm <= 1e-10 * d.abs(), "P{order} θ = {theta} d = {d}: {}", riesz.norm);
            }
        }
    }
    // the contact term is really tested: a wrong normal displacement is seen
    let (problem, mut u) = v2_solution(1, 0.0, -1e-2);
    for (x, v) in problem.mesh.points.iter().zip(u.iter_mut()) {
        if x[1] == 0.0 {
            v[1] += 1e-5;
        }
    }
    let dual = residual_dual_norm(&problem, &u, Some(&data), 2).unwrap();
    println!("P1, bottom shifted by 1e-5: ‖r‖ = {dual:.3e}");
    assert!(dual > 1e-4, "a penetration of 1e-5 with γ = 400 must show: {dual}");
}

/// V3 on the n × n unit square of degree p, solved by the project's Nitsche solver with
/// θ = 0, γ₀ = 100 and the regularisation δ (δ = 0: the exact projection).
fn v3_solution(n: usize, order: usize, delta: f64) -> (Problem, Vec<[f64; 2]>) {
    let problem = v3::problem(unit_square(n, order));
    let disc = problem.discretise();
    let joint = ContactJoint::frictionless(vec![BOTTOM], crate::nitsche_parameters());
    let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta });
    let x0 = vec![0.0; disc.dofs.n_free];
    let (x, _) =
        continuation(&mut contact, delta, 0.1, x0, &NewtonOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let u = problem.displacement(&disc, &x);
    (problem, u)
}

/// (Σ_F h_F ‖[P_γ(u_h)]_{R⁻} − σ^n(u)‖²_F)^{1/2} on Γ_C = {y = 0} of V3, computed here
/// independently of the tool (composite Gauss rule, 16 × 6 points per face).
fn v3_contact_defect(problem: &Problem, u_h: &[[f64; 2]], gamma0: f64) -> f64 {
    let mesh = &problem.mesh;
    let topology = Topology::new(mesh);
    let rule = gauss_segment(6);
    let mut scratch = [[0.0; 2]; 6];
    let mut phi = [0.0; 6];
    let mut sum = 0.0;
    for f in (0..mesh.n_facets()).filter(|&f| mesh.facet_tags[f] == BOTTOM) {
        let cell = topology.tagged_cell(f);
        let map = AffineMap::new(mesh.cell_vertices(cell));
        let u: Vec<[f64; 2]> = mesh.cell(cell).iter().map(|&n| u_h[n]).collect();
        let (lambda, mu) = problem.materials[cell].lame();
        let nodes = mesh.facet(f);
        let (a, b) = (mesh.points[nodes[0]], mesh.points[nodes[1]]);
        let h = mesh.facet_length(f);
        let gamma = gamma0 * problem.materials[cell].young / h;
        for piece in 0..16 {
            for (&s, &w) in rule.points.iter().zip(&rule.weights) {
                let t = (piece as f64 + s) / 16.0;
                let x = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                let xi = reference_point(&map, x);
                damfem::fem::lagrange::values(mesh.order, xi, &mut phi);
                let uy: f64 = u.iter().zip(&phi).map(|(v, p)| v[1] * p).sum();
                let g = displacement_gradient(&map, mesh.order, xi, &u, &mut scratch[..u.len()]);
                // n = (0, −1): σ^n = σ_yy, u^n = −u_y, gap 0
                let sigma_n = stress_tensor(g, lambda, mu)[1][1];
                let p_gamma = sigma_n - gamma * (-uy);
                let defect = p_gamma.min(0.0) - v3::sigma(x)[1];
                sum += h * defect * defect * w * h / 16.0;
            }
        }
    }
    sum.sqrt()
}

/// Contact: Galerkin orthogonality and a two-sided check. Source: V3, θ = 0, γ₀ = 100.
/// (a) The P2 solution with the exact projection (δ = 0) on n = 8 (the kink x = ½ of the
///     data on a mesh line, so the solver integrates exactly) satisfies the discrete
///     equation, i.e. ⟨R(u_h), v_h⟩ = 0 on its own space: ‖r‖ at levels 0 is below 10⁻⁷ of
///     its value at levels 2 (Newton stops at ‖F‖ ≤ 10⁻¹⁰ ‖b‖).
/// (b) For P1 (n = 8…32) and P2 (n = 4…16), δ = 10⁻¹⁰:
///     ⟨R(u_h), v⟩ = (σ(u) − σ(u_h), ε(v)) + ([P_γ(u_h)]_{R⁻} − σ^n(u), v^n)_{Γ_C},
///     so ‖r‖ ≤ (‖σ(u) − σ(u_h)‖² + Σ_F h_F ‖[P_γ(u_h)]_{R⁻} − σ^n(u)‖²_F)^{1/2}, asserted
///     with both terms integrated here; the fitted rate of ‖r‖ is at least 0.9 (P1) and 1.4
///     (P2), the bounds of the H¹ error in tests/verification/contact.rs.
#[test]
fn contact_residual_orthogonality_bound_and_rate() {
    let data = ContactJoint::frictionless(vec![BOTTOM], crate::nitsche_parameters());
    let (problem, u_h) = v3_solution(8, 2, 0.0);
    let own = residual_dual_norm(&problem, &u_h, Some(&data), 0).unwrap();
    let refined = residual_dual_norm(&problem, &u_h, Some(&data), 2).unwrap();
    println!("V3 P2 n = 8, δ = 0: ‖r‖ on levels 0: {own:.3e}, on levels 2: {refined:.3e}");
    assert!(own <= 1e-7 * refined, "residual on the coarse space {own} vs {refined}");

    for (p, sizes, min_rate) in [(1, [8, 16, 32], 0.9), (2, [4, 8, 16], 1.4)] {
        let mut h = Vec::new();
        let mut norms = Vec::new();
        for n in sizes {
            let (problem, u_h) = v3_solution(n, p, 1e-10);
            let dual = residual_dual_norm(&problem, &u_h, Some(&data), 2).unwrap();
            let volume = stress_error(&problem, &u_h, v3::grad_u);
            let face = v3_contact_defect(&problem, &u_h, 100.0);
            let bound = volume.hypot(face);
            println!(
                "V3 P{p} n = {n:2}: ‖r‖ = {dual:.4e} ≤ {bound:.4e} (‖σ(u − u_h)‖ = {volume:.3e}, contact {face:.3e})"
            );
            assert!(dual <= bound * (1.0 + 1e-6), "P{p} n = {n}: {dual} > {bound}");
            h.push(1.0 / n as f64);
            norms.push(dual);
        }
        let rate = common::fitted_rate(&h, &norms);
        println!("V3 P{p}: fitted rate {rate:.3}");
        assert!(rate >= min_rate, "V3 P{p} rate {rate} < {min_rate}");
    }
}
