//! The pipeline in one page: scene → mesh → solve → estimate → ParaView file.
//!
//! What it shows: the library calls behind `damfem solve --estimate` on Scene A (a gravity
//! dam on rigid rock, frictionless Nitsche contact on its base, P2).
//!
//! Run: `cargo run --release --example tutorial [OUTPUT.vtu]` from the crate root (default
//! `out/tutorial.vtu`). Key number: η_tot, the guaranteed bound of the error in the dual norm
//! of the residual [Pa·m], printed with the contact length on the last line.

use anyhow::{Context, Result};
use damfem::contact::solve_by_continuation;
use damfem::elasticity::kernels::von_mises;
use damfem::elasticity::stress::cell_mean_stress;
use damfem::estimate::estimate_iterate;
use damfem::io::gmsh::mesh_geo;
use damfem::io::vtu::{write_mesh_vtu, Field};
use damfem::scene::Scene;
use std::path::{Path, PathBuf};

fn main() -> Result<()> {
    let output = std::env::args().nth(1).map_or_else(|| PathBuf::from("out/tutorial.vtu"), PathBuf::from);
    let summary = run(&output)?;
    println!(
        "{} unknowns, {} Newton steps, contact length {:.3} m, eta_tot = {:.4e} Pa m (equilibrated to {:.1e}); wrote {}",
        summary.unknowns,
        summary.newton_steps,
        summary.contact_length,
        summary.eta_tot,
        summary.equilibration,
        output.display()
    );
    Ok(())
}

/// The key numbers of a run.
pub struct Summary {
    pub unknowns: usize,
    pub newton_steps: usize,
    /// Length of the contact zone \[m\].
    pub contact_length: f64,
    /// η_tot [Pa·m].
    pub eta_tot: f64,
    /// The largest relative violation of the equilibration checks.
    pub equilibration: f64,
}

/// Solves Scene A, estimates its error and writes `output`.
pub fn run(output: &Path) -> Result<Summary> {
    // 1. Scene: materials, boundary roles and loads by physical-group name
    let scene = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("geo/scene_a.toml"))?;

    // 2. Mesh: gmsh meshes the scene's .geo file at the scene's degree
    let mesh = mesh_geo(&scene.geometry, &scene.mesh_options(), false, false)?;

    // 3. Problem: the elasticity problem and its contact joint; dofs and sparsity pattern
    let (problem, joint) = scene.problem(mesh)?;
    let joint = joint.context("Scene A has a contact curve")?;
    let disc = problem.discretise();

    // 4. Solve: Newton on the Nitsche contact problem along the δ path of the scene
    let continuation = scene.continuation(&problem, &disc.topology);
    let solution = solve_by_continuation(&problem, &disc, &joint, &continuation)?;

    // 5. Estimate: equilibrated stresses and the six estimators, with the checks
    let state = solution.linearisation(&problem, &disc);
    let estimate = estimate_iterate(&problem, &disc, &solution.x, Some(&state))?;
    let eta = estimate.estimators.global();
    let worst = estimate.equilibration.worst(problem.mesh.order);

    // 6. Write: displacement at the nodes, von Mises stress and η_tot per cell
    let u = problem.displacement(&disc, &solution.x);
    let von_mises = cell_mean_stress(&problem, &u).iter().map(|&s| von_mises(s)).collect();
    let cells = [
        Field::scalar("von_mises", "Pa", von_mises),
        Field::scalar("eta_tot", "Pa m", estimate.estimators.tot.clone()),
    ];
    if let Some(dir) = output.parent() {
        std::fs::create_dir_all(dir)?;
    }
    write_mesh_vtu(output, &problem.mesh, &[Field::vector("displacement", "m", u)], &cells)?;

    Ok(Summary {
        unknowns: disc.dofs.n_free,
        newton_steps: solution.newton_steps(),
        contact_length: solution.contact_length(),
        eta_tot: eta.tot,
        equilibration: worst,
    })
}
