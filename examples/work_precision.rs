//! Work–precision benchmark: adaptive against uniform refinement, in one process, for P1 and
//! P2 on V3 (manufactured contact solution, gmsh meshes of `geo/unit_square.geo`), on Scene A
//! (`geo/scene_a.toml`) and on Hertz (`geo/hertz.toml`).
//!
//! For every case, uniform refinement runs first (every size halved at each step); adaptive
//! refinement then runs until it has as many unknowns as uniform's last mesh (or its step
//! limit), so that both show their rates over the same range. The first table gives, as
//! ratios measured in this run, the unknowns and the wall time adaptive needs to reach
//! uniform's final η_tot against uniform's, the fitted rates of η against the unknowns (last
//! four steps), and the estimator's share of the total time of the adaptive run; the second
//! the steps and unknowns of each fit. On V3 the true error |u − u_h|_{H¹} is known and is
//! reported too.
//!
//! Run: `cargo run --release --example work_precision -- [OUTPUT_DIR] [--quick]`
//! (default `out/work_precision`): writes `work_precision.md`, one history CSV per run, and
//! per case a figure of η against unknowns (with the fitted rates in the legend) and one of η
//! against wall time (SVG and PNG). `--quick` runs fewer steps.

use damfem::adapt::geo::GeoMesher;
use damfem::adapt::history::{adaptive_uniform_figure, comparison_figure, eta_rate, to_csv, RATE_STEPS};
use damfem::adapt::{self, AdaptError, AdaptSettings, Model, Refinement, StepRecord};
use damfem::contact::nitsche::NitscheParameters;
use damfem::contact::ContactJoint;
use damfem::elasticity::Problem;
use damfem::fem::norms::errors;
use damfem::io::gmsh::MeshOptions;
use damfem::io::plot::write_figure;
use damfem::mesh::structured::BOTTOM;
use damfem::mesh::Mesh;
use damfem::scene::Scene;
use damfem::solve::NewtonOptions;
use damfem::verify::v3;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// V3 with contact on the bottom side.
struct V3;

impl Model for V3 {
    fn problem(&self, mesh: Mesh) -> Result<(Problem, Option<ContactJoint>), AdaptError> {
        Ok((v3::problem(mesh), Some(ContactJoint::frictionless(vec![BOTTOM], NitscheParameters::default()))))
    }

    fn newton(&self) -> NewtonOptions {
        NewtonOptions::default()
    }
}

/// One benchmark case: a geometry, its model and step limits (uniform, adaptive).
struct Case {
    name: String,
    geometry: PathBuf,
    options: MeshOptions,
    model: Box<dyn Model>,
    exact: bool,
    steps: (usize, usize),
}

/// A finished run: its history and, where known, |u − u_h|_{H¹} per step.
struct Run {
    history: Vec<StepRecord>,
    error: Vec<f64>,
}

fn run(case: &Case, refinement: Refinement, settings: AdaptSettings) -> Result<Run, AdaptError> {
    let mut mesher = GeoMesher {
        geometry: case.geometry.clone(),
        options: case.options.clone(),
        refinement,
        verbose: false,
        allow_system_calls: false,
        joints: Vec::new(),
    };
    let mut error = Vec::new();
    let history = adapt::run(&settings, &mut mesher, case.model.as_ref(), |step| {
        if case.exact {
            let u = step.problem.displacement(step.disc, step.x);
            error.push(errors(&step.problem.mesh, &u, v3::u, v3::grad_u).1);
        }
        let r = step.record;
        eprintln!(
            "  {:?} step {} {} unknowns eta {:.3e} {:.1} s",
            refinement, r.step, r.unknowns, r.eta.tot, r.elapsed
        );
        Ok(())
    })?;
    Ok(Run { history, error })
}

/// The first step of `history` with η_tot ≤ eta.
fn reaching(history: &[StepRecord], eta: f64) -> Option<&StepRecord> {
    history.iter().find(|r| r.eta.tot <= eta * (1.0 + 1e-12))
}

/// The rate of η_tot against the unknowns ([`eta_rate`], −p/2 is optimal), with the steps
/// and unknowns it spans.
struct Fit {
    slope: f64,
    steps: (usize, usize),
    unknowns: (usize, usize),
}

fn fit(history: &[StepRecord]) -> Fit {
    let tail = &history[history.len().saturating_sub(RATE_STEPS)..];
    let (first, last) = (&tail[0], &tail[tail.len() - 1]);
    Fit { slope: eta_rate(history), steps: (first.step, last.step), unknowns: (first.unknowns, last.unknowns) }
}

fn estimator_share(history: &[StepRecord]) -> f64 {
    let estimate: f64 = history.iter().map(|r| r.seconds.estimate).sum();
    estimate / history.last().map_or(1.0, |r| r.elapsed)
}

