//! Newton steps of the contact solve from a cold start, for γ₀ from 1 to 10³, and from the
//! fully active state.
//!
//! What it shows: Scene A (`geo/scene_a.toml`: gravity dam, frictionless Nitsche contact on
//! the heel side of the base, P2) meshed by gmsh at size factor 0.275 (99 608 unknowns), δ =
//! 10⁻⁴ × stress scale, θ = 0, rtol = 10⁻¹⁰, at most 100 steps. For γ₀ ∈ {1, 10, 100, 1000}: the Newton steps and
//! wall time of the solve from u = 0, and from the fully active start u_a (every point of Γ_C
//! held closed: the linear problem with [P_γ] replaced by P_γ, one solve); and the distance
//! ‖u_cold − u_a-start‖ / ‖u_cold‖ between the two converged displacements; and nested
//! iteration: the cold solve on the mesh of size factor ×3 (about 9 times fewer unknowns),
//! its displacement interpolated to the fine mesh (`fem::transfer`) as the start there. The
//! factorisation of the stiffness with its contact layer (once per mesh and γ₀, printed on
//! stderr) is left out of the fine solves' times; the coarse solve's time includes its own.
//!
//! Run: `cargo run --release --example newton_start -- [SIZE_FACTOR]` from the crate root
//! (default 0.275); prints a markdown table.

use damfem::contact::projection::Smoothing;
use damfem::contact::ContactProblem;
use damfem::elasticity::{Discretisation, Problem};
use damfem::fem::dofs::FIXED;
use damfem::fem::transfer::interpolate;
use damfem::io::gmsh::{mesh_geo, MeshOptions};
use damfem::mesh::Mesh;
use damfem::scene::Scene;
use damfem::solve::{newton, NewtonOptions, NonlinearSystem};
use std::path::Path;
use std::time::Instant;

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt()
}

/// Scene A meshed by gmsh at `size_factor`.
fn mesh(scene: &Scene, size_factor: f64) -> Mesh {
    let m = &scene.mesh;
    let options =
        MeshOptions { order: m.order, size_factor, size_min: m.size_min, size_max: m.size_max, algorithm: m.algorithm };
    mesh_geo(&scene.geometry, &options, false, false).expect("gmsh meshes Scene A")
}

/// The free unknowns of the displacement `u` of `old` interpolated at the nodes of `problem`.
fn transferred(problem: &Problem, disc: &Discretisation, old: &Mesh, u: &[[f64; 2]]) -> Vec<f64> {
    let values = interpolate(old, u, &problem.mesh.points);
    let mut x = vec![0.0; disc.dofs.n_free];
    for (dof, &k) in disc.dofs.free.iter().enumerate() {
        if k != FIXED {
            x[k] = values[dof / 2][dof % 2];
        }
    }
    x
}

fn main() {
    let size_factor: f64 = std::env::args().nth(1).map_or(0.275, |a| a.parse().expect("SIZE_FACTOR is a number"));
    let scene = Scene::load(Path::new("geo/scene_a.toml")).expect("run from the crate root: geo/scene_a.toml");
    let (problem, joint) = scene.problem(mesh(&scene, size_factor)).expect("Scene A is valid");
    let coarse_mesh = mesh(&scene, 3.0 * size_factor);
    let (coarse, _) = scene.problem(coarse_mesh.clone()).expect("Scene A is valid");
    let coarse_disc = coarse.discretise();
    let joint = joint.expect("Scene A has a contact curve");
    let disc = problem.discretise();
    let settings = scene.continuation(&problem, &disc.topology);
    // from u = 0 at γ₀ = 10³ the default 50 steps are too few at 10⁵ unknowns
    let options = NewtonOptions { max_iter: 100, ..settings.newton };
    println!(
        "Scene A, P2, {} unknowns, δ = {:.3e} Pa, θ = 0, rtol = 10⁻¹⁰, at most 100 steps\n",
        disc.dofs.n_free, settings.delta
    );
    println!("| γ₀ | Newton steps from u = 0 | time [s] | Newton steps from the fully active state (+ its solve) | time [s] | ‖u_cold − u_active‖ / ‖u_cold‖ | coarse steps ({} unknowns) + fine steps from its solution | time [s] | ‖u_cold − u_nested‖ / ‖u_cold‖ |", coarse_disc.dofs.n_free);
    println!("|---|---|---|---|---|---|---|---|---|");
    for gamma0 in [1.0, 10.0, 100.0, 1000.0] {
        let mut joint = joint.clone();
        joint.parameters.gamma0 = gamma0;
        let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: settings.delta });
        let (clock, schur) = (Instant::now(), contact.schur().is_some());
        let setup = clock.elapsed().as_secs_f64();
        eprintln!("γ₀ = {gamma0}: Cholesky with the contact layer last and S₀ in {setup:.2} s (used: {schur})");
        let clock = Instant::now();
        let cold = newton(&contact, vec![0.0; disc.dofs.n_free], &options).expect("Newton converges");
        let cold_time = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let start = contact.fully_active_start().expect("the fully active state");
        let warm = newton(&contact, start, &options).expect("Newton converges");
        let warm_time = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let coarse_contact = ContactProblem::new(&coarse, &coarse_disc, &joint, Smoothing { delta: settings.delta });
        let x0 = vec![0.0; coarse_disc.dofs.n_free];
        let first = newton(&coarse_contact, x0, &options).expect("Newton converges");
        let start = transferred(&problem, &disc, &coarse_mesh, &coarse.displacement(&coarse_disc, &first.x));
        let nested = newton(&contact, start, &options).expect("Newton converges");
        let nested_time = clock.elapsed().as_secs_f64();
        let norm = distance(&cold.x, &vec![0.0; cold.x.len()]);
        println!(
            "| {gamma0} | {} | {cold_time:.2} | {} + 1 | {warm_time:.2} | {:.1e} | {} + {} | {nested_time:.2} | {:.1e} |",
            cold.iterations.len(),
            warm.iterations.len(),
            distance(&cold.x, &warm.x) / norm,
            first.iterations.len(),
            nested.iterations.len(),
            distance(&cold.x, &nested.x) / norm,
        );
    }
}
