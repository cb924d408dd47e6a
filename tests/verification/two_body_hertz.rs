//! Two-body Hertz (docs/method.md §7, V4 on a deformable foundation): a half-disk pressed on
//! an elastic block, both meshed, with two-body Nitsche contact between the disk's arc and the
//! block's top.
//!
//! Source: the plane-strain Hertz solution for a cylinder of radius R on an elastic half-plane
//! (Johnson, Contact Mechanics, §5.2): with 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ and the force per
//! unit thickness F, b = 2√(R F/(π E*)) and p(x) = p₀ √(1 − x²/b²), p₀ = 2F/(π b).
//!
//! Geometry and mesh: tests/data/hertz_two_body.geo meshed by gmsh (order 2): the half-disk of
//! geo/hertz.geo (R = 8) on a block 64 × 32 whose top touches the arc at (0, −8); mesh size
//! 0.02 at the contact point on both bodies, so the meshes of the two sides do not match
//! (with 0.035 the fit is off by −0.61 % in b and +0.42 % in p₀; with 0.02, +0.01 % and
//! +0.11 %).
//! Materials: disk E₁ = 200, ν₁ = 0.3; block E₂ = 100, ν₂ = 0.2; no body force.
//! Boundary conditions: u = (0, −d) on the disk's top, the block clamped at its bottom, its
//! sides free. Joint: the block's top is the slave (its normal ν = (0, 1) is the exact
//! direction of the flat side, as the plane's normal of V4), the arc the master; the gap is
//! the vertical distance from the block's top to the arc; θ = 0, γ₀ = 100, δ = 10⁻⁶ S, reached
//! by δ-continuation from 10⁻² S.
//!
//! Why a finite block is a half-plane here: b and p₀ depend on the force only through the
//! curvature of the gap, 1/R. The block's finite size adds to the half-plane's surface
//! displacement a smooth field whose curvature over the contact zone is of order F/(E* L²)
//! (L the block's half-width and depth), that is (π/4)(b/L)² times 1/R: about 10⁻⁴ here
//! (b/L ≈ 0.02), far below the 1 % of the check.

use super::hertz::{fit_profile, moment_half_width, Sample};
use damfem::contact::projection::{negative_part, Smoothing};
use damfem::contact::{solve_by_continuation, ContactJoint, ContactSolution, Continuation, JointLaw, Linearisation};
use damfem::elasticity::{BodyForce, Dirichlet, Discretisation, Material, Problem};
use damfem::estimate::estimate_iterate;
use damfem::estimate::reference::{sharp_reference, REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS};
use damfem::io::gmsh::{mesh_geo, MeshOptions};
use damfem::solve::NewtonOptions;
use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;

const R: f64 = 8.0;
const HALF_WIDTH: f64 = 32.0;
const DISK: Material = Material { young: 200.0, poisson: 0.3, density: 0.0 };
const BLOCK: Material = Material { young: 100.0, poisson: 0.2, density: 0.0 };
const PUSH: f64 = 0.1;

/// Hertz half-width and peak pressure for the force F per unit thickness, with the combined
/// modulus 1/E* = Σ (1 − ν_i²)/E_i.
fn hertz(force: f64) -> (f64, f64) {
    let compliance = |m: Material| (1.0 - m.poisson * m.poisson) / m.young;
    let e_star = 1.0 / (compliance(DISK) + compliance(BLOCK));
    let b = 2.0 * (R * force / (PI * e_star)).sqrt();
    (b, 2.0 * force / (PI * b))
}

/// The disk on the block, meshed, and its joint (slave: the block's top).
fn disk_on_block() -> (Problem, ContactJoint) {
    let geo = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/hertz_two_body.geo");
    let options = MeshOptions { order: 2, ..Default::default() };
    let mesh = mesh_geo(&geo, &options, false, false).expect("gmsh meshes tests/data/hertz_two_body.geo");
    let tag = |dim: u8, name: &str| mesh.group(dim, name).unwrap_or_else(|| panic!("physical group {name}")).tag;
    let (top, bottom, arc, block_top, disk) =
        (tag(1, "top"), tag(1, "block_bottom"), tag(1, "arc"), tag(1, "block_top"), tag(2, "disk"));
    let problem = Problem {
        materials: mesh.cell_tags.iter().map(|&t| if t == disk { DISK } else { BLOCK }).collect(),
        dirichlet: vec![
            Dirichlet { tag: top, fix: [true; 2], value: Arc::new(|_| [0.0, -PUSH]) },
            Dirichlet { tag: bottom, fix: [true; 2], value: Arc::new(|_| [0.0; 2]) },
        ],
        neumann: vec![],
        body_force: BodyForce::None,
        mesh,
    };
    let joint = ContactJoint::uniform(vec![block_top], vec![arc], JointLaw::Frictionless, crate::nitsche_parameters());
    (problem, joint)
}

/// [`disk_on_block`] solved along the δ path down to 10⁻⁶ of its stress scale: the problem,
/// its discretisation, the joint and the solution.
fn solved_disk_on_block() -> (Problem, Discretisation, ContactJoint, ContactSolution) {
    let (problem, joint) = disk_on_block();
    let disc = problem.discretise();
    let scale = problem.stress_scale(&disc.topology);
    let settings =
        Continuation { delta: 1e-6 * scale, delta_start: 1e-2 * scale, newton: NewtonOptions::default(), path: None };
    let solution = solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("{e}"));
    (problem, disc, joint, solution)
}

