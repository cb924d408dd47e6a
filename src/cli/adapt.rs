//! `damfem adapt`: the adaptive loop on a scene, with ParaView files of every step, the
//! history (JSON and CSV) and its figures.

use super::common::{output_dir, remove_earlier_outputs, stem, Input, Output};
use super::interrupt;
use super::output::{write_results, Results, Summary, Units, UNITS};
use super::settings::{self, Setting};
use crate::adapt::geo::GeoMesher;
use crate::adapt::history::{to_csv, write_adaptive_uniform, write_plots};
use crate::adapt::marking::Marking;
use crate::adapt::{self, AdaptError, AdaptSettings, Model, PhaseTimes, Refinement, Step, StepRecord};
use crate::contact::{ContactJoint, JointLine, LoadPath, PathPoint};
use crate::elasticity::stress::cell_mean_stress;
use crate::elasticity::Problem;
use crate::estimate::reference::{effectivity, Effectivity};
use crate::geometry::Vector;
use crate::io::atomic::{write_output, Provisional};
use crate::io::pvd::write_pvd;
use crate::mesh::Mesh;
use crate::safety::resultant::Resultant;
use crate::scene::Scene;
use crate::solve::NewtonOptions;
use anyhow::{Context, Result};
use serde::Serialize;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    #[command(flatten)]
    output: Output,
    /// Maximum number of meshes; overrides adapt.steps (default 8)
    #[arg(long)]
    steps: Option<usize>,
    /// Stop when eta_tot <= TOL [Pa m]; overrides adapt.tol
    #[arg(long, allow_negative_numbers = true)]
    tol: Option<f64>,
    /// Stop when eta_tot <= TOL ||sigma_h||; overrides adapt.tol_relative
    #[arg(long, allow_negative_numbers = true)]
    tol_relative: Option<f64>,
    /// Stop after the first mesh with at least N unknowns; overrides adapt.max_unknowns
    #[arg(long)]
    max_unknowns: Option<usize>,
    /// Refine everywhere (every size halved at each step) instead of adaptively
    #[arg(long)]
    uniform: bool,
    /// How eta_T sets the next sizes: dorfler (bulk), maximum, or equidistribution; overrides
    /// adapt.marking
    #[arg(long, value_enum)]
    marking: Option<Marking>,
    /// Fraction theta of the marking strategy (equidistribution: the aimed reduction of eta
    /// per step); overrides adapt.bulk (default 0.5)
    #[arg(long, allow_negative_numbers = true)]
    bulk: Option<f64>,
    /// gamma_lin of the Newton stopping rule; overrides adapt.gamma_lin (default 0.1)
    #[arg(long, allow_negative_numbers = true)]
    gamma_lin: Option<f64>,
    /// gamma_reg of the regularisation stopping rule; overrides adapt.gamma_reg (default 0.1)
    #[arg(long, allow_negative_numbers = true)]
    gamma_reg: Option<f64>,
    /// Then refine uniformly from the same first mesh until the unknowns exceed the adaptive
    /// run's (into OUTPUT/uniform) and draw eta_tot of both against the unknowns; sets
    /// adapt.compare_uniform
    #[arg(long)]
    compare_uniform: bool,
    /// At every step, also compute a sharp lower bound of the error's dual norm and I_eff =
    /// eta_tot / bound (column i_eff of the history; costly)
    #[arg(long)]
    effectivity: bool,
}

/// What `history.json` records.
#[derive(Serialize)]
struct History<'a> {
    units: Units,
    scene: &'a Path,
    order: usize,
    settings: &'a AdaptSettings,
    steps: &'a [StepRecord],
    /// Why the run stopped early, if it did.
    error: Option<String>,
}

/// What `summary.json` records of `adapt` beside the last step's solution: with `best_step`,
/// the earlier step of smallest η_tot, null when the last step has it.
#[derive(Serialize)]
struct AdaptSummary {
    step: usize,
    seconds: PhaseTimes,
    best_step: Option<BestStep>,
}