/// The scene `geo/<name>.toml` at degree `order`.
fn scene_case(name: &str, order: usize, steps: (usize, usize)) -> Case {
    let file = format!("geo/{name}.toml");
    let mut scene = Scene::load(Path::new(&file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    scene.mesh.order = order;
    Case {
        name: format!("{name}_p{order}"),
        geometry: scene.geometry.clone(),
        options: scene.mesh_options(),
        model: Box::new(scene),
        exact: false,
        steps,
    }
}

fn cases(quick: bool) -> Vec<Case> {
    let square = PathBuf::from("geo/unit_square.geo");
    let mut all = Vec::new();
    for order in [1, 2] {
        let options = MeshOptions { order, ..Default::default() };
        let v3_steps = if quick { (3, 6) } else { (6 - order, 16) };
        all.push(Case {
            name: format!("v3_p{order}"),
            geometry: square.clone(),
            options: options.clone(),
            model: Box::new(V3),
            exact: true,
            steps: v3_steps,
        });
        // P2 on Scene A stops after step 10: its corner cells then reach the smallest size,
        // 10⁻⁸ of the domain, and step 11 can no longer halve η there (docs/method.md §5.5)
        all.push(scene_case(
            "scene_a",
            order,
            if quick { (2, 6) } else { (5 - order, if order == 2 { 11 } else { 20 }) },
        ));
        all.push(scene_case("hertz", order, if quick { (2, 6) } else { (4, 20) }));
    }
    all
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let quick = args.iter().any(|a| a == "--quick");
    let dir = PathBuf::from(args.iter().find(|a| !a.starts_with("--")).map_or("out/work_precision", |s| s));
    std::fs::create_dir_all(&dir)?;
    let mut table = String::from(
        "| case | uniform: unknowns, time [s], η | adaptive reaching it: unknowns, time [s] | unknowns ratio | time ratio \
         | rate uniform | rate adaptive | estimator share (adaptive) |\n|---|---|---|---|---|---|---|---|\n",
    );
    let mut fits = String::from("| case | refinement | steps fitted | unknowns | slope |\n|---|---|---|---|---|\n");
    for case in cases(quick) {
        eprintln!("{}", case.name);
        let uniform = run(&case, Refinement::Uniform, AdaptSettings { steps: case.steps.0, ..Default::default() })?;
        let last = uniform.history.last().expect("a step");
        let settings = AdaptSettings { steps: case.steps.1, max_unknowns: Some(last.unknowns), ..Default::default() };
        let adaptive = run(&case, Refinement::Adaptive, settings)?;
        let (n, t) =
            reaching(&adaptive.history, last.eta.tot).map_or((f64::NAN, f64::NAN), |r| (r.unknowns as f64, r.elapsed));
        writeln!(
            table,
            "| {} | {}, {:.1}, {:.3e} | {}, {:.1} | {:.3} | {:.3} | {:.2} | {:.2} | {:.2} |",
            case.name,
            last.unknowns,
            last.elapsed,
            last.eta.tot,
            n,
            t,
            n / last.unknowns as f64,
            t / last.elapsed,
            eta_rate(&uniform.history),
            eta_rate(&adaptive.history),
            estimator_share(&adaptive.history)
        )?;
        for (kind, run) in [("uniform", &uniform), ("adaptive", &adaptive)] {
            let (f, n) = (fit(&run.history), run.history.len());
            let (s, u) = (f.steps, f.unknowns);
            writeln!(fits, "| {} | {kind} | {}–{} of {n} | {} … {} | {:.2} |", case.name, s.0, s.1, u.0, u.1, f.slope)?;
        }
        write_case(&dir, &case, &uniform, &adaptive)?;
    }
    let report = dir.join("work_precision.md");
    std::fs::write(&report, format!("{table}\n{fits}"))?;
    print!("{table}\n{fits}");
    eprintln!("written {}", report.display());
    Ok(())
}

/// The histories as CSV and the figures of one case.
fn write_case(dir: &Path, case: &Case, uniform: &Run, adaptive: &Run) -> Result<(), Box<dyn std::error::Error>> {
    for (kind, run) in [("uniform", uniform), ("adaptive", adaptive)] {
        let mut csv = to_csv(&run.history);
        if case.exact {
            csv = csv
                .lines()
                .enumerate()
                .map(|(i, line)| {
                    let extra = if i == 0 { "error_h1".into() } else { format!("{:e}", run.error[i - 1]) };
                    format!("{line},{extra}\n")
                })
                .collect();
        }
        std::fs::write(dir.join(format!("{}_{kind}.csv", case.name)), csv)?;
    }
    let runs = [("adaptive", &adaptive.history[..]), ("uniform", &uniform.history[..])];
    let mut by_unknowns = adaptive_uniform_figure(&case.name, &adaptive.history, &uniform.history);
    let mut by_time = comparison_figure(&case.name, "wall time [s]", &runs, |r| r.elapsed);
    if case.exact {
        for (figure, x) in [(&mut by_unknowns, 0), (&mut by_time, 1)] {
            for (label, run) in [("adaptive |u − u_h|_H¹", adaptive), ("uniform |u − u_h|_H¹", uniform)] {
                let points = run
                    .history
                    .iter()
                    .zip(&run.error)
                    .map(|(r, &e)| (if x == 0 { r.unknowns as f64 } else { r.elapsed }, e))
                    .collect();
                figure.series.push(damfem::io::plot::Series { label: label.into(), points, dashed: true });
            }
        }
    }
    write_figure(&dir.join(format!("{}_unknowns", case.name)), &by_unknowns)?;
    write_figure(&dir.join(format!("{}_time", case.name)), &by_time)?;
    Ok(())
}
