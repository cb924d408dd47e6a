//! Verification of the cohesive joint: tensile strength and linear softening
//! (docs/method.md §1.13).

use damfem::contact::projection::Smoothing;
use damfem::contact::{
    solve_by_continuation, Bond, BondLengths, ContactJoint, ContactProblem, ContactSolution, Continuation, JointLaw,
};
use damfem::elasticity::{BodyForce, Dirichlet, Material, Problem};
use damfem::mesh::structured::{rectangle, unit_square, BOTTOM, LEFT, RIGHT, TOP};
use damfem::mesh::Mesh;
use damfem::solve::NewtonOptions;
use std::sync::Arc;

/// λ = μ = 1: the uniaxial stiffness of the unit block, λ + 2μ = 3, above the softening slope
/// σ_t / o_c = 0.5 of [`BOND`], so that the pull is stable under displacement control.
const LAMBDA: f64 = 1.0;
const MU: f64 = 1.0;
/// σ_t = 0.01, G_f = 10⁻⁴: o_c = 2 G_f / σ_t = 0.02.
const BOND: Bond = Bond { tensile_strength: 0.01, fracture_energy: 1e-4 };

/// The block `mesh` on a rigid foundation through a bond at y = 0, rollers on its sides
/// (u_x = 0) and its top pulled up by u_y = `lift`.
fn pulled_block(mesh: Mesh, lift: f64) -> Problem {
    let roller = |tag| Dirichlet { tag, fix: [true, false], value: Arc::new(|_| [0.0, 0.0]) };
    Problem {
        materials: vec![Material::from_lame(LAMBDA, MU); mesh.n_cells()],
        dirichlet: vec![
            Dirichlet { tag: TOP, fix: [true, true], value: Arc::new(move |_| [0.0, lift]) },
            roller(LEFT),
            roller(RIGHT),
        ],
        neumann: Vec::new(),
        body_force: BodyForce::None,
        mesh,
    }
}

/// The frictionless joint of the block's base with `bond` (None: without).
fn base_joint(bond: Option<Bond>) -> ContactJoint {
    ContactJoint::uniform(vec![BOTTOM], Vec::new(), JointLaw::Frictionless, crate::nitsche_parameters()).with_bond(bond)
}

/// The block (0, 4) × (0, 1) on an 8 × 2 grid pulled up unevenly, u_y = −0.01 + 0.01 x on its
/// top: with [`BOND`] its joint is bonded, softening and broken at once.
fn wide_block_pulled_unevenly(order: usize) -> Problem {
    let mut problem = pulled_block(rectangle(0.0, 4.0, 0.0, 1.0, 8, 2, order), 0.0);
    problem.dirichlet[0].value = Arc::new(|x| [0.0, -0.01 + 0.01 * x[0]]);
    problem
}

/// The block pulled up by `lift`, solved at δ = 0 from a δ-continuation: the solution and the
/// joint's mean opening o and mean normal traction σ'^n.
fn pull(lift: f64, order: usize) -> (ContactSolution, f64, f64) {
    let problem = pulled_block(unit_square(4, order), lift);
    let disc = problem.discretise();
    let joint = base_joint(Some(BOND));
    let settings = Continuation { delta: 0.0, delta_start: 1e-3, newton: NewtonOptions::default(), path: None };
    let solution = solve_by_continuation(&problem, &disc, &joint, &settings)
        .unwrap_or_else(|e| panic!("P{order}, lift {lift}: {e}"));
    // the outward normal is −e_y: u^n = −o, and the traction pulls (p_c < 0)
    let length: f64 = solution.faces.iter().map(|f| f.length).sum();
    let opening = -solution.faces.iter().map(|f| f.normal_displacement * f.length).sum::<f64>() / length;
    let traction = -solution.faces.iter().map(|f| f.pressure * f.length).sum::<f64>() / length;
    (solution, opening, traction)
}

/// The exact pull of the block by `lift` U: with the stiffness k = λ + 2μ of the unit block
/// and σ = k (U − o) = T(o) on the joint, o = 0 while k U ≤ σ_t, o = (k U − σ_t)/(k − σ_t/o_c)
/// while o < o_c, and o = U (σ = 0) past it.
fn exact_pull(lift: f64) -> (f64, f64) {
    let (k, t, oc) = (LAMBDA + 2.0 * MU, BOND.tensile_strength, BOND.critical_opening());
    if k * lift <= t {
        return (0.0, k * lift);
    }
    let o = (k * lift - t) / (k - t / oc);
    if o < oc {
        (o, k * (lift - o))
    } else {
        (lift, 0.0)
    }
}