/// The step of smallest η_tot when the last step's η_tot is larger: the run's tightest bound
/// of the error, its size, its joint numbers as `history.json` has them, and its fields.
#[derive(Serialize, Clone, Debug)]
pub struct BestStep {
    pub step: usize,
    pub eta_tot: f64,
    pub unknowns: usize,
    /// On a straight joint with a heel: the crack open from the heel \[m\] and the resultant.
    pub crack_length: Option<f64>,
    pub resultant: Option<Resultant>,
    /// Its `<scene>_NN.vtu`.
    pub file: PathBuf,
}

/// The index in `history` of the step of smallest η_tot, if the last step's η_tot is larger
/// (the first of equal ones).
pub fn best_step(history: &[StepRecord]) -> Option<usize> {
    let last = history.last()?.eta.tot;
    let (k, best) = history.iter().enumerate().min_by(|a, b| a.1.eta.tot.total_cmp(&b.1.eta.tot))?;
    (best.eta.tot < last).then_some(k)
}

impl BestStep {
    /// The [`best_step`] of `history`, whose steps wrote the VTU files `vtu` (the main one
    /// first).
    fn of(history: &[StepRecord], vtu: &[Vec<PathBuf>]) -> Option<Self> {
        let k = best_step(history)?;
        let r = &history[k];
        Some(BestStep {
            step: r.step,
            eta_tot: r.eta.tot,
            unknowns: r.unknowns,
            crack_length: r.crack_length,
            resultant: r.resultant,
            file: vtu[k][0].clone(),
        })
    }

    /// The closing line of a run whose last step is `last`.
    fn line(&self, last: &StepRecord) -> String {
        format!(
            "step {} has the smallest eta_tot, {:.3e} Pa m with {} unknowns, against {:.3e} Pa m with {} unknowns \
             on the last step {}, which summary.json describes; its fields are in {}",
            self.step,
            self.eta_tot,
            self.unknowns,
            last.eta.tot,
            last.unknowns,
            last.step,
            self.file.display()
        )
    }
}

/// What an adaptive run leaves to its command.
pub struct Sequence {
    pub history: Vec<StepRecord>,
    /// The closing lines of the last step's summary.
    pub headline: Vec<String>,
    pub best: Option<BestStep>,
}

/// The scene as the adaptive loop's model, with the Newton trace of `-v`.
struct Traced<'a> {
    scene: &'a Scene,
    trace: Option<fn(usize, f64)>,
    path_trace: Option<fn(&PathPoint)>,
}

impl Model for Traced<'_> {
    fn problem(&self, mesh: Mesh) -> Result<(Problem, Option<ContactJoint>), AdaptError> {
        Model::problem(self.scene, mesh)
    }

    fn newton(&self) -> NewtonOptions {
        NewtonOptions { trace: self.trace, ..self.scene.newton_options() }
    }

    fn joint_line(&self, problem: &Problem) -> Option<JointLine> {
        self.scene.joint_line(problem)
    }

    fn load_path(&self) -> Option<LoadPath> {
        self.scene.load_path().map(|path| LoadPath { trace: self.path_trace, ..path })
    }
}

pub fn run(args: Args) -> Result<()> {
    let progress = args.input.progress();
    let mut scene = args.input.scene()?;
    override_settings(&args, &mut scene)?;
    anyhow::ensure!(
        scene.geometry.extension().is_some_and(|e| e == "geo"),
        "{}: adaptive refinement remeshes the geometry, so it needs a .geo file, not a mesh",
        scene.geometry.display()
    );
    let dir = args.output.dir(&scene)?;
    let name = stem(&scene.source);
    let run = args.input.in_combination(run_sequence(
        &scene,
        &args.input,
        &dir,
        &name,
        "",
        &mut |_| Ok(()),
        args.effectivity,
    ))?;
    progress.say(&format!("results in {} ({name}.pvd, history.csv, {name}_eta.png)", dir.display()));
    progress.result(&table(&run.history));
    for line in run.headline {
        progress.result(&format!("last step: {line}"));
    }
    if scene.adapt.compare_uniform {
        compare_uniform(&scene, &args.input, &dir, &name, &run.history)?;
    }
    Ok(())
}

