//! Where the round-off of the equilibration checks comes from (docs/method.md §4.1, §5.2).
//!
//! What it shows, one table per hypothesis, on V1's data (`verify::v1`, clamped bottom):
//!
//! 1. The representation of u_h: the checks of the double Cholesky solution against those of
//!    the refined pair x + lo (`Problem::solve_refined`), on the unit square squeezed to cells
//!    of aspect 10² … 10⁴.
//! 2. The size of u_h against h |∇u_h|: the same with a rigid translation c = 0, 1, 100
//!    added to the Dirichlet data (u_h shifts by c, σ(u_h) does not).
//! 3. The estimator's own arithmetic: u_h the exact discrete solution, the linear field
//!    u = (x/2 + y/4 + c, x/8 − y/2 + c) without body force, whose nodal values at the dyadic
//!    nodes of a bisected mesh are exact doubles, on meshes graded by 10², 10⁴, 10⁶.
//! 4. The solve output on meshes graded by 10² … 10⁸ against the representation bound
//!    ε max|u_h| (λ + 2μ) / (h_min max|σ(u_h)|): a double u_h resolves nodal differences only
//!    to ε |u_h|, so the residual of the discrete equation cannot fall below ε E |u_h| per node;
//!    the refined pair x + lo, whose differences are exact, below it.
//! 5. The patch problems on thin cells: the size of σ_h and η_flux against the stress.
//! 6. With `--hertz`: the adaptive runs of geo/hertz.toml (size factor 2; P2, 5 steps; P1,
//!    6 steps), and the P1 run with the plane and the top moved down by 0.5 (|u_h| from 0.05
//!    to 0.55, the same contact): per step the worst check of the estimated iterate (the
//!    pair x + lo of the refinement round after Newton) against the
//!    `estimate::checks::representation_bound` of the double x alone (which weighs the cells
//!    of Γ_C by γ₀).
//!
//! 7. The cost of the refinement: the refined solve against the double one at 10⁵ unknowns.
//!
//! Run: `cargo run --release --example equilibration_roundoff` (a few seconds; `-- --hertz`
//! adds about three minutes).

use damfem::adapt::{self, AdaptSettings, Refinement};
use damfem::contact::Linearisation;
use damfem::elasticity::stress::cell_mean_stress;
use damfem::elasticity::{BodyForce, Displacement, Problem};
use damfem::estimate::checks::{check, representation_bound, Equilibration};
use damfem::estimate::estimators::estimate;
use damfem::estimate::reconstruction::reconstruct;
use damfem::mesh::structured::{rectangle, unit_square, BOTTOM, LEFT, RIGHT, TOP};
use damfem::mesh::{Mesh, Topology};
use damfem::scene::Scene;
use damfem::verify::meshes::graded_unit_square;
use damfem::verify::v1;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// The checks, η_flux and max |σ_h| (coefficients) of the reconstruction of nodal `u`.
fn checks(problem: &Problem, u: &Displacement) -> (Equilibration, f64, f64) {
    let topology = Topology::new(&problem.mesh);
    let rec = reconstruct(problem, &topology, u, None).expect("reconstruction");
    let eta = estimate(problem, &topology, u, &rec, None);
    let flux = eta.flux.iter().map(|v| v * v).sum::<f64>().sqrt();
    let largest = (0..rec.n_cells()).flat_map(|c| rec.total(c)).fold(0.0_f64, |m, v| m.max(v.abs()));
    (check(problem, &topology, u, &rec, None), flux, largest)
}

fn line(eq: &Equilibration) -> String {
    format!(
        "div {:.1e}  cont {:.1e}  sym {:.1e}  compat {:.1e}",
        eq.divergence, eq.normal_continuity, eq.weak_symmetry, eq.compatibility
    )
}

/// V1 with the Dirichlet data shifted by the translation (c, c).
fn shifted_v1(mesh: Mesh, c: f64) -> Problem {
    let mut problem = v1::problem(mesh, &[BOTTOM]);
    for bc in &mut problem.dirichlet {
        bc.value = Arc::new(move |x| {
            let u = v1::exact(x);
            [u[0] + c, u[1] + c]
        });
    }
    problem
}

/// Tables 1 and 2.
fn solve_and_refine() {
    println!("1-2. squeezed unit square (4 x 4), V1 shifted by c: the double Cholesky solution, then the refined pair x + lo");
    for order in [1, 2] {
        for aspect in [1e2, 1e3, 1e4] {
            for c in [0.0, 1.0, 100.0] {
                let problem = shifted_v1(rectangle(0.0, 1.0, 0.0, 1.0 / aspect, 4, 4, order), c);
                let disc = problem.discretise();
                let x = problem.solve_linear(&disc).expect("solve");
                let (double, _, _) = checks(&problem, &problem.displacement(&disc, &x).into());
                let refined = problem.solve_refined(&disc).expect("solve");
                let (pair, _, _) = checks(&problem, &refined.displacement(&problem, &disc));
                println!("  P{order} aspect {aspect:.0e} c {c:<5} double {}", line(&double));
                println!("  {:>25}pair   {}", "", line(&pair));
            }
        }
    }
}

