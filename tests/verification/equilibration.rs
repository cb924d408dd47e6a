//! Equilibration of the reconstruction on thin and graded cells.

use damfem::adapt::{self, AdaptSettings, Refinement};
use damfem::contact::{ContactProblem, Linearisation};
use damfem::elasticity::{BodyForce, Displacement, Problem};
use damfem::estimate::checks::{check, representation_bound, Equilibration};
use damfem::estimate::reconstruction::reconstruct;
use damfem::estimate::{estimate_displacement, estimate_iterate};
use damfem::mesh::structured::{rectangle, BOTTOM, LEFT, RIGHT, TOP};
use damfem::mesh::Topology;
use damfem::scene::Scene;
use damfem::solve::{Cholesky, NonlinearSystem};
use damfem::verify::meshes::graded_unit_square;
use damfem::verify::v1;
use std::path::Path;
use std::sync::Arc;

/// The Galerkin solution of `problem` (nodal values) and the checks of its reconstruction.
fn solve_and_check(problem: &Problem) -> (Vec<[f64; 2]>, Equilibration) {
    let disc = problem.discretise();
    let system = problem.assemble(&disc);
    let x = Cholesky::analyse(&disc.pattern).unwrap().solve(&disc.pattern, &system.values, &system.rhs).unwrap();
    let u = problem.displacement(&disc, &x);
    let nodal = Displacement::from(u.clone());
    let topology = Topology::new(&problem.mesh);
    let rec = reconstruct(problem, &topology, &nodal, None).expect("reconstruction");
    let eq = check(problem, &topology, &nodal, &rec, None);
    (u, eq)
}

/// Source: docs/method.md §4.1 (thin cells); the patch problems are solved by orthogonal
/// factorisations whose round-off does not grow with the aspect ratio of the cells.
/// Goal: the divergence and interior normal-continuity conditions hold to round-off on
/// cells of aspect ratio 1 to 10⁴ (they grew like the square of the aspect ratio, to 10⁻³).
/// Parameters: V1 data on the structured rectangle \[0, 1\] × \[0, 1/a\], 4 × 4 cells, clamped
/// bottom, a = 1, 10, 10², 10³, 10⁴, p = 1, 2. Measured (`-- --nocapture`): divergence
/// ≤ 7.7·10⁻¹², continuity ≤ 6.5·10⁻¹³ (P1) and ≤ 9.4·10⁻¹² up to a = 10³, 2.1·10⁻¹⁰ at 10⁴
/// (P2). The last is the round-off of patch solutions that are themselves a² times too large
/// (the face rows of a thin patch are nearly dependent; docs/method.md §4.1), not of their
/// solver.
#[test]
fn thin_cells_are_equilibrated_to_round_off() {
    for order in [1, 2] {
        for aspect in [1.0, 1e1, 1e2, 1e3, 1e4] {
            let problem = v1::problem(rectangle(0.0, 1.0, 0.0, 1.0 / aspect, 4, 4, order), &[BOTTOM]);
            let (_, eq) = solve_and_check(&problem);
            eprintln!("P{order} aspect {aspect:e}: {eq:?}");
            assert!(eq.divergence <= 1e-11, "P{order}, aspect {aspect:e}: {eq:?}");
            let continuity = if aspect <= 1e3 { 1e-11 } else { 1e-9 };
            assert!(eq.normal_continuity <= continuity, "P{order}, aspect {aspect:e}: {eq:?}");
            if order == 2 {
                assert!(eq.weak_symmetry <= 1e-12, "P{order}, aspect {aspect:e}: {eq:?}");
            }
        }
    }
}

/// A linear field with dyadic coefficients plus the translation (c, c): its values at the
/// dyadic nodes of a bisected unit square are exact doubles.
fn dyadic_linear(c: f64) -> impl Fn([f64; 2]) -> [f64; 2] + Copy + Send + Sync + 'static {
    move |x| [0.5 * x[0] + 0.25 * x[1] + c, 0.125 * x[0] - 0.5 * x[1] + c]
}