/// The refinement sequence of `scene` into `dir`: every step written as it comes (and handed
/// to `also`), then the lists and figures; progress lines start with `prefix`. An error names
/// the step and where the steps before it are. With `effectivity`, every step records its
/// I_eff. Closes with a line naming the step of smallest η_tot if it is not the last.
pub fn run_sequence(
    scene: &Scene,
    input: &Input,
    dir: &Path,
    name: &str,
    prefix: &str,
    also: &mut dyn FnMut(&Step) -> Result<()>,
    effectivity: bool,
) -> Result<Sequence> {
    let progress = input.progress();
    interrupt::record_in(&dir.join("history.json"));
    let scene = &input.before_earthquake(scene.clone())?;
    let mut mesher = GeoMesher {
        verbose: input.verbose,
        allow_system_calls: input.allow_system_calls,
        ..scene.mesher(scene.adapt.refinement)
    };
    let mut writer = StepWriter {
        dir,
        name,
        scene,
        effectivity,
        history: Vec::new(),
        vtu: Vec::new(),
        headline: Vec::new(),
        best: None,
    };
    let model = Traced { scene, trace: input.newton_trace(), path_trace: input.path_trace() };
    let result = adapt::run(&scene.adapt, &mut mesher, &model, |step| {
        let output = |error: anyhow::Error| AdaptError::Output { step: step.record.step, error: error.into() };
        if writer.history.is_empty() {
            let removed = remove_earlier_outputs(dir, name, &[]).map_err(output)?;
            if removed > 0 {
                progress.say(&format!("{prefix}removed {removed} files of an earlier run from {}", dir.display()));
            }
        }
        writer.write(step).map_err(output)?;
        also(step).map_err(output)?;
        progress.say(&format!("{prefix}{}", step_line(writer.history.last().expect("just written"))));
        Ok(())
    });
    // a scene or geometry that does not fit its first mesh is bad input, and a first step that
    // cannot be written has nothing to keep: nothing is written
    if let Err(e @ (AdaptError::Mesh(_) | AdaptError::Problem(_) | AdaptError::Output { .. })) = &result {
        anyhow::ensure!(!writer.history.is_empty(), "{e}");
    }
    let error = result.as_ref().err().map(|e| format!("{e}"));
    writer.finish(error.clone())?;
    if let Some((last, stall)) = writer.history.last().and_then(|r| Some((r.step, r.stall?))) {
        progress.say(&format!("{prefix}stopped after step {last}: {stall}"));
    }
    if let Some((last, limit)) = writer.history.last().and_then(|r| Some((r.step, r.cell_limit?))) {
        progress.say(&format!("{prefix}stopped after step {last}: {limit}"));
    }
    if let Some((best, last)) = writer.best.as_ref().zip(writer.history.last()) {
        progress.say(&format!("{prefix}{}", best.line(last)));
    }
    if let Some(e) = error {
        let kind = match scene.adapt.refinement {
            Refinement::Adaptive => "adaptive",
            Refinement::Uniform => "uniform",
        };
        let hint = result.as_ref().err().and_then(|e| remesh_hint(e, writer.history.len(), scene.adapt.refinement));
        let kept = match writer.history.is_empty() {
            true => format!("its history is in {}", dir.display()),
            false => format!("the steps before it are in {}", dir.display()),
        };
        if let (None, Err(source)) = (&hint, result) {
            // the error kept as the source: its outcome (no equilibrium, a failed solve) sets the exit code
            let at = format!("{}: {kind} step {}", scene.source.display(), writer.history.len());
            return Err(anyhow::Error::new(source).context(format!("{at} ({kept})")));
        }
        anyhow::bail!(
            "{}: {kind} step {}: {e}; {kept}{}",
            scene.source.display(),
            writer.history.len(),
            hint.map_or(String::new(), |h| format!("\n{h}"))
        );
    }
    Ok(Sequence { history: writer.history, headline: writer.headline, best: writer.best })
}