/// Table 3.
fn exact_linear() {
    println!("3. exact discrete solution (linear, dyadic) on meshes graded towards (0.5, 0.5)");
    for order in [1, 2] {
        for ratio in [1e2, 1e4, 1e6] {
            let mesh = graded_unit_square(ratio, order);
            for c in [0.0, 1.0, 100.0] {
                let exact = move |x: [f64; 2]| [0.5 * x[0] + 0.25 * x[1] + c, 0.125 * x[0] - 0.5 * x[1] + c];
                let mut problem = v1::problem(mesh.clone(), &[BOTTOM, RIGHT, TOP, LEFT]);
                problem.body_force = BodyForce::None;
                problem.dirichlet.iter_mut().for_each(|bc| bc.value = Arc::new(exact));
                let u: Vec<[f64; 2]> = problem.mesh.points.iter().map(|&p| exact(p)).collect();
                let (eq, _, _) = checks(&problem, &u.into());
                println!("  P{order} ratio {ratio:.0e} c {c:<5} {}", line(&eq));
            }
        }
    }
}

/// Table 4.
fn graded_solve() {
    println!("4. V1 solved on meshes graded towards (0.5, 0.5): checks of the double solution and of the refined pair x + lo,");
    println!("   against eps max|u| (lambda + 2 mu) / (h_min max|sigma(u)|)");
    for order in [1, 2] {
        for ratio in [1e2, 1e4, 1e6, 1e7, 1e8] {
            let problem = v1::problem(graded_unit_square(ratio, order), &[BOTTOM]);
            let disc = problem.discretise();
            let refined = problem.solve_refined(&disc).expect("solve");
            let x = problem.solve_linear(&disc).expect("solve");
            let u = problem.displacement(&disc, &x);
            let mesh = &problem.mesh;
            let h = (0..mesh.n_cells()).map(|c| mesh.cell_diameter(c)).fold(f64::MAX, f64::min);
            let size = u.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max);
            let stress = cell_mean_stress(&problem, &u).into_iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
            let bound = f64::EPSILON * size * (v1::LAMBDA + 2.0 * v1::MU) / (h * stress);
            let (eq, _, _) = checks(&problem, &u.into());
            let (pair, _, _) = checks(&problem, &refined.displacement(&problem, &disc));
            println!("  P{order} ratio {ratio:.0e} bound {bound:.1e}  double: {}", line(&eq));
            println!("  {:>31}refined: {}", "", line(&pair));
        }
    }
}

/// Table 5.
fn thin_patches() {
    println!("5. squeezed unit square, V1 solved: eta_flux and max |sigma_h| (coefficients)");
    for order in [1, 2] {
        for aspect in [1.0, 1e2, 1e3, 1e4] {
            let problem = v1::problem(rectangle(0.0, 1.0, 0.0, 1.0 / aspect, 4, 4, order), &[BOTTOM]);
            let disc = problem.discretise();
            let x = problem.solve_linear(&disc).expect("solve");
            let (eq, flux, largest) = checks(&problem, &problem.displacement(&disc, &x).into());
            println!("  P{order} aspect {aspect:.0e} eta_flux {flux:.2e} max|sigma_h| {largest:.2e}  {}", line(&eq));
        }
    }
}

/// Table 6: one adaptive run of Hertz at degree `order`, its plane and top moved down by
/// `shift`.
fn hertz(order: usize, steps: usize, shift: f64) {
    let mut scene = Scene::load(Path::new("geo/hertz.toml")).expect("geo/hertz.toml");
    scene.mesh.order = order;
    scene.mesh.size_factor = 2.0;
    scene.contact.gap += shift;
    let top = scene.boundary.get_mut("top").expect("the top of geo/hertz.toml");
    top.value = [top.value.at(0), top.value.at(1) - shift].into();
    let mut mesher = scene.mesher(Refinement::Adaptive);
    let settings = AdaptSettings { steps, ..Default::default() };
    adapt::run(&settings, &mut mesher, &scene, |step| {
        let contact = step.contact.expect("Hertz has a contact curve");
        let state = Linearisation::new(step.problem, step.disc, &contact.nitsche, contact.smoothing, &contact.x_prev);
        // the bound of the double x alone: what the pair x + lo is estimated below
        let x = step.problem.displacement(step.disc, &contact.x).into();
        let worst = step.estimate.equilibration.worst(order);
        let bound = representation_bound(step.problem, &x, Some(&state));
        let pair = if contact.lo.is_some() { "pair" } else { "double" };
        println!(
            "  P{order} shift {shift}: {:>7} unknowns, {pair}, worst {worst:.1e}, double bound {bound:.1e}, worst / bound {:.2}",
            step.disc.dofs.n_free,
            worst / bound
        );
        Ok(())
    })
    .expect("adaptive run");
}

/// Table 7: the cost of the refinement, V1 (P2, clamped bottom) on the structured n × n unit
/// square: three alternating runs of the double solve and of the refined one.
fn refinement_cost(n: usize) {
    let problem = v1::problem(unit_square(n, 2), &[BOTTOM]);
    let disc = problem.discretise();
    println!("7. cost of the refinement: V1, P2, {n} x {n}, {} unknowns", disc.dofs.n_free);
    for _ in 0..3 {
        let clock = Instant::now();
        problem.solve_linear(&disc).expect("solve");
        let double = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        problem.solve_refined(&disc).expect("solve");
        let refined = clock.elapsed().as_secs_f64();
        println!("  solve {double:.3} s, refined solve {refined:.3} s (+{:.0} %)", 100.0 * (refined / double - 1.0));
    }
}

fn main() {
    solve_and_refine();
    exact_linear();
    graded_solve();
    thin_patches();
    refinement_cost(112);
    if std::env::args().any(|a| a == "--hertz") {
        println!("6. Hertz adaptive runs (size factor 2): worst check against the representation bound");
        hertz(2, 5, 0.0);
        hertz(1, 6, 0.0);
        hertz(1, 5, 0.5);
    }
}
