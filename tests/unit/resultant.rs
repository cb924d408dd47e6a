//! The resultant of the joint traction (docs/method.md §1.9) against exact integrals.

use damfem::contact::nitsche::NitscheParameters;
use damfem::contact::{solve_by_continuation, ContactJoint, Continuation, JointLine};
use damfem::elasticity::{BodyForce, Dirichlet, Material, Problem};
use damfem::mesh::structured::{unit_square, BOTTOM, TOP};
use damfem::safety::base::mean_normal_stress;
use damfem::safety::resultant::resultant;
use damfem::solve::NewtonOptions;
use std::sync::Arc;

/// A linear contact pressure. Source: the exact solution u = (k y²/(4μ), −(p₀ + k x) y/(2μ)) of
/// plane-strain elasticity with λ = 0 and no body force on the unit square: σ_yy = −(p₀ + k x),
/// σ_xx = σ_xy = 0, so the sides are traction-free, the top is clamped to u, and the base
/// y = 0 rests on a rigid, frictionless foundation with p_c = p₀ + k x (u is quadratic: P2
/// reproduces it). Goal: N = p₀ + k/2, x_R = (p₀/2 + k/3)/N, s_R and e = s_R − ½ from either
/// end, the middle-third check, no crack, and the mean normal stress −(p₀ + k x̄) over windows
/// that do and do not end at face ends, all to round-off. Parameters: μ = 1, λ = 0, P2, 4 × 4
/// grid, (p₀, k) = (10⁻², 10⁻²): x_R = 5/9, and (0, 2·10⁻²), the triangle: x_R = 2/3, on
/// the edge of the middle third; δ = 0 reached from 10⁻³, γ₀ = 100.
#[test]
fn the_resultant_of_a_linear_pressure_is_exact() {
    let mu = 1.0;
    for (p0, k) in [(1e-2, 1e-2), (0.0, 2e-2)] {
        let exact = move |x: [f64; 2]| [k * x[1] * x[1] / (4.0 * mu), -(p0 + k * x[0]) * x[1] / (2.0 * mu)];
        let mesh = unit_square(4, 2);
        let problem = Problem {
            materials: vec![Material::from_lame(0.0, mu); mesh.n_cells()],
            dirichlet: vec![Dirichlet { tag: TOP, fix: [true; 2], value: Arc::new(exact) }],
            neumann: vec![],
            body_force: BodyForce::None,
            mesh,
        };
        let disc = problem.discretise();
        let joint = ContactJoint::frictionless(vec![BOTTOM], NitscheParameters::default());
        let settings = Continuation { delta: 0.0, delta_start: 1e-3, newton: NewtonOptions::default(), path: None };
        let solution = solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("{e}"));
        let n = p0 + k / 2.0;
        let x_r = (p0 / 2.0 + k / 3.0) / n;
        for (heel, toe, s_r) in [([0.0, 0.0], [1.0, 0.0], x_r), ([1.0, 0.0], [0.0, 0.0], 1.0 - x_r)] {
            let line = JointLine::new(heel, toe);
            let r = resultant(&solution, &line).expect("the joint is pressed");
            println!("p0 = {p0}, k = {k}, heel {heel:?}: {r:?}");
            assert!((r.normal_force - n).abs() <= 1e-12 * n, "N = {} against {n}", r.normal_force);
            assert!(r.tangential_force.abs() <= 1e-12 * n && r.uplift_force == 0.0, "{r:?}");
            assert!((r.point[0] - x_r).abs() <= 1e-12 && r.point[1].abs() <= 1e-12, "x_R = {:?}", r.point);
            assert!((r.position - s_r).abs() <= 1e-12 && (r.eccentricity - (s_r - 0.5)).abs() <= 1e-12, "{r:?}");
            assert_eq!(r.length, 1.0);
            if p0 > 0.0 {
                assert!(r.middle_third, "|e| = 1/18 < 1/6");
            }
            let crack = solution.crack_from_heel(&line);
            assert!(crack.abs() <= 1e-12, "closed to the heel, not open on {crack} m");
        }
        let line = JointLine::new([0.0, 0.0], [1.0, 0.0]);
        for window in [[0.0, 0.25], [0.3, 0.7], [0.9, 1.0]] {
            let mean = mean_normal_stress(&solution, &problem, &disc, &line, window);
            let expected = -(p0 + k * 0.5 * (window[0] + window[1]));
            println!("  mean normal stress on {window:?}: {mean:.15e} against {expected:.15e}");
            assert!((mean - expected).abs() <= 1e-12 * (p0 + k), "{window:?}: {mean} against {expected}");
        }
    }
}