/// Uniform refinement of `scene` from the same first mesh into `<dir>/uniform`, up to the
/// first mesh with more unknowns than the last of `adaptive` (or adapt.steps meshes), and the
/// figure `<name>_adaptive_uniform` of both runs.
fn compare_uniform(scene: &Scene, input: &Input, dir: &Path, name: &str, adaptive: &[StepRecord]) -> Result<()> {
    let mut uniform = scene.clone();
    uniform.adapt = uniform_settings(&scene.adapt, adaptive.last().map_or(0, |r| r.unknowns));
    let sub = output_dir(dir.join("uniform"))?;
    let history = run_sequence(&uniform, input, &sub, name, "uniform ", &mut |_| Ok(()), false)?.history;
    input.progress().result(&format!("uniform refinement from the same first mesh:\n{}", table(&history)));
    let files = write_adaptive_uniform(dir, name, adaptive, &history).context("writing the comparison figure")?;
    let figures: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    input.progress().say(&format!(
        "uniform refinement in {}; adaptive against uniform in {}",
        sub.display(),
        figures.join(" and ")
    ));
    Ok(())
}

/// `adaptive` with every size halved at each step, no tolerance, and a stop at the first mesh
/// with more than `unknowns` unknowns.
fn uniform_settings(adaptive: &AdaptSettings, unknowns: usize) -> AdaptSettings {
    AdaptSettings {
        refinement: Refinement::Uniform,
        tol: None,
        tol_relative: None,
        max_unknowns: Some(unknowns + 1),
        compare_uniform: false,
        ..adaptive.clone()
    }
}

/// What to try when gmsh fails to remesh with the sizes of an adaptive step: the sizes it
/// was given shrink fastest at corners, where gmsh can produce a degenerate triangle.
fn remesh_hint(error: &AdaptError, step: usize, refinement: Refinement) -> Option<&'static str> {
    let remesh = matches!(error, AdaptError::Mesh(_)) && step > 0 && refinement == Refinement::Adaptive;
    remesh.then_some(
        "the adaptive sizes were too small for gmsh near a corner: set [mesh] size_min to bound them, \
         or use --marking dorfler, which refines fewer cells per step",
    )
}

/// The flags of `adapt` that override `[adapt]` keys.
fn adapt_settings(args: &Args) -> Vec<Setting<'static>> {
    vec![
        Setting::value("--steps", "adapt.steps", args.steps, |s, v| s.adapt.steps = v),
        Setting::value("--tol", "adapt.tol", args.tol, |s, v| s.adapt.tol = Some(v)),
        Setting::value("--tol-relative", "adapt.tol_relative", args.tol_relative, |s, v| {
            s.adapt.tol_relative = Some(v)
        }),
        Setting::value("--max-unknowns", "adapt.max_unknowns", args.max_unknowns, |s, v| {
            s.adapt.max_unknowns = Some(v)
        }),
        Setting::switch("--uniform", "adapt.refinement", args.uniform, |s| s.adapt.refinement = Refinement::Uniform),
        Setting::value("--marking", "adapt.marking", args.marking, |s, v| s.adapt.marking = v),
        Setting::value("--bulk", "adapt.bulk", args.bulk, |s, v| s.adapt.bulk = v),
        Setting::value("--gamma-lin", "adapt.gamma_lin", args.gamma_lin, |s, v| s.adapt.gamma_lin = v),
        Setting::value("--gamma-reg", "adapt.gamma_reg", args.gamma_reg, |s, v| s.adapt.gamma_reg = v),
        Setting::switch("--compare-uniform", "adapt.compare_uniform", args.compare_uniform, |s| {
            s.adapt.compare_uniform = true
        }),
    ]
}

