//! The adaptive loop on real gmsh meshes: physical groups survive remeshing, refinement goes
//! where the estimators point, warm starts cut Newton steps, and failures stop the run with
//! the earlier steps kept.

use damfem::adapt::geo::GeoMesher;
use damfem::adapt::{self, AdaptError, AdaptSettings, Mesher, Model, Refinement, StepRecord};
use damfem::contact::nitsche::NitscheParameters;
use damfem::elasticity::Problem;
use damfem::mesh::Mesh;
use damfem::scene::Scene;
use damfem::solve::NewtonOptions;
use std::path::Path;

fn scene(name: &str, order: usize) -> Scene {
    let mut scene = Scene::load(Path::new(&format!("geo/{name}.toml"))).expect("scene");
    scene.mesh.order = order;
    scene
}

fn mesher(scene: &Scene, refinement: Refinement) -> GeoMesher {
    GeoMesher {
        geometry: scene.geometry.clone(),
        options: scene.mesh_options(),
        refinement,
        verbose: false,
        allow_system_calls: false,
    }
}

/// Runs `steps` adaptive steps on `scene`, giving every step's mesh to `inspect`.
fn run(
    settings: AdaptSettings,
    mesher: &mut dyn Mesher,
    model: &dyn Model,
    mut inspect: impl FnMut(&Mesh, &StepRecord),
) -> Result<Vec<StepRecord>, AdaptError> {
    adapt::run(&settings, mesher, model, |step| {
        inspect(&step.problem.mesh, step.record);
        Ok(())
    })
}

fn steps(n: usize) -> AdaptSettings {
    AdaptSettings { steps: n, ..Default::default() }
}

fn tag(mesh: &Mesh, name: &str) -> i32 {
    mesh.group(1, name).unwrap_or_else(|| panic!("group {name} lost")).tag
}

#[test]
fn physical_groups_survive_every_remesh() {
    let scene = scene("scene_a", 1);
    let lengths = [("base", 32.0), ("toe", 8.0), ("upstream", 50.0), ("crest", 5.0), ("downstream", 35f64.hypot(50.0))];
    let mut seen = Vec::new();
    let history = run(steps(4), &mut mesher(&scene, Refinement::Adaptive), &scene, |mesh, record| {
        assert_eq!(mesh.group_names(1), ["base", "toe", "downstream", "crest", "upstream"], "step {}", record.step);
        assert_eq!(mesh.group_names(2), ["concrete"]);
        for (name, length) in lengths {
            let measured = mesh.boundary_length(tag(mesh, name));
            assert!((measured - length).abs() <= 1e-9 * length, "step {}: {name} has length {measured}", record.step);
        }
        let area: f64 = (0..mesh.n_cells()).map(|c| mesh.cell_area(c)).sum();
        assert!((area - 1125.0).abs() < 1e-9 * 1125.0);
        seen.push(mesh.n_cells());
    })
    .expect("adaptive run");
    assert_eq!(history.len(), 4);
    assert!(seen.windows(2).all(|w| w[1] > w[0]), "cells per step {seen:?}");
}