/// Two blocks pulled apart. Source: docs/method.md §1.13, the linear softening law σ'^n =
/// σ_t (1 − o/o_c) with o_c = 2 G_f/σ_t, and the uniaxial pull of a unit block on it (exact in
/// P1: u = (0, (U − o) y + o)). Goal: under displacement control, through the bonded state, the
/// peak, the softening branch and the broken joint, every solved (o, σ'^n) lies on the law and
/// on the exact pull to round-off, the face states say bonded, softening and broken where the
/// exact state is, and the area under the computed force–opening curve (trapezoids through
/// its points, the peak and the breaking point among them) equals G_f to 10⁻⁶. Parameters:
/// λ = μ = 1, σ_t = 0.01, G_f = 10⁻⁴ (o_c = 0.02), γ₀ = 100, θ = 0, δ = 0, 4 × 4 grid, P1 and
/// P2; U from 0 to 0.025 in 25 steps, with U = σ_t/3 (the peak) and U = o_c (broken) among them.
#[test]
fn two_blocks_pulled_apart_follow_the_softening_law() {
    let (t, oc, k) = (BOND.tensile_strength, BOND.critical_opening(), LAMBDA + 2.0 * MU);
    let mut lifts: Vec<f64> = (0..=25).map(|i| 0.001 * i as f64).collect();
    lifts.extend([t / k, oc]);
    lifts.sort_by(f64::total_cmp);
    for order in [1, 2] {
        let mut curve = Vec::new();
        for &lift in &lifts {
            let (solution, o, sigma) = pull(lift, order);
            let (o_exact, sigma_exact) = exact_pull(lift);
            println!("P{order} U = {lift:.5}: o = {o:.6e} (exact {o_exact:.6e}), σ = {sigma:.6e} (exact {sigma_exact:.6e}), {} Newton steps", solution.newton_steps());
            assert!((o - o_exact).abs() <= 1e-12 * oc, "P{order} U = {lift}: opening {o} against {o_exact}");
            assert!(
                (sigma - sigma_exact).abs() <= 1e-12 * t,
                "P{order} U = {lift}: traction {sigma} against {sigma_exact}"
            );
            let law = if o > 1e-12 * oc { t * (1.0 - o / oc).max(0.0) } else { sigma.min(t) };
            assert!((sigma - law).abs() <= 1e-12 * t, "P{order} U = {lift}: off the law");
            let BondLengths { bonded, process_zone: softening, broken } = BondLengths::of(&solution.faces);
            let expected = if o_exact <= 1e-15 {
                [1.0, 0.0, 0.0]
            } else if o_exact < oc * (1.0 - 1e-12) {
                [0.0, 1.0, 0.0]
            } else {
                [0.0, 0.0, 1.0]
            };
            // at the peak and at the breaking point the state is a tie
            if lift != t / k && lift != oc {
                assert_eq!(
                    [bonded, softening, broken].map(|l| (l * 1e9).round() / 1e9),
                    expected,
                    "P{order} U = {lift}"
                );
            }
            curve.push((o, sigma));
        }
        curve.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let area: f64 = curve.windows(2).map(|w| 0.5 * (w[1].0 - w[0].0) * (w[0].1 + w[1].1)).sum();
        println!("P{order}: area under the force–opening curve {area:.9e}, G_f {:.9e}", BOND.fracture_energy);
        assert!((area - BOND.fracture_energy).abs() <= 1e-6 * BOND.fracture_energy, "P{order}: area {area}");
    }
}

/// The bound with a cohesive joint. Source: docs/method.md §5.2 with the Γ_C traction of §1.13
/// (the bound holds for any traction law evaluated at u_h: it bounds the residual's dual norm).
/// Goal: on a wide block pulled up unevenly, at every full Newton step of the solve, the
/// reconstruction is equilibrated to round-off and η_tot ≥ the dual norm of the residual,
/// computed independently by the sharp reference; the converged state has bonded, softening and
/// broken parts. Parameters: the block (0, 4) × (0, 1) on an 8 × 2 grid, P1 and P2, with
/// u_y = −0.01 + 0.01 x on its top, Newton from u = 0 at δ = 10⁻³, then at δ = 10⁻⁶; θ = 0,
/// γ₀ = 100.
#[test]
fn eta_tot_bounds_the_residual_of_a_softening_joint() {
    for order in [1, 2] {
        let problem = wide_block_pulled_unevenly(order);
        let disc = problem.discretise();
        let joint = base_joint(Some(BOND));
        let (x, steps) = crate::full_steps::full_steps(&problem, &disc, &joint, &[1e-3, 1e-6]);
        let contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: 1e-6 });
        let lengths = BondLengths::of(&contact.face_states(&x));
        println!("P{order}: {lengths:?}");
        let all = [lengths.bonded, lengths.process_zone, lengths.broken];
        assert!(all.iter().all(|&l| l > 0.05), "P{order}: not every state is present: {lengths:?}");
        assert!(steps.len() >= 2, "P{order}: {} full steps", steps.len());
        crate::full_steps::assert_bounds(&format!("P{order}"), &steps);
    }
}