/// Two-body Hertz. Source, geometry, parameters: the module's header.
/// Goal: the half-width and the peak pressure of a least-squares fit of the Hertz profile to
/// −[P_γ(u_h)]₋ (sampled with the contact quadrature, split where P_γ(u_h) = 0, on the pieces
/// with |x| < 2 b_m, b_m = 2 (∫p x²/∫p)^½) are within 1 % of Hertz's for the computed force,
/// and that force balances the reaction on the disk's top.
#[test]
fn two_body_hertz_half_width_and_peak_pressure() {
    let (problem, disc, _, solution) = solved_disk_on_block();
    let nitsche = &solution.nitsche;
    // the block's top has ν = (0, 1): the pressure pushes the block down and the disk up
    let force: f64 =
        nitsche.faces.iter().zip(&solution.faces).map(|(f, s)| s.pressure * f.length * f.direction[1]).sum();
    let u_full = disc.dofs.expand(&solution.x);
    let (mut profile, mut dofs): (Vec<Sample>, Vec<usize>) = (Vec::new(), Vec::new());
    for k in 0..nitsche.faces.len() {
        nitsche.face_dofs(&problem.mesh, k, &mut dofs);
        let u: Vec<f64> = dofs.iter().map(|&g| u_full[g]).collect();
        let u = nitsche.local(k, &u, None);
        for (s, w) in nitsche.quadrature(k, &u, Smoothing::NONE) {
            let point = nitsche.point(k, s);
            profile.push((point.x[0], -negative_part(nitsche.p_gamma(k, &point, &u)), w));
        }
    }
    let reaction = top_reaction(&problem, &u_full);
    let (b, p0) = hertz(force);
    let b_m = moment_half_width(&profile);
    profile.retain(|s| s.0.abs() < 2.0 * b_m);
    let (p0_fit, b_fit) = fit_profile(&profile, 0.5 * b_m, 1.5 * b_m);
    let rel = |v: f64, exact: f64| (v - exact) / exact;
    println!(
        "{} cells, {} contact pieces; F = {force:.6}, reaction on the top {reaction:.6}; b/R = {:.4}, b/L = {:.4}",
        problem.mesh.n_cells(),
        nitsche.faces.len(),
        b / R,
        b / HALF_WIDTH
    );
    println!(
        "Hertz b = {b:.5}, p0 = {p0:.5}; fit b = {b_fit:.5} ({:+.2} %), p0 = {p0_fit:.5} ({:+.2} %)",
        100.0 * rel(b_fit, b),
        100.0 * rel(p0_fit, p0)
    );
    assert!((force - reaction).abs() <= 1e-6 * force, "contact force {force} against the top's reaction {reaction}");
    assert!((0.03..=0.1).contains(&(b / R)), "b/R = {} outside the Hertz range of this test", b / R);
    assert!(rel(b_fit, b).abs() <= 0.01, "half-width off by {:.2} %", 100.0 * rel(b_fit, b));
    assert!(rel(p0_fit, p0).abs() <= 0.01, "peak pressure off by {:.2} %", 100.0 * rel(p0_fit, p0));
}

/// The upward reaction on the disk's top: −Σ (K u_h)_i over its y dofs, K assembled without
/// Dirichlet conditions.
fn top_reaction(problem: &Problem, u_full: &[f64]) -> f64 {
    let top = problem.dirichlet[0].tag;
    let unconstrained = Problem { dirichlet: vec![], ..problem.clone() };
    let all_dofs = unconstrained.discretise();
    let stiffness = unconstrained.assemble(&all_dofs);
    let mut ku = vec![0.0; u_full.len()];
    all_dofs.pattern.multiply(&stiffness.values, u_full, &mut ku);
    let top_y: std::collections::BTreeSet<usize> = (0..problem.mesh.n_facets())
        .filter(|&f| problem.mesh.facet_tags[f] == top)
        .flat_map(|f| problem.mesh.facet(f).iter().map(|&n| 2 * n + 1))
        .collect();
    -top_y.iter().map(|&i| ku[i]).sum::<f64>()
}

/// The estimate across the Hertz joint. Source: docs/method.md §5.6.
/// Goal: at P2 the reconstruction is equilibrated on both bodies to round-off and η_tot bounds
/// the sharp reference (the dual norm of the residual by its Riesz representative on a mesh
/// refined where it concentrates); I_eff is printed.
/// Parameters: the module's header.
#[test]
fn two_body_hertz_estimate_bounds_the_residual() {
    let (problem, disc, joint, solution) = solved_disk_on_block();
    let state = Linearisation::new(&problem, &disc, &solution.nitsche, solution.smoothing, &solution.x_prev);
    let estimate = estimate_iterate(&problem, &disc, &solution.x, Some(&state)).unwrap_or_else(|e| panic!("{e}"));
    let eq = estimate.equilibration;
    let worst = eq.divergence.max(eq.normal_continuity).max(eq.contact).max(eq.compatibility);
    let u = problem.displacement(&disc, &solution.x);
    let sharp = sharp_reference(&problem, &u, Some(&joint), REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS)
        .unwrap_or_else(|e| panic!("{e}"));
    let (eta, reference) = (estimate.estimators.global().tot, sharp.norm());
    println!(
        "worst equilibration {worst:.1e}; η_tot {eta:.4e}, reference {reference:.4e} (converged {}), I_eff {:.3}",
        sharp.converged,
        eta / reference
    );
    assert!(worst < 1e-10, "equilibration {worst:.2e}");
    assert!(eta >= reference, "η_tot {eta:.4e} < reference {reference:.4e}");
}