/// Source: docs/method.md §4.1 (graded cells) and §5.2; the displacement gradient is taken
/// from nodal differences, Σ (u_k − u_0) ⊗ ∇φ_k.
/// Goal: when u_h is the exact discrete solution, the estimator's own arithmetic keeps every
/// equilibration condition at round-off on cells graded by 10⁴ and 10⁶, whatever the size of
/// u_h against h |∇u_h|. With Σ u_k ⊗ ∇φ_k the P2 divergence read 1.8·10⁻¹¹ (c = 1) and
/// 1.2·10⁻⁹ (c = 100) at 10⁴, and up to 1.2·10⁻⁷ at 10⁶. Measured now: ≤ 2.6·10⁻¹⁵, apart
/// from the P1 weak symmetry, which P1 does not impose (1.4·10⁻¹⁰).
/// Parameters: the structured 4 × 4 unit square bisected towards (0.5, 0.5) until its cells
/// span a ratio of 10⁴ and 10⁶ in diameter; u = (x/2 + y/4 + c, x/8 − y/2 + c), c = 0, 1,
/// 100, no body force, Dirichlet data on the four sides; p = 1, 2.
#[test]
fn graded_cells_are_equilibrated_to_round_off() {
    for order in [1, 2] {
        for ratio in [1e4, 1e6] {
            let mesh = graded_unit_square(ratio, order);
            for c in [0.0, 1.0, 100.0] {
                let exact = dyadic_linear(c);
                let mut problem = v1::problem(mesh.clone(), &[BOTTOM, RIGHT, TOP, LEFT]);
                problem.body_force = BodyForce::None;
                problem.dirichlet.iter_mut().for_each(|bc| bc.value = Arc::new(exact));
                let u: Vec<[f64; 2]> = problem.mesh.points.iter().map(|&p| exact(p)).collect();
                let nodal = Displacement::from(u);
                let topology = Topology::new(&problem.mesh);
                let rec = reconstruct(&problem, &topology, &nodal, None).expect("reconstruction");
                let eq = check(&problem, &topology, &nodal, &rec, None);
                eprintln!("P{order} ratio {ratio:e} c {c}: {eq:?}");
                assert!(eq.worst(order) <= 1e-12, "P{order}, ratio {ratio:e}, c = {c}: {eq:?}");
            }
        }
    }
}

/// Source: docs/method.md §5.2 ("Round-off on graded meshes"): a double u_h resolves the
/// differences of nodal values only to ε |u_h|, so the residual of the discrete equation at
/// a vertex of a cell of size h cannot fall below about ε E |u_h|, and a patch's data balance
/// only to that: relative to the stresses, ε |u_h| / (h |∇u_h|) (`representation_bound`).
/// Goal: on graded meshes, the equilibration of the solver's output stays within a small
/// multiple of that bound (measured: 5.8–7.5 times it for P1, 10.7–17.8 for P2), so nothing
/// but the representation of u_h is left; and `estimate_iterate` accepts these converged solves, which a fixed
/// tolerance of 10⁻⁸ refused from a grading of 10⁷ on (divergence 2.0·10⁻⁸ for P1 and
/// 4.8·10⁻⁸ for P2 there, 2.0·10⁻⁷ and 4.4·10⁻⁷ at 10⁸).
/// Parameters: V1 (clamped bottom) on the unit square graded towards (0.5, 0.5) by 10², 10⁴,
/// 10⁶, 10⁷, 10⁸, p = 1, 2, sparse Cholesky; factor 30 on the bound.
#[test]
fn graded_solves_are_equilibrated_to_their_representation() {
    for order in [1, 2] {
        for ratio in [1e2, 1e4, 1e6, 1e7, 1e8] {
            let problem = v1::problem(graded_unit_square(ratio, order), &[BOTTOM]);
            let disc = problem.discretise();
            let x = problem.solve_linear(&disc).expect("solve");
            let bound = representation_bound(&problem, &problem.displacement(&disc, &x).into(), None);
            let estimate = estimate_iterate(&problem, &disc, &x, None)
                .unwrap_or_else(|e| panic!("P{order}, ratio {ratio:e}: a converged solve is refused: {e}"));
            let eq = estimate.equilibration;
            eprintln!(
                "P{order} ratio {ratio:e}: bound {bound:.1e}, worst / bound {:.1}, {eq:?}",
                eq.worst(order) / bound
            );
            assert!(eq.worst(order) <= 30.0 * bound, "P{order}, ratio {ratio:e}: bound {bound:.1e}, {eq:?}");
        }
    }
}