/// The scene with the flags' `[adapt]` keys, checked.
fn override_settings(args: &Args, scene: &mut Scene) -> Result<()> {
    settings::write(scene, adapt_settings(args)).validate(scene)?;
    Ok(scene.check_adaptive()?)
}

/// Writes every step as it comes, and the files that list the steps.
struct StepWriter<'a> {
    dir: &'a Path,
    name: &'a str,
    scene: &'a Scene,
    /// Whether each step records I_eff against the sharp reference.
    effectivity: bool,
    history: Vec<StepRecord>,
    /// The VTU files of every step.
    vtu: Vec<Vec<PathBuf>>,
    /// The closing lines of the last step's summary.
    headline: Vec<String>,
    /// The step of smallest η_tot so far, if not the last.
    best: Option<BestStep>,
}

impl StepWriter<'_> {
    /// The ParaView files of `step`, then the collections and the history so far, then the
    /// summary. Until the collections list them, the step's files are removed on a failure
    /// (and the step left out of the lists).
    fn write(&mut self, step: &Step) -> Result<()> {
        let problem = step.problem;
        let u = problem.displacement(step.disc, step.x);
        let sigma = cell_mean_stress(problem, &u);
        let results = Results { problem, u: &u, sigma: &sigma, contact: step.contact, estimate: Some(step.estimate) };
        let name = format!("{}_{:02}", self.name, step.record.step);
        let mut provisional = Provisional::default();
        let files = write_results(self.dir, &name, self.scene, &results, &mut provisional)?;
        let reference = self.effectivity.then(|| self.reference(step, &u)).transpose()?;
        self.vtu.push(files.clone());
        self.history.push(StepRecord {
            i_eff: reference.as_ref().map(|r| r.i_eff),
            i_eff_reference_converged: reference.map(|r| r.converged),
            ..step.record.clone()
        });
        self.best = BestStep::of(&self.history, &self.vtu);
        if let Err(e) = self.write_lists(None) {
            self.vtu.pop();
            self.history.pop();
            self.best = BestStep::of(&self.history, &self.vtu);
            return Err(e);
        }
        provisional.keep();
        let line = self.scene.joint_line(problem);
        let command =
            AdaptSummary { step: step.record.step, seconds: step.record.seconds, best_step: self.best.clone() };
        let summary = Summary::new(self.scene, step.disc, &results, line, files, command);
        write_output(&self.dir.join("summary.json"), serde_json::to_string_pretty(&summary)?.as_bytes())?;
        self.headline = summary.headline();
        Ok(())
    }

    /// η_tot of `step` against the sharp reference of its residual.
    fn reference(&self, step: &Step, u: &[Vector]) -> Result<Effectivity> {
        let solved = step.joint.zip(step.contact).map(|(j, c)| j.as_solved(c));
        Ok(effectivity(step.problem, u, solved.as_ref(), step.record.eta.tot)?)
    }

    /// `history.json` and `history.csv`, then one `.pvd` per kind of VTU file (time = step):
    /// a collection never lists a step the history does not have.
    fn write_lists(&self, error: Option<String>) -> Result<()> {
        let history = History {
            units: UNITS,
            scene: &self.scene.source,
            order: self.scene.mesh.order,
            settings: &self.scene.adapt,
            steps: &self.history,
            error,
        };
        write_output(&self.dir.join("history.json"), serde_json::to_string_pretty(&history)?.as_bytes())?;
        write_output(&self.dir.join("history.csv"), to_csv(&self.history).as_bytes())?;
        let kinds = self.vtu.first().map_or(0, Vec::len);
        for k in 0..kinds {
            let entries: Vec<(f64, PathBuf)> =
                self.vtu.iter().enumerate().map(|(step, files)| (step as f64, files[k].clone())).collect();
            write_pvd(&self.dir.join(pvd_name(self.name, &entries[0].1)), &entries)?;
        }
        Ok(())
    }

    /// The lists with the reason of an early stop, and the figures of the steps done.
    fn finish(&self, error: Option<String>) -> Result<()> {
        self.write_lists(error)?;
        if !self.history.is_empty() {
            let title = match &self.scene.combination_name {
                Some(c) => format!("{}, combination {c}", self.name),
                None => self.name.to_string(),
            };
            write_plots(self.dir, self.name, &title, &self.history).context("writing the figures")?;
        }
        Ok(())
    }
}

