//! Newton steps of the contact solve from a cold start and from nested iteration, for γ₀ from
//! 1 to 10³.
//!
//! What it shows: Scene A (`geo/scene_a.toml`: gravity dam, frictionless Nitsche contact on
//! the heel side of the base, 70 m flood, P2) meshed by gmsh at size factor 0.275 (99 608
//! unknowns), δ = 10⁻⁴ × stress scale, θ = 0, rtol = 10⁻¹⁰, at most 100 steps. For γ₀ ∈ {1,
//! 10, 100, 1000}: the Newton steps and wall time of the solve from u = 0
//! (`contact::solve_by_continuation`), and of the solve of `damfem solve`
//! (`Scene::solve_contact`: nested iteration on the geometry meshed 1.5 and 3 times coarser
//! here, 1.5 × 4^k in general (docs/solver.md §4), each solution interpolated as the start
//! of the next), with the steps on each coarser mesh and ‖u_cold − u_nested‖ / ‖u_cold‖. Each
//! time includes the factorisation of the stiffness with its contact layer; the nested one
//! also includes gmsh's coarse meshes.
//!
//! Run: `cargo run --release --example newton_start -- [SIZE_FACTOR]` from the crate root
//! (default 0.275); prints a markdown table.

use damfem::contact::{solve_by_continuation, ContactSolution};
use damfem::io::gmsh::mesh_geo;
use damfem::scene::Scene;
use std::path::Path;
use std::time::Instant;

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt()
}

/// The solution of `solve` and its wall time.
fn timed(solve: impl FnOnce() -> ContactSolution) -> (ContactSolution, f64) {
    let clock = Instant::now();
    let solution = solve();
    (solution, clock.elapsed().as_secs_f64())
}

fn main() {
    let size_factor: f64 = std::env::args().nth(1).map_or(0.275, |a| a.parse().expect("SIZE_FACTOR is a number"));
    let mut scene = Scene::load(Path::new("geo/scene_a.toml")).expect("run from the crate root: geo/scene_a.toml");
    scene.mesh.size_factor = size_factor;
    scene.contact.max_iter = 100;
    let mesh = mesh_geo(&scene.geometry, &scene.mesh_options(), false, false).expect("gmsh meshes Scene A");
    let (problem, joint) = scene.problem(mesh).expect("Scene A is valid");
    let disc = problem.discretise();
    let mut settings = scene.continuation(&problem, &disc.topology);
    println!(
        "Scene A, P2, {} unknowns, δ = {:.3e} Pa, θ = 0, rtol = 10⁻¹⁰, at most 100 steps\n",
        disc.dofs.n_free, settings.delta
    );
    println!("| γ₀ | Newton steps from u = 0 | time [s] | steps on the coarser meshes (unknowns) | fine steps from nested iteration | time [s] | ‖u_cold − u_nested‖ / ‖u_cold‖ |");
    println!("|---|---|---|---|---|---|---|");
    for gamma0 in [1.0, 10.0, 100.0, 1000.0] {
        let mut joint = joint.clone().expect("Scene A has a contact curve");
        joint.laws.iter_mut().for_each(|c| c.parameters.gamma0 = gamma0);
        scene.contact.gamma0 = gamma0;
        settings.newton.max_iter = 100;
        let (cold, cold_time) =
            timed(|| solve_by_continuation(&problem, &disc, &joint, &settings).expect("Newton converges"));
        let (nested, nested_time) =
            timed(|| scene.solve_contact(&problem, &disc, &joint, &settings, false).expect("Newton converges"));
        let coarse: Vec<String> =
            nested.coarse.iter().map(|c| format!("{} ({})", c.newton_steps, c.unknowns)).collect();
        println!(
            "| {gamma0} | {} | {cold_time:.2} | {} | {} | {nested_time:.2} | {:.1e} |",
            cold.newton_steps(),
            coarse.join(", "),
            nested.newton_steps(),
            distance(&cold.x, &nested.x) / distance(&cold.x, &vec![0.0; cold.x.len()]),
        );
    }
}
