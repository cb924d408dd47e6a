//! Newton steps of the first stage of the δ path on a frictional joint, from u = 0 and from the
//! closed, sticking state.
//!
//! What it shows: for each scene given, meshed by gmsh at its own sizes (times SIZE_FACTOR if
//! given), the Newton steps at δ_start = 0.1 × the stress scale from u = 0 and from the closed,
//! sticking state (`ContactProblem::fully_active_start`), or why Newton stopped: the start from
//! rest is the default of `damfem solve`, the closed one its fallback when the first stage fails
//! from rest (docs/solver.md §4; measured in docs/results.md, "The closed start").
//!
//! Run: `cargo run --release --example closed_start -- SCENE.toml [SCENE.toml …] [--size-factor F]`
//! from the crate root; prints a markdown table.

use damfem::contact::projection::Smoothing;
use damfem::contact::ContactProblem;
use damfem::io::gmsh::mesh_geo;
use damfem::scene::Scene;
use damfem::solve::{newton, NewtonError, NewtonOptions};
use std::path::Path;

/// The Newton steps of a run, or how it ended without converging.
fn steps(run: Result<usize, NewtonError>) -> String {
    match run {
        Ok(n) => n.to_string(),
        Err(NewtonError::NotConverged { history, scale }) => {
            format!(
                "no convergence in {} (relative residual {:.2e})",
                history.len(),
                history[history.len() - 1].residual / scale
            )
        }
        Err(e) => e.to_string(),
    }
}

fn main() {
    let (mut size_factor, mut scenes) = (None, Vec::new());
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--size-factor" => size_factor = args.next().map(|f| f.parse::<f64>().expect("--size-factor F")),
            _ => scenes.push(arg),
        }
    }
    println!("| scene | unknowns | δ_start [Pa] | steps from u = 0 | steps from the closed, sticking state |");
    println!("|---|---|---|---|---|");
    for path in &scenes {
        let mut scene = Scene::load(Path::new(path)).unwrap_or_else(|e| panic!("{path}: {e}"));
        if let Some(f) = size_factor {
            scene.mesh.size_factor *= f;
        }
        let mesh = mesh_geo(&scene.geometry, &scene.mesh_options(), false, false).expect("gmsh meshes the scene");
        let (problem, joint) = scene.problem(mesh).unwrap_or_else(|e| panic!("{path}: {e}"));
        let joint = joint.expect("the scene has a joint");
        let disc = problem.discretise();
        let settings = scene.continuation(&problem, &disc.topology);
        let options = NewtonOptions { trace: None, ..settings.newton };
        let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: settings.delta_start });
        let from_rest = newton(&contact, vec![0.0; disc.dofs.n_free], &options).map(|r| r.iterations.len());
        let closed = contact.fully_active_start().expect("the closed, sticking problem is solved");
        let from_closed = newton(&contact, closed, &options).map(|r| r.iterations.len());
        println!(
            "| {path} | {} | {:.3e} | {} | {} |",
            disc.dofs.n_free,
            settings.delta_start,
            steps(from_rest),
            steps(from_closed)
        );
    }
}