/// `<name><kind>.pvd` for the step file `<name>_NN<kind>.vtu`.
fn pvd_name(name: &str, file: &Path) -> String {
    let stem = file.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
    let kind = stem
        .strip_prefix(name)
        .map_or("", |rest| rest.trim_start_matches('_').trim_start_matches(|c: char| c.is_ascii_digit()));
    format!("{name}{kind}.pvd")
}

/// The progress line of a step.
fn step_line(r: &StepRecord) -> String {
    let delta = r.delta.map_or(String::new(), |d| format!("  delta {d:.2e}"));
    let crack = r.crack_length.map_or(String::new(), |c| format!("  crack {c:.3} m"));
    let resultant = r.resultant.map_or(String::new(), |f| format!("  resultant {:.3} m", f.position));
    let i_eff = match (r.i_eff, r.i_eff_reference_converged) {
        (Some(i), Some(false)) => format!("  I_eff {i:.3} (reference not converged: the index may be lower)"),
        (Some(i), _) => format!("  I_eff {i:.3}"),
        (None, _) => String::new(),
    };
    let finish = match r.finish {
        Some(f) if f.eta_lin_stopped.is_some() => format!(" (+{} to the residual tolerance)", f.n_lin),
        Some(_) => " (to the residual tolerance)".into(),
        None => String::new(),
    };
    let balance = match r.regularisation_balanced {
        Some(false) => "  (eta_reg above its share: Newton stalled at smaller delta)",
        _ => "",
    };
    let stalled = match r.newton_stalled {
        true => "  (Newton stalled before the residual tolerance: the iterate where eta_lin met its share)",
        false => "",
    };
    format!(
        "step {:>2}  {:>8} unknowns  eta {:.3e} ({:.2e} of |sigma_h|)  N_reg {:>2}  N_lin {:>2}{finish}{delta}{crack}{resultant}{i_eff}  {:.2} s{balance}{stalled}",
        r.step,
        r.unknowns,
        r.eta.tot,
        r.eta.tot / r.stress_norm,
        r.n_reg,
        r.n_lin,
        r.seconds.total()
    )
}

/// The closing table: one row per step, with the crack at the heel and the resultant's
/// distance from the heel on a straight joint with a heel, and I_eff if it was computed.
fn table(history: &[StepRecord]) -> String {
    let with_i_eff = history.iter().any(|r| r.i_eff.is_some());
    let i_eff_head = if with_i_eff { format!(" {:>6}", "I_eff") } else { String::new() };
    let mut lines = vec![format!(
        "{:>4} {:>9} {:>11} {:>11} {:>11} {:>11} {:>5} {:>5} {:>9} {:>9} {:>9}{i_eff_head}",
        "step",
        "unknowns",
        "eta_tot",
        "eta_flux",
        "eta_reg",
        "eta_lin",
        "N_reg",
        "N_lin",
        "crack [m]",
        "s_R [m]",
        "time [s]"
    )];
    let metres = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.4}"));
    for r in history {
        let i_eff = match (with_i_eff, r.i_eff) {
            (false, _) => String::new(),
            (true, Some(i)) => format!(" {i:>6.3}"),
            (true, None) => format!(" {:>6}", "-"),
        };
        lines.push(format!(
            "{:>4} {:>9} {:>11.4e} {:>11.4e} {:>11.4e} {:>11.4e} {:>5} {:>5} {:>9} {:>9} {:>9.2}{i_eff}",
            r.step,
            r.unknowns,
            r.eta.tot,
            r.eta.flux,
            r.eta.reg,
            r.eta.lin,
            r.n_reg,
            r.n_lin,
            metres(r.crack_length),
            metres(r.resultant.map(|f| f.position)),
            r.seconds.total()
        ));
    }
    lines.join("\n")
}

