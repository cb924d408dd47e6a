//! Nested iteration (docs/solver.md §4): the contact solve of `damfem solve` started on
//! coarser meshes of the scene's geometry, or on the degree-1 problem of a `.msh`.

use damfem::contact::{solve_by_continuation, ContactSolution};
use damfem::io::gmsh::{mesh_geo, read_msh, save_geo_mesh, MeshOptions};
use damfem::mesh::midpoints::elevate_to_p2;
use damfem::mesh::Mesh;
use damfem::scene::Scene;
use std::path::Path;

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>().sqrt()
}

/// The contact solve of `scene` on `mesh` from u = 0 and from its coarse levels, and the
/// number of free unknowns.
fn cold_and_nested(scene: &Scene, mesh: Mesh) -> (ContactSolution, ContactSolution, f64) {
    let (problem, joint) = scene.problem(mesh).unwrap_or_else(|e| panic!("{e}"));
    let (disc, joint) = (problem.discretise(), joint.expect("Scene A has a contact curve"));
    let settings = scene.continuation(&problem, &disc.topology);
    let cold = solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("{e}"));
    let nested = scene.solve_contact(&problem, &disc, &joint, &settings, false).unwrap_or_else(|e| panic!("{e}"));
    (cold, nested, disc.dofs.n_free as f64)
}

/// The nested solve ends at the cold solution, ‖u_cold − u_nested‖ ≤ 10⁻⁹ ‖u_cold‖, in fewer
/// steps on the given mesh.
fn assert_same_solution_in_fewer_steps(cold: &ContactSolution, nested: &ContactSolution) {
    assert!(nested.newton_steps() < cold.newton_steps());
    let relative = distance(&cold.x, &nested.x) / distance(&cold.x, &vec![0.0; cold.x.len()]);
    assert!(relative <= 1e-9, "‖u_cold − u_nested‖ / ‖u_cold‖ = {relative:.1e}");
}

/// The nested start reaches the cold solution. Source: docs/solver.md §4 (coarse levels 1.5
/// and 1.5 × 2 times coarser here, solved to ‖F‖ ≤ 10⁻³ ‖b‖; Newton on the given mesh to the
/// scene's tolerance). Goal: `Scene::solve_contact` solves the levels the rule gives, each
/// with ≥ 1 000 unknowns, and ends at the solution of the solve from u = 0 to the Newton
/// tolerance, in fewer steps on the given mesh. Parameters: Scene A (geo/scene_a.toml: P2,
/// 70 m flood, frictionless, γ₀ = 100, θ = 0, δ = 10⁻⁴ S, rtol = 10⁻¹⁰) meshed by gmsh at size
/// factor 0.6 (about 2·10⁴ unknowns: 1.5 × 4 times coarser would leave fewer than 1 000);
/// ‖u_cold − u_nested‖ ≤ 10⁻⁹ ‖u_cold‖.
#[test]
fn nested_start_reaches_the_cold_solution() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("geo/scene_a.toml");
    let mut scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    scene.mesh.size_factor = 0.6;
    let mesh = mesh_geo(&scene.geometry, &scene.mesh_options(), false, false).expect("gmsh meshes scene A");
    let (cold, nested, n) = cold_and_nested(&scene, mesh);
    let levels: Vec<f64> = nested.coarse.iter().map(|c| c.unknowns as f64).collect();
    println!(
        "{n} unknowns: {} steps from u = 0; nested: {:?} on the coarse levels, then {}",
        cold.newton_steps(),
        nested.coarse,
        nested.newton_steps()
    );
    assert_eq!(levels.len(), 2, "two coarse levels for {n} unknowns");
    assert!(levels[0] >= 1000.0, "the coarsest level has {} unknowns", levels[0]);
    // about N / (1.5 × 2)² and N / 1.5² unknowns
    for (level, ratio) in levels.iter().zip([3.0, 1.5]) {
        let expected = n / (ratio * ratio);
        assert!((level / expected - 1.0).abs() < 0.15, "a level of {level} unknowns, expected about {expected:.0}");
    }
    assert_same_solution_in_fewer_steps(&cold, &nested);
}

/// A degree-2 mesh read from a `.msh` starts from the degree-1 problem on its triangles.
/// Source: docs/solver.md §4 (the degree-1 level of a `.msh`, solved to ‖F‖ ≤ 10⁻³ ‖b‖, its
/// solution a degree-2 field of the same triangles). Goal: `Scene::solve_contact` on the
/// order-1 `.msh` that gmsh writes, raised to degree 2 as `--order 2` raises it, solves one
/// coarse level, of degree 1 and about N / 4 unknowns, then ends at the solution of the solve
/// from u = 0 to the Newton tolerance in fewer steps on the given mesh. Parameters: Scene A
/// (geo/scene_a.toml: 70 m flood, frictionless, γ₀ = 100, θ = 0, δ = 10⁻⁴ S, rtol = 10⁻¹⁰)
/// meshed by gmsh at order 1 and size factor 0.6 (about 2·10⁴ unknowns at degree 2);
/// ‖u_cold − u_nested‖ ≤ 10⁻⁹ ‖u_cold‖.
#[test]
fn msh_starts_from_its_degree_one_problem() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("geo/scene_a.toml");
    let mut scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let dir = std::env::temp_dir().join(format!("damfem-nested-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let msh = dir.join("scene_a.msh");
    let options = MeshOptions { order: 1, size_factor: 0.6, ..scene.mesh_options() };
    save_geo_mesh(&scene.geometry, &options, &msh, false, false).expect("gmsh meshes scene A");
    let mesh = elevate_to_p2(&read_msh(&msh, false).expect("gmsh reads its .msh"));
    std::fs::remove_dir_all(&dir).ok();
    scene.geometry = msh;
    let (cold, nested, n) = cold_and_nested(&scene, mesh);
    println!(
        "{n} unknowns: {} steps from u = 0; from the degree-1 level: {:?}, then {}",
        cold.newton_steps(),
        nested.coarse,
        nested.newton_steps()
    );
    assert_eq!(nested.coarse.len(), 1, "one coarse level for a .msh");
    let level = nested.coarse[0];
    assert_eq!(level.order, 1);
    let ratio = n / level.unknowns as f64;
    assert!((ratio / 4.0 - 1.0).abs() < 0.15, "{n} unknowns against {} on the degree-1 level", level.unknowns);
    assert_same_solution_in_fewer_steps(&cold, &nested);
}
