//! Parallel error estimation: the same bits on any number of threads.

use crate::common::{solve_scene, SolvedScene};
use damfem::estimate::{estimate_iterate, Estimate};

/// The estimate of the solution of `scene` on a pool of `threads` threads.
fn estimate_on(threads: usize, scene: &SolvedScene) -> Estimate {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
    let state = scene.solution.linearisation(&scene.problem, &scene.disc);
    pool.install(|| estimate_iterate(&scene.problem, &scene.disc, &scene.solution.x, Some(&state)))
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The estimate on 1, 2 and 3 threads. Source: src/estimate (the patch problems are solved
/// independently and summed in the order of the vertices; every check and estimator is computed
/// cell by cell or face by face, and the largest violations are reduced in order, the first on
/// ties). Goal: the reconstruction, the estimators and the equilibration checks with their
/// places are bit for bit independent of the number of threads. Problem: Scene A
/// (`geo/scene_a.toml`, contact on the base, the 70 m flood) at P2 and P1, size factor 1, solved
/// as `damfem solve` does. Checks: σ_h1, σ_h2, σ_h3, the seven per-cell estimators and the
/// checks of 2 and 3 threads equal those of 1 thread exactly.
#[test]
fn estimate_is_identical_on_one_two_and_three_threads() {
    for order in [2, 1] {
        let scene = solve_scene("geo/scene_a.toml", order, 1.0);
        let one = estimate_on(1, &scene);
        for threads in [2, 3] {
            let many = estimate_on(threads, &scene);
            assert!(
                one.reconstruction.sigma == many.reconstruction.sigma,
                "P{order}: σ_h differs on {threads} threads"
            );
            assert!(
                one.estimators.components() == many.estimators.components(),
                "P{order}: the estimators differ on {threads} threads"
            );
            let checks = |e: &Estimate| format!("{:?}", e.equilibration);
            assert_eq!(checks(&one), checks(&many), "P{order}: the checks differ on {threads} threads");
        }
        println!(
            "P{order}: {} cells, η_tot = {:.6e}, identical on 1, 2, 3 threads",
            one.estimators.tot.len(),
            one.estimators.global().tot
        );
    }
}