#[cfg(test)]
mod tests {
    use super::{
        best_step, remesh_hint, step_line, AdaptError, AdaptSummary, BestStep, PhaseTimes, Refinement, StepRecord,
    };
    use crate::estimate::estimators::GlobalEstimators;
    use std::path::PathBuf;

    /// A step's record with η_reg = η_flux, balanced, without I_eff.
    fn record() -> StepRecord {
        StepRecord {
            step: 0,
            cells: 10,
            unknowns: 20,
            eta: GlobalEstimators { osc: 0.0, flux: 1.0, neu: 0.0, disc: 0.0, reg: 1.0, lin: 0.0, tot: 2.0 },
            stress_norm: 1.0,
            delta: Some(1.0),
            n_reg: 1,
            n_lin: 3,
            finish: None,
            newton_stalled: false,
            regularisation_balanced: Some(true),
            n_est: 1,
            equilibration: 0.0,
            i_eff: None,
            i_eff_reference_converged: None,
            crack_length: None,
            resultant: None,
            stall: None,
            cell_limit: None,
            seconds: PhaseTimes::default(),
            elapsed: 0.0,
        }
    }

    // The record of a step whose level ended at a δ_s solved on it after Newton failed below
    // (docs/method.md §5.3; the level itself: tests/end_to_end/adapt.rs). Goal: history.json
    // writes `regularisation_balanced: false` and the progress line says that Newton stalled
    // at the smaller δ; a balanced step's line says nothing of it. Parameters: a record with
    // η_reg = η_flux, above γ_reg = 0.1 of the rest.
    #[test]
    fn an_unbalanced_step_says_so() {
        let record = |balanced| StepRecord { regularisation_balanced: Some(balanced), ..record() };
        let line = step_line(&record(false));
        assert!(line.ends_with("(eta_reg above its share: Newton stalled at smaller delta)"), "{line}");
        assert!(!step_line(&record(true)).contains("stalled"));
        let json = serde_json::to_value(record(false)).unwrap();
        assert_eq!(json["regularisation_balanced"], serde_json::Value::Bool(false), "{json}");
    }

    // The record of a step whose sharp reference stopped at its size limit before its last
    // two values agreed (src/estimate/reference/mod.rs). Goal: the progress line and history.json say
    // so, since I_eff then overestimates the true index by more than the reference's 2 %; a
    // converged reference's line says nothing of it. Parameters: a record with I_eff 1.5.
    #[test]
    fn an_unconverged_reference_says_so() {
        let record =
            |converged| StepRecord { i_eff: Some(1.5), i_eff_reference_converged: Some(converged), ..record() };
        let line = step_line(&record(false));
        assert!(line.contains("I_eff 1.500 (reference not converged: the index may be lower)"), "{line}");
        assert!(!step_line(&record(true)).contains("not converged"));
        let json = serde_json::to_value(record(false)).unwrap();
        assert_eq!(json["i_eff_reference_converged"], serde_json::Value::Bool(false), "{json}");
    }