/// Source: docs/method.md §5.2 ("Round-off on graded meshes"): `Problem::solve_refined` adds
/// to the Cholesky solution x one step of iterative refinement, lo = K⁻¹(F − K x) with the
/// residual summed cell by cell in difference form, and the estimator reads the nodal
/// differences of the pair x + lo.
/// Goal: the solver's output, estimated as `damfem solve` and `damfem adapt` do, is
/// equilibrated to 10⁻¹² on cells graded by 10⁴ and beyond, where the double solution reads
/// 1.5·10⁻¹¹ (P1) and 4.5·10⁻¹¹ (P2) at 10⁴ (asserted above 10⁻¹², so the meshes are graded
/// enough to matter). Measured: every check ≤ 3.4·10⁻¹⁵ up to 10⁶, except the P1 continuity
/// (7.7·10⁻¹⁴ at 10⁶, the same for the double solution: not a matter of u_h).
/// Parameters: V1 (clamped bottom) on the unit square graded towards (0.5, 0.5) by 10², 10⁴,
/// 10⁶, p = 1, 2; `estimate_displacement` of the pair.
#[test]
fn refined_solves_are_equilibrated_to_round_off_on_graded_meshes() {
    for order in [1, 2] {
        for ratio in [1e2, 1e4, 1e6] {
            let problem = v1::problem(graded_unit_square(ratio, order), &[BOTTOM]);
            let disc = problem.discretise();
            let solution = problem.solve_refined(&disc).expect("solve");
            let pair = estimate_displacement(&problem, &disc.topology, &solution.displacement(&problem, &disc), None)
                .unwrap_or_else(|e| panic!("P{order}, ratio {ratio:e}: the refined solve is refused: {e}"))
                .equilibration;
            let x = problem.solve_linear(&disc).expect("solve");
            let double = estimate_iterate(&problem, &disc, &x, None).expect("estimate").equilibration;
            eprintln!("P{order} ratio {ratio:e}: pair {pair:?}, double worst {:.1e}", double.worst(order));
            assert!(pair.worst(order) <= 1e-12, "P{order}, ratio {ratio:e}: {pair:?}");
            if ratio >= 1e4 {
                assert!(double.worst(order) > 1e-12, "P{order}, ratio {ratio:e}: double {double:?}");
            }
        }
    }
}

/// Source: docs/method.md §4.1, §5.2 and §5.3 (the adaptive loop).
/// Goal: along a Scene A P2 adaptive run, whose cells are graded to a few µm at x = 32 m,
/// every equilibration condition holds to 10⁻¹² at every step. The interior continuity
/// check read 2.7·10⁻⁹ at step 9 when it mapped its quadrature points back through
/// J⁻¹(x − x₀), which loses ε |x| / h_T; it now takes them on the reference edge. Measured:
/// 3.9·10⁻¹⁴ at step 0 to 3.3·10⁻¹³ at step 11 (the patch compatibility; the other checks
/// ≤ 1.8·10⁻¹⁴), about 60 s in release mode.
/// Parameters: geo/scene_a.toml, p = 2, 12 adaptive steps with the default settings (the
/// smallest-size stall may end the run after 11; measured so with the Schur-complement steps).
#[test]
fn scene_a_p2_adaptive_run_stays_equilibrated() {
    let mut scene = Scene::load(Path::new("geo/scene_a.toml")).expect("scene");
    scene.mesh.order = 2;
    let mut mesher = scene.mesher(Refinement::Adaptive);
    let settings = AdaptSettings { steps: 12, ..Default::default() };
    let mut worst: Vec<f64> = Vec::new();
    let history = adapt::run(&settings, &mut mesher, &scene, |step| {
        let contact = step.contact.expect("Scene A has a contact curve");
        let state = Linearisation::new(step.problem, step.disc, &contact.nitsche, contact.smoothing, &contact.x_prev);
        let u = contact.displacement(step.problem, step.disc);
        let eq = check(step.problem, &step.disc.topology, &u, &step.estimate.reconstruction, Some(&state));
        eprintln!("step {} ({} unknowns): {eq:?}", worst.len(), step.disc.dofs.n_free);
        worst.push(eq.worst(2));
        Ok(())
    })
    .expect("adaptive run");
    let shown: Vec<String> = worst.iter().map(|w| format!("{w:.1e}")).collect();
    eprintln!("worst per step: {shown:?}");
    // twelve meshes, unless the cells at the junction reach the smallest size first
    let stalled = history.last().is_some_and(|r| r.stall.is_some());
    assert!(worst.len() == 12 || (stalled && worst.len() >= 10), "{} steps, stalled: {stalled}", worst.len());
    assert!(worst.iter().all(|&w| w <= 1e-12), "{shown:?}");
}

