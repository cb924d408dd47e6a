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

/// Cells per unit area within `r` of `p`, over the mean cells per unit area.
fn relative_density(mesh: &Mesh, p: [f64; 2], r: f64) -> f64 {
    let centroid = |c: usize| {
        let v = mesh.cell_vertices(c);
        [(v[0][0] + v[1][0] + v[2][0]) / 3.0, (v[0][1] + v[1][1] + v[2][1]) / 3.0]
    };
    let near = (0..mesh.n_cells()).filter(|&c| damfem::mesh::distance(centroid(c), p) < r).count() as f64;
    let area: f64 = (0..mesh.n_cells()).map(|c| mesh.cell_area(c)).sum();
    (near / (0.5 * std::f64::consts::PI * r * r)) / (mesh.n_cells() as f64 / area)
}

#[test]
fn refinement_concentrates_at_the_junction_and_the_end_of_the_contact_zone() {
    // Scene A lifts off at the heel (x < 11.3) and just before the anchored toe (30.4 < x < 32):
    // the Γ_D/Γ_C junction at (32, 0) and the contact end at x ≈ 30.4 are the singular points
    let scene = scene("scene_a", 1);
    let (mut first, mut last) = (None, None);
    run(steps(6), &mut mesher(&scene, Refinement::Adaptive), &scene, |mesh, _| {
        let density = relative_density(mesh, [31.0, 0.0], 2.0);
        first.get_or_insert(density);
        last = Some(density);
    })
    .expect("adaptive run");
    let (first, last) = (first.unwrap(), last.unwrap());
    eprintln!("relative cell density within 2 m of (31, 0): {first:.1} -> {last:.1}");
    assert!(last > 4.0 * first, "{first} -> {last}");
}