    /// Records of steps 0, 1, … with these η_tot and 100 (k + 1) unknowns.
    fn run(eta_tot: &[f64]) -> Vec<StepRecord> {
        let step = |(k, &tot): (usize, &f64)| {
            let r = record();
            StepRecord { step: k, unknowns: 100 * (k + 1), eta: GlobalEstimators { tot, ..r.eta }, ..r }
        };
        eta_tot.iter().enumerate().map(step).collect()
    }

    // Source: an adaptive run of geo/dam_lift_joint.toml (docs/results.md), whose η_tot fell
    // over six meshes and rose on the last two, the last mesh 19 times looser than the sixth.
    // Goal: the step of smallest η_tot is named only when the last step's η_tot is larger: not
    // on a falling run, a single step, or a last step that ties the smallest; the first of equal
    // minima; summary.json's `best_step` holds that step's η_tot, unknowns and file, and is
    // null otherwise; the closing line names both steps and the file. Parameters: hand-built
    // records, η_tot in Pa m.
    #[test]
    fn the_step_of_smallest_eta_is_named_when_the_last_is_looser() {
        let lift = [3.85e5, 1.2e5, 5.0e4, 3.0e4, 1.5e4, 1.06e4, 2.36e4, 2.01e5];
        assert_eq!(best_step(&run(&lift)), Some(5));
        assert_eq!(best_step(&run(&[3.0, 1.0, 2.0, 1.0, 1.5])), Some(1), "the first of equal minima");
        assert_eq!(best_step(&run(&[3.0, 2.0, 1.0])), None, "the last step has the smallest");
        assert_eq!(best_step(&run(&[3.0, 1.0, 2.0, 1.0])), None, "the last step ties the smallest");
        assert_eq!(best_step(&run(&[3.0])), None);
        assert_eq!(best_step(&[]), None);
        let history = run(&lift);
        let vtu: Vec<Vec<PathBuf>> = (0..lift.len())
            .map(|k| vec![format!("d_{k:02}.vtu").into(), format!("d_{k:02}_boundary.vtu").into()])
            .collect();
        let best = BestStep::of(&history, &vtu).unwrap();
        assert_eq!((best.step, best.eta_tot, best.unknowns, best.file.clone()), (5, 1.06e4, 600, "d_05.vtu".into()));
        let line = best.line(history.last().unwrap());
        assert!(line.starts_with("step 5 has the smallest eta_tot, 1.060e4 Pa m with 600 unknowns"), "{line}");
        assert!(line.contains("against 2.010e5 Pa m with 800 unknowns on the last step 7"), "{line}");
        assert!(line.ends_with("its fields are in d_05.vtu"), "{line}");
        let summary = |best_step| AdaptSummary { step: 7, seconds: PhaseTimes::default(), best_step };
        let json = serde_json::to_value(summary(Some(best))).unwrap();
        assert_eq!(json["best_step"]["step"], 5, "{json}");
        assert_eq!(json["best_step"]["eta_tot"], 1.06e4, "{json}");
        assert_eq!(json["best_step"]["file"], "d_05.vtu", "{json}");
        let falling = BestStep::of(&run(&[3.0, 2.0, 1.0]), &vtu[..3]);
        assert!(serde_json::to_value(summary(falling)).unwrap()["best_step"].is_null());
    }

    #[test]
    fn a_failed_remesh_suggests_size_min_or_dorfler() {
        let mesh = || AdaptError::Mesh("degenerate triangle".into());
        let hint = remesh_hint(&mesh(), 5, Refinement::Adaptive).unwrap();
        assert!(hint.contains("[mesh] size_min") && hint.contains("--marking dorfler"), "{hint}");
        assert!(remesh_hint(&mesh(), 0, Refinement::Adaptive).is_none(), "the first mesh is not a remesh");
        assert!(remesh_hint(&mesh(), 5, Refinement::Uniform).is_none());
        let regularisation = AdaptError::Regularisation { delta: 1.0, reductions: 3, eta_reg: 1.0 };
        assert!(remesh_hint(&regularisation, 5, Refinement::Adaptive).is_none());
    }
}
