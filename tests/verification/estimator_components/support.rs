//! The helpers of the estimator's component tests: solves, evaluations, scene meshes.

use damfem::contact::nitsche::Nitsche;
use damfem::contact::projection::Smoothing;
use damfem::contact::{solve_by_continuation, ContactJoint, ContactProblem, Continuation, Linearisation};
use damfem::elasticity::{Discretisation, Displacement, Problem};
use damfem::estimate::checks::{check, Equilibration};
use damfem::estimate::estimators::{estimate, GlobalEstimators};
use damfem::estimate::reconstruction::reconstruct;
use damfem::estimate::reference::residual_dual_norm;
use damfem::io::gmsh::{mesh_geo, MeshOptions};
use damfem::mesh::{Mesh, Topology};
use damfem::scene::Scene;
use damfem::solve::{Cholesky, NonlinearSystem, SparseLu};
use std::path::{Path, PathBuf};

pub(super) fn manifest(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// Solves a linear problem (no contact) and returns the nodal displacement.
pub(super) fn solve_linear(problem: &Problem) -> Vec<[f64; 2]> {
    let disc = problem.discretise();
    let system = problem.assemble(&disc);
    let x = Cholesky::analyse(&disc.pattern).unwrap().solve(&disc.pattern, &system.values, &system.rhs).unwrap();
    problem.displacement(&disc, &x)
}

/// A converged contact solution and what the reconstruction needs.
pub(super) struct ContactRun {
    pub(super) u: Vec<[f64; 2]>,
    /// The iterate before the last Newton step of the last stage.
    pub(super) u_prev: Vec<[f64; 2]>,
    pub(super) nitsche: Nitsche,
    pub(super) delta: f64,
    pub(super) newton_steps: usize,
    pub(super) contact_length: f64,
}

/// Solves along the δ path of `settings` (as tests/verification/estimator.rs does).
pub(super) fn solve_with_contact(
    problem: &Problem,
    disc: &Discretisation,
    joint: &ContactJoint,
    settings: &Continuation,
) -> ContactRun {
    let solution = solve_by_continuation(problem, disc, joint, settings).unwrap_or_else(|e| panic!("{e}"));
    let last = &solution.stages.last().unwrap().report;
    ContactRun {
        u: problem.displacement(disc, &last.x),
        u_prev: problem.displacement(disc, &last.x_prev),
        nitsche: solution.nitsche.clone(),
        delta: settings.delta,
        newton_steps: solution.stages.iter().map(|s| s.report.iterations.len()).sum(),
        contact_length: solution.contact_length(),
    }
}

impl ContactRun {
    pub(super) fn state(&self) -> Option<(&Nitsche, f64, &[[f64; 2]])> {
        Some((&self.nitsche, self.delta, &self.u_prev))
    }
}

/// Equilibration checks, global estimators and (if asked) the dual norm of one iterate.
pub(super) struct Evaluation {
    pub(super) eq: Equilibration,
    pub(super) est: GlobalEstimators,
    pub(super) dual: Option<f64>,
}

/// Reconstructs σ_h for the iterate `u` (with `contact` = (faces, δ, u_prev) on Γ_C = `tags`),
/// checks it, computes the estimators and, if `levels` is given, the dual norm on the mesh
/// refined `levels` times.
pub(super) fn evaluate(
    problem: &Problem,
    u: &[[f64; 2]],
    contact: Option<(&Nitsche, f64, &[[f64; 2]])>,
    tags: &[i32],
    levels: Option<usize>,
) -> Evaluation {
    let topology = Topology::new(&problem.mesh);
    let state = contact.map(|(nitsche, delta, u_prev)| Linearisation {
        nitsche,
        smoothing: Smoothing { delta },
        u_prev: u_prev.to_vec(),
    });
    let nodal = Displacement::from(u.to_vec());
    let rec = reconstruct(problem, &topology, &nodal, state.as_ref()).unwrap_or_else(|e| panic!("{e}"));
    let eq = check(problem, &topology, &nodal, &rec, state.as_ref());
    let est = estimate(problem, &topology, &nodal, &rec, state.as_ref()).global();
    let dual = levels.map(|levels| {
        let data = contact.map(|(nitsche, _, _)| ContactJoint::frictionless(tags.to_vec(), nitsche.laws[0].parameters));
        residual_dual_norm(problem, u, data.as_ref(), levels).unwrap_or_else(|e| panic!("{e}"))
    });
    Evaluation { eq, est, dual }
}

pub(super) fn components(e: &GlobalEstimators) -> String {
    format!(
        "osc {:.3e}  flux {:.3e}  Neu {:.3e}  disc {:.3e}  reg {:.3e}  lin {:.3e}  tot {:.4e}",
        e.osc, e.flux, e.neu, e.disc, e.reg, e.lin, e.tot
    )
}

/// Full Newton steps (no damping, one step of iterative refinement per linear solve) from
/// x0: the iterates x_0, …, x_steps and the relative residuals ‖F(x_k)‖/‖b‖.
pub(super) fn full_newton(contact: &ContactProblem, x0: Vec<f64>, steps: usize) -> (Vec<Vec<f64>>, Vec<f64>) {
    let pattern = contact.pattern();
    let lu = SparseLu::analyse(pattern).unwrap();
    let (n, scale) = (pattern.n(), contact.scale());
    let (mut r, mut jac, mut product) = (vec![0.0; n], vec![0.0; pattern.nnz()], vec![0.0; n]);
    let mut xs = vec![x0];
    let mut residuals = Vec::new();
    for _ in 0..=steps {
        let x = xs.last().unwrap().clone();
        contact.evaluate(&x, &mut r, Some(&mut jac));
        residuals.push(r.iter().map(|v| v * v).sum::<f64>().sqrt() / scale);
        if xs.len() > steps {
            break;
        }
        let factors = lu.factor(pattern, &jac).unwrap();
        let minus_r: Vec<f64> = r.iter().map(|v| -v).collect();
        let mut d = factors.solve(&minus_r);
        pattern.multiply(&jac, &d, &mut product);
        let defect: Vec<f64> = minus_r.iter().zip(&product).map(|(b, a)| b - a).collect();
        for (di, c) in d.iter_mut().zip(factors.solve(&defect)) {
            *di += c;
        }
        xs.push(x.iter().zip(&d).map(|(a, b)| a + b).collect());
    }
    (xs, residuals)
}

/// A scene file loaded and meshed by gmsh at degree `order`, the mesh sizes multiplied by
/// `size_factor` on top of the scene's own factor.
pub(super) fn scene_mesh(file: &str, order: usize, size_factor: f64) -> (Scene, Mesh) {
    let scene = Scene::load(&manifest(file)).unwrap_or_else(|e| panic!("{e}"));
    let m = &scene.mesh;
    let options = MeshOptions {
        order,
        size_factor: size_factor * m.size_factor,
        size_min: m.size_min,
        size_max: m.size_max,
        algorithm: m.algorithm,
    };
    let mesh = mesh_geo(&scene.geometry, &options, false, false).unwrap_or_else(|e| panic!("{file}: {e}"));
    (scene, mesh)
}

/// Solves a scene with contact (CLI settings): the problem, its contact tags and the run.
pub(super) fn scene_with_contact(file: &str, order: usize, size_factor: f64) -> (Problem, Vec<i32>, ContactRun) {
    let (scene, mesh) = scene_mesh(file, order, size_factor);
    let (problem, joint) = scene.problem(mesh).unwrap_or_else(|e| panic!("{e}"));
    let joint = joint.unwrap_or_else(|| panic!("{file} has a contact curve"));
    let disc = problem.discretise();
    let settings = scene.continuation(&problem, &disc.topology);
    assert!(joint.laws.iter().all(|c| c.parameters.theta == 0.0), "{file}: the estimator needs theta = 0");
    let run = solve_with_contact(&problem, &disc, &joint, &settings);
    (problem, joint.tags, run)
}

/// Values in short scientific notation.
pub(super) fn fmt(v: &[f64]) -> Vec<String> {
    v.iter().map(|r| format!("{r:.2e}")).collect()
}