/// Source: docs/method.md §5.2 ("The refined pair", contact iterates): P_γ(u_h) in difference
/// form (σ^n from nodal differences, u_h·ν − g from the compensated jump of the first nodes
/// plus the differences), and after Newton one refinement round lo = −J⁻¹ F_lin(x) with the
/// last step's factors, F_lin the linearised residual in difference form; the estimator reads
/// the pair x + lo.
/// Goal: along Hertz's adaptive runs, refined towards the ends of the contact zone, every
/// equilibration check of the estimated iterate is ≤ 10⁻¹² at every step, on meshes graded
/// enough that a double x could not be (the representation bound of x, γ₀-weighted on Γ_C,
/// exceeds 10⁻¹² at the last step: the double iterates read up to 1.0·10⁻¹² for P2 and
/// 5.4·10⁻¹² for P1 there). Measured: ≤ 1.2·10⁻¹⁴ (P2), ≤ 4.6·10⁻¹⁴ (P1). And the pair solves
/// the linearised problem of its last Newton step better than its rounding x = fl(x + lo) can:
/// at the last step ‖F_lin(x + lo)‖ ≤ 0.1 ‖F_lin(x)‖ over the free rows, both in difference form
/// (measured: 4.6·10⁻¹⁵ against 1.0·10⁻¹³ for P2, 1.5·10⁻¹⁵ against 2.4·10⁻¹³ for P1, with
/// loads of order 1).
/// Parameters: geo/hertz.toml (γ₀ = 100: at γ₀ = 10 the γ₀-weighted bound of the last mesh
/// stays below 10⁻¹²), size factor 2, default adaptive settings; P2 five steps, P1
/// five steps (to about 72 000 unknowns).
#[test]
fn hertz_adaptive_runs_are_equilibrated_to_round_off() {
    for order in [2, 1] {
        let mut scene = Scene::load(Path::new("geo/hertz.toml")).expect("scene");
        scene.mesh.order = order;
        scene.mesh.size_factor = 2.0;
        let mut mesher = scene.mesher(Refinement::Adaptive);
        let settings = AdaptSettings { steps: 5, ..Default::default() };
        let (mut worst, mut bound, mut residuals) = (Vec::new(), 0.0, [0.0; 2]);
        adapt::run(&settings, &mut mesher, &scene, |step| {
            let contact = step.contact.expect("Hertz has a contact curve");
            let lo = contact.lo.as_deref().unwrap_or_else(|| panic!("P{order} step {}: not refined", worst.len()));
            let state =
                Linearisation::new(step.problem, step.disc, &contact.nitsche, contact.smoothing, &contact.x_prev);
            let x = step.problem.displacement(step.disc, &contact.x).into();
            bound = representation_bound(step.problem, &x, Some(&state));
            worst.push(step.estimate.equilibration.worst(order));
            // ‖F_lin‖ of the pair x + lo and of x = fl(x + lo) alone
            let (_, joint) = scene.problem(step.problem.mesh.clone()).expect("the scene's problem");
            let joint = joint.expect("Hertz has a contact curve").as_solved(contact);
            let system = ContactProblem::new(step.problem, step.disc, &joint, contact.smoothing);
            let norm = |lo: &[f64]| {
                let r = system.linearised_residual(&contact.x, lo, &contact.x_prev).expect("a linearised residual");
                r.iter().map(|v| v * v).sum::<f64>().sqrt()
            };
            residuals = [norm(lo), norm(&vec![0.0; lo.len()])];
            eprintln!(
                "P{order} step {}: worst {:.1e}, bound of x {bound:.1e}, |F_lin| of the pair {:.1e}, of x {:.1e}",
                worst.len() - 1,
                worst[worst.len() - 1],
                residuals[0],
                residuals[1]
            );
            Ok(())
        })
        .expect("adaptive run");
        assert_eq!(worst.len(), 5, "P{order}: steps");
        assert!(bound > 1e-12, "P{order}: the last mesh is not graded enough to matter (bound {bound:.1e})");
        assert!(worst.iter().all(|&w| w <= 1e-12), "P{order}: worst per step {worst:?}");
        assert!(residuals[0] <= 0.1 * residuals[1], "P{order}: |F_lin| of the pair and of x: {residuals:?}");
    }
}