/// The limits of the bond. Source: docs/method.md §1.13: N(P) → q(P) as σ_t → 0 (|N − q| ≤
/// σ_t), and N(P) = P wherever P ≤ σ_t, the bonded interface (the joint held closed,
/// `Smoothing::CLOSED`). Goal: on the wide block pulled up unevenly (bonded, softening and
/// broken parts at σ_t = 0.01), the solution with σ_t = 10⁻⁹ is that of the joint without a
/// bond to 10⁻⁶ of max |u|, and the solution with σ_t = 10⁶ (G_f = 10⁴, o_c = 0.02) is that of
/// the bonded interface to 10⁻¹⁰ of max |u|. Parameters: as
/// `eta_tot_bounds_the_residual_of_a_softening_joint`, δ = 0 from a δ-continuation, P1 and P2.
#[test]
fn a_vanishing_bond_is_plain_contact_and_a_strong_one_a_bonded_interface() {
    use damfem::solve::newton;
    for order in [1, 2] {
        let problem = wide_block_pulled_unevenly(order);
        let disc = problem.discretise();
        let joint = base_joint;
        let settings = Continuation { delta: 0.0, delta_start: 1e-3, newton: NewtonOptions::default(), path: None };
        let solve = |bond| {
            solve_by_continuation(&problem, &disc, &joint(bond), &settings)
                .unwrap_or_else(|e| panic!("P{order}: {e}"))
                .x
        };
        let scale = solve(None).iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let distance = |a: &[f64], b: &[f64]| a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale;
        let weak = Bond { tensile_strength: 1e-9, fracture_energy: 1e-4 };
        let to_plain = distance(&solve(Some(weak)), &solve(None));
        let strong = Bond { tensile_strength: 1e6, fracture_energy: 1e4 };
        let closed = ContactProblem::new(&problem, &disc, &joint(None), Smoothing::CLOSED);
        let bonded = newton(&closed, vec![0.0; disc.dofs.n_free], &NewtonOptions::default()).expect("linear").x;
        let to_bonded = distance(&solve(Some(strong)), &bonded);
        println!("P{order}: σ_t = 1e-9 from plain contact {to_plain:.1e}, σ_t = 1e6 from the bonded interface {to_bonded:.1e}");
        assert!(to_plain <= 1e-6, "P{order}: {to_plain}");
        assert!(to_bonded <= 1e-10, "P{order}: {to_bonded}");
    }
}

/// The load path records where the holonomic bond heals. Source: docs/method.md §1.13 (D
/// follows the present opening; `PathPoint::healing`). Goal: a block clamped on its right side
/// and lifted by a body force opens its bond at the far end (softening there) at λ = 0; a
/// pressure on its top, brought on by λ, closes the joint again, and the path's last state
/// records a fall of a face's mean damage of more than 10⁻³, which the solve's lines turn into
/// a warning, while a path that only opens the joint records none. Parameters: the block
/// (0, 4) × (0, 1) on an 8 × 2 grid, P1, λ = μ = 1 with density 1, body force (0, 0.02), the
/// pressure 0.1 (0 for the path that only opens), [`BOND`], γ₀ = 100, δ = 10⁻⁶.
#[test]
fn the_load_path_records_where_the_bond_heals() {
    use damfem::contact::LoadPath;
    use damfem::elasticity::{Neumann, Traction};
    let healing = |pressure: f64| {
        let mesh = rectangle(0.0, 4.0, 0.0, 1.0, 8, 2, 1);
        let material = Material { density: 1.0, ..Material::from_lame(LAMBDA, MU) };
        let problem = Problem {
            materials: vec![material; mesh.n_cells()],
            dirichlet: vec![Dirichlet { tag: RIGHT, fix: [true, true], value: Arc::new(|_| [0.0, 0.0]) }],
            neumann: vec![Neumann { tag: TOP, traction: Traction::Constant([0.0, -pressure]) }],
            body_force: BodyForce::Acceleration([0.0, 0.02]),
            mesh,
        };
        let disc = problem.discretise();
        let path = Some(LoadPath { weight: [0.0, 0.02], trace: None });
        let settings = Continuation { delta: 1e-6, delta_start: 1e-3, newton: NewtonOptions::default(), path };
        let solution = solve_by_continuation(&problem, &disc, &base_joint(Some(BOND)), &settings)
            .unwrap_or_else(|e| panic!("pressure {pressure}: {e}"));
        let first = solution.path.first().map(|p| p.load_factor);
        let opened = BondLengths::of(&solution.faces);
        println!("pressure {pressure}: path from λ = {first:?}, {} states, {opened:?}", solution.path.len());
        solution.path.iter().map(|p| p.healing).fold(0.0, f64::max)
    };
    let (closing, opening) = (healing(0.1), healing(0.0));
    println!("largest healing: closed again {closing:.3e}, only opened {opening:.3e}");
    assert!(closing > 1e-3, "the bond closed again without healing: {closing}");
    assert_eq!(opening, 0.0, "a path that only opens the joint healed: {opening}");
}
