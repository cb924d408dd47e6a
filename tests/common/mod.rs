//! Helpers shared by the integration tests.
#![allow(dead_code)]

/// Least-squares slope of log(e) against log(h).
pub fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    damfem::adapt::history::loglog_slope(&h.iter().copied().zip(e.iter().copied()).collect::<Vec<_>>())
}

/// max over the nodes of max_i |u_h,i − u_i| for the exact solution `u`.
pub fn max_nodal_error(points: &[[f64; 2]], u_h: &[[f64; 2]], u: impl Fn([f64; 2]) -> [f64; 2]) -> f64 {
    points.iter().zip(u_h).map(|(&x, v)| (v[0] - u(x)[0]).abs().max((v[1] - u(x)[1]).abs())).fold(0.0, f64::max)
}

/// The mesh gmsh makes of `scene`'s geometry at degree `order`, its sizes times `size_factor`.
pub fn mesh_scene(scene: &damfem::scene::Scene, order: usize, size_factor: f64) -> damfem::mesh::Mesh {
    use damfem::io::gmsh::{mesh_geo, MeshOptions};
    let m = &scene.mesh;
    let options =
        MeshOptions { order, size_factor, size_min: m.size_min, size_max: m.size_max, algorithm: m.algorithm };
    mesh_geo(&scene.geometry, &options, false, false).unwrap_or_else(|e| panic!("{e}"))
}

/// A scene of the repository meshed by gmsh and solved as `damfem solve` solves it.
pub struct SolvedScene {
    pub problem: damfem::elasticity::Problem,
    pub disc: damfem::elasticity::Discretisation,
    pub joint: damfem::contact::ContactJoint,
    pub solution: damfem::contact::ContactSolution,
}

/// Solves the scene `path` (relative to the crate) with a contact joint at degree `order`, its
/// mesh sizes times `size_factor`.
pub fn solve_scene(path: &str, order: usize, size_factor: f64) -> SolvedScene {
    let scene = damfem::scene::Scene::load(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path))
        .unwrap_or_else(|e| panic!("{e}"));
    let (problem, joint) = scene.problem(mesh_scene(&scene, order, size_factor)).unwrap_or_else(|e| panic!("{e}"));
    let joint = joint.expect("a contact joint");
    let disc = problem.discretise();
    let solution =
        damfem::contact::solve_by_continuation(&problem, &disc, &joint, &scene.continuation(&problem, &disc.topology))
            .unwrap_or_else(|e| panic!("{path}: {e}"));
    SolvedScene { problem, disc, joint, solution }
}
