//! Parallel assembly: the same bits on any number of threads.

use crate::common::mesh_scene;
use damfem::fem::sparse::LinearSystem;
use damfem::scene::Scene;
use std::path::Path;

/// K and b of `problem` assembled on a pool of `threads` threads.
fn assemble_on(threads: usize, problem: &damfem::elasticity::Problem) -> LinearSystem {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
    pool.install(|| problem.assemble(&problem.discretise()))
}

/// Assembly on 1, 2 and 3 threads. Source: src/fem/sparse.rs (each task owns a range of columns
/// and adds the cells of its range in increasing order, so every entry sums the same terms in
/// the same order). Goal: the stiffness and load are bit for bit independent of the number of
/// threads. Problem: Scene A
/// (`geo/scene_a.toml`, gmsh's node numbering, P2 and P1, size factor 1: about 8 000 and 2 000
/// unknowns), gravity and the 70 m flood. Checks: the values and the right-hand sides of 2 and
/// 3 threads equal those of 1 thread exactly.
#[test]
fn assembly_is_identical_on_one_two_and_three_threads() {
    let scene = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("geo/scene_a.toml")).expect("Scene A");
    for order in [2, 1] {
        let (problem, _) = scene.problem(mesh_scene(&scene, order, 1.0)).expect("Scene A is valid");
        let one = assemble_on(1, &problem);
        for threads in [2, 3] {
            let many = assemble_on(threads, &problem);
            assert!(one.values == many.values, "P{order}: K differs on {threads} threads");
            assert!(one.rhs == many.rhs, "P{order}: b differs on {threads} threads");
        }
        println!("P{order}: {} values, identical on 1, 2, 3 threads", one.values.len());
    }
}

/// The same for a solid. Source: the solid's assembly through src/fem/sparse.rs (three
/// components per node). Goal: K and b of tetrahedra are bit for bit independent of the number
/// of threads. Problem: geo/monolith.toml (dam and rock, gravity and the reservoir at 45 m),
/// P1 and P2 from gmsh. Checks: the values and right-hand sides of 2 and 3 threads equal those
/// of 1 thread exactly.
#[test]
fn a_solid_assembles_identically_on_one_two_and_three_threads() {
    use damfem::fem::sparse::SparsePattern;
    use damfem::io::gmsh::{mesh_geo_any, AnyMesh, MeshOptions};
    let scene = Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("geo/monolith.toml")).expect("the monolith");
    for order in [2, 1] {
        let options = MeshOptions { order, ..Default::default() };
        let AnyMesh::Solid(mesh) = mesh_geo_any(&scene.geometry, &options, false, false).expect("a mesh") else {
            panic!("monolith.geo has volumes")
        };
        let solid = scene.solid(mesh).expect("the monolith is valid");
        let dofs = solid.dofs();
        let pattern = SparsePattern::new(&solid.mesh, &dofs);
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
            pool.install(|| solid.assemble(&dofs, &pattern).expect("assembled"))
        };
        let one = on(1);
        for threads in [2, 3] {
            let many = on(threads);
            assert!(one.values == many.values, "P{order}: K differs on {threads} threads");
            assert!(one.rhs == many.rhs, "P{order}: b differs on {threads} threads");
        }
        println!("P{order}: {} values, identical on 1, 2, 3 threads", one.values.len());
    }
}
