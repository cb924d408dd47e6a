//! `damfem safety`: the dam-safety analysis of a scene (docs/method.md §1.9). The adaptive
//! loop of `damfem adapt` refines until η_tot ≤ `--tol-relative` ‖σ_h‖; on its last mesh, whose
//! Newton run the loop finishes to the residual tolerance, the joint gives N, T, U, the contact and crack lengths, the resultant and the middle-third
//! check, the heel and toe normal stresses averaged over a stated length, FS_LE and FS_SR.

mod report;

use super::adapt::run_sequence;
use super::common::{output_dir, remove_earlier_outputs, stem, Input, Output, Progress};
use super::output::{drain_note, Units, UNITS};
use super::settings::{self, Setting};
use crate::adapt::{AdaptError, Step};
use crate::contact::{BondLengths, ContactError, ContactJoint, ContactSolution, JointLine};
use crate::elasticity::Problem;
use crate::io::atomic::write_output;
use crate::io::plot::write_linear_figure;
use crate::safety::base::base_stresses;
use crate::safety::check::{checks, verdict, FiniteElements};
use crate::safety::classical::classical;
use crate::safety::criteria::Requirements;
use crate::safety::resultant::{forces_on, resultant};
use crate::safety::strength::{reduce_strength, StrengthReduction, STRENGTH_TOLERANCE};
use crate::scene::Scene;
use crate::solve::NewtonOptions;
use anyhow::{Context, Result};
use report::{
    base_figure, combination_rows, combinations_markdown, joint_csv, joint_rows, plane_drains, table, text_columns,
    text_table, write_files, Report, StepRow,
};
use serde::Serialize;
use std::path::Path;

/// The default tolerance on η_tot / ‖σ_h‖.
const TOL_RELATIVE: f64 = 0.01;

/// The heel and toe stresses are averaged over this fraction of the joint by default.
const AVERAGE_FRACTION: f64 = 0.1;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    #[command(flatten)]
    output: Output,
    /// Refine until eta_tot <= TOL ||sigma_h||; overrides adapt.tol_relative (default 0.01)
    #[arg(long, allow_negative_numbers = true)]
    tol_relative: Option<f64>,
    /// Most meshes of the adaptive run; overrides adapt.steps (default 8)
    #[arg(long)]
    max_steps: Option<usize>,
    /// Length [m] from the heel and from the toe over which the normal stress is averaged
    /// (default: a tenth of the joint)
    #[arg(long, allow_negative_numbers = true)]
    average_length: Option<f64>,
}

pub fn run(args: Args) -> Result<()> {
    let progress = args.input.progress();
    let scene = scene(&args)?;
    let names: Vec<String> = scene.combinations.keys().cloned().collect();
    let cases: Vec<(Option<&str>, Scene)> = if names.is_empty() {
        vec![(None, scene.clone())]
    } else {
        names.iter().map(|n| Ok((Some(n.as_str()), scene.combination(n)?))).collect::<Result<_>>()?
    };
    // every case is checked before anything is written; one whose loads need more than the
    // joint alone can carry already has its verdict
    let mut lines = Vec::new();
    for (name, case) in &cases {
        let named = |e: anyhow::Error| match name {
            Some(n) => e.context(format!("combination {n}")),
            None => e,
        };
        let prefix = name.map_or(String::new(), |n| format!("combination {n}: "));
        lines.push(match joint_line(case, &args.input) {
            Err(e) if !names.is_empty() && super::exit_code(&e) == super::DOES_NOT_HOLD => Err(e),
            checked => {
                let (line, warnings) = checked.map_err(named)?;
                progress.warn(&warnings.iter().map(|w| format!("{prefix}{w}")).collect::<Vec<_>>());
                Ok((line, average_length(args.average_length, &line).map_err(named)?))
            }
        });
    }
    let dir = args.output.dir(&scene)?;
    if names.is_empty() {
        let line = lines.remove(0)?;
        // a scene without combinations, or one run by --combination
        let req = scene.criteria.requirements(scene.criteria.category_of(args.input.combination.as_deref()));
        let (report, table) = analyse(&cases[0].1, &args, line, req, &dir)?;
        write_files(&dir, &report, &table)?;
        if !args.input.quiet {
            println!("{}", text_table(&table));
        }
        progress.say(&format!("results in {} (safety.json, report.md, joint.csv, base_stresses.png)", dir.display()));
        return Ok(());
    }
    remove_earlier_outputs(&dir, &stem(&scene.source), &[])?;
    // each combination on its own: one that does not hold or whose solve fails gets its row,
    // and the report is written again after every combination
    let (mut reports, mut worst): (Vec<Combination>, Option<anyhow::Error>) = (Vec::new(), None);
    for ((name, case), line) in cases.iter().zip(lines) {
        let name = name.expect("a combination");
        progress.say(&format!("combination {name}"));
        let sub = output_dir(dir.join(name))?;
        let req = scene.criteria.requirements(scene.criteria.category_of(Some(name)));
        let outcome = match line.and_then(|line| analyse(case, &args, line, req, &sub)) {
            Ok((report, table)) => {
                write_files(&sub, &report, &table)?;
                Outcome::Solved(Box::new(report))
            }
            Err(e) => {
                let e = e.context(format!("combination {name}"));
                let outcome = match super::exit_code(&e) {
                    super::DOES_NOT_HOLD => Outcome::DoesNotHold { load_factor: limit(&e), verdict: format!("{e:#}") },
                    super::SOLVER_FAILED => Outcome::SolverFailed { error: format!("{e:#}") },
                    _ => return Err(e),
                };
                progress.say(&format!("{}: {e:#}", outcome.label()));
                worst = match worst {
                    Some(w) if super::exit_code(&w) <= super::exit_code(&e) => Some(w),
                    _ => Some(e),
                };
                outcome
            }
        };
        reports.push(Combination { name: name.to_string(), outcome });
        write_combinations(&dir, &scene, &reports)?;
    }
    if !args.input.quiet {
        println!("{}", text_columns(&combination_rows(&reports)));
    }
    progress.say(&format!("results in {} (safety.json, report.md; one directory per combination)", dir.display()));
    match worst {
        Some(e) => Err(e.context("not every combination has a result (report.md lists them)")),
        None => Ok(()),
    }
}

/// λ* of a combination that does not hold, where the load path ended.
fn limit(e: &anyhow::Error) -> Option<f64> {
    e.chain().find_map(|link| match link.downcast_ref::<ContactError>() {
        Some(ContactError::NoEquilibrium(v)) => Some(v.load_factor),
        _ => match link.downcast_ref::<AdaptError>() {
            Some(AdaptError::Contact(ContactError::NoEquilibrium(v))) => Some(v.load_factor),
            _ => None,
        },
    })
}

/// The scene with the flags' tolerance and steps for the adaptive run, checked.
fn scene(args: &Args) -> Result<Scene> {
    let mut scene = args.input.scene()?;
    scene.adapt.tol_relative = Some(scene.adapt.tol_relative.unwrap_or(TOL_RELATIVE));
    scene.adapt.compare_uniform = false;
    let table = vec![
        Setting::value("--tol-relative", "adapt.tol_relative", args.tol_relative, |s, v| {
            s.adapt.tol_relative = Some(v)
        }),
        Setting::value("--max-steps", "adapt.steps", args.max_steps, |s, v| s.adapt.steps = v),
    ];
    settings::write(&mut scene, table).validate(&scene)?;
    scene.check_adaptive()?;
    anyhow::ensure!(
        scene.geometry.extension().is_some_and(|e| e == "geo"),
        "{}: the safety analysis refines the mesh adaptively, so it needs a .geo file, not a mesh",
        scene.geometry.display()
    );
    Ok(scene)
}

/// `safety.json` and `report.md` of the combinations in `dir` finished so far.
fn write_combinations(dir: &Path, scene: &Scene, reports: &[Combination]) -> Result<()> {
    let rows = combination_rows(reports);
    let json = serde_json::to_string_pretty(&Combinations { units: UNITS, combinations: reports })?;
    write_output(&dir.join("safety.json"), json.as_bytes())?;
    write_output(&dir.join("report.md"), combinations_markdown(&scene.source, &rows, reports).as_bytes())?;
    Ok(())
}

/// One combination's outcome, as the combined `safety.json` lists it.
#[derive(Serialize)]
struct Combination {
    name: String,
    #[serde(flatten)]
    outcome: Outcome,
}

/// What a combination gave: its report, the verdict that the dam does not hold under it (the
/// load path ended at λ* < 1, or the loads need more than the joint alone can carry: λ*
/// None), or the failure of its solve.
#[derive(Serialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
enum Outcome {
    Solved(Box<Report>),
    DoesNotHold { load_factor: Option<f64>, verdict: String },
    SolverFailed { error: String },
}

impl Outcome {
    /// The outcome in a word or two.
    fn label(&self) -> String {
        match self {
            Outcome::Solved(_) => "holds".to_string(),
            Outcome::DoesNotHold { load_factor: Some(l), .. } => format!("does not hold beyond λ* = {l:.3}"),
            Outcome::DoesNotHold { load_factor: None, .. } => "does not hold".to_string(),
            Outcome::SolverFailed { .. } => "solver failed".to_string(),
        }
    }

    /// The report of a combination that has one.
    fn report(&self) -> Option<&Report> {
        match self {
            Outcome::Solved(r) => Some(r),
            _ => None,
        }
    }
}

/// What `safety.json` records of a scene with load combinations.
#[derive(Serialize)]
struct Combinations<'a> {
    units: Units,
    combinations: &'a [Combination],
}

/// The analysis of `scene` into `dir`: the adaptive run on the joint `line` (with the
/// averaging length), then the safety quantities of its last mesh; returns the report and its
/// table.
fn analyse(
    scene: &Scene,
    args: &Args,
    (line, average): (JointLine, f64),
    requirements: Requirements,
    dir: &Path,
) -> Result<(Report, Vec<[String; 3]>)> {
    let progress = args.input.progress();
    let tol_relative = scene.adapt.tol_relative.unwrap_or(TOL_RELATIVE);
    let name = stem(&scene.source);
    let mut rows = Vec::new();
    // the last step's problem (its joints already split) and joint, and the solution
    let mut last: Option<(Problem, ContactJoint, ContactSolution)> = None;
    let mut keep = |step: &Step| -> Result<()> {
        let c = step.contact.context("the step has no contact solution")?;
        let r = step.record;
        rows.push(StepRow {
            step: r.step,
            unknowns: r.unknowns,
            eta_relative: r.eta.tot / r.stress_norm,
            crack_length: c.crack_from_heel(&line),
            resultant_position: resultant(c, &line).map(|f| f.position),
            sliding_safety_factor: forces_on(c, &line).sliding_safety_factor,
        });
        let joint = step.joint.context("the step has no joint")?;
        last = Some((step.problem.clone(), joint.clone(), c.clone()));
        Ok(())
    };
    let run = run_sequence(scene, &args.input, dir, &name, "", &mut keep, false)?;
    let (problem, joint, solution) = last.context("the adaptive run made no step")?;
    let record = run.history.last().context("the adaptive run made no step")?;
    let disc = problem.discretise();
    // the sliding plane's curves: their friction alone gives FS_SR a strength to divide
    let plane = solution.curves_on(&line);
    let forces = forces_on(&solution, &line);
    let (strength, note) = match joint.has_friction_on(&plane) {
        false => (None, Some(FRICTIONLESS.to_string())),
        true => {
            let newton = NewtonOptions { trace: args.input.newton_trace(), ..scene.newton_options() };
            let sr = progress
                .stage(
                    "strength",
                    || Ok(reduce_strength(&problem, &disc, &joint, &plane, &solution, &newton, STRENGTH_TOLERANCE)?),
                    describe_strength,
                )?
                .0;
            let unbounded = (!sr.failed.is_finite()).then(|| format!("{} {:.0}", UNBOUNDED, sr.held));
            let fs_le = forces.sliding_safety_factor;
            (Some(sr), unbounded.or_else(|| outside_note(fs_le?, &sr, joint.has_bond_on(&plane))))
        }
    };
    let eta_relative = record.eta.tot / record.stress_norm;
    let (gravity, acceleration) = (scene.loads.gravity, scene.loads.acceleration);
    let (classical, classical_note) = match classical(&problem, &joint, &line, gravity, acceleration) {
        Ok(c) => (Some(c), None),
        Err(why) => (None, Some(format!("the classical method has no answer: {why}"))),
    };
    let mut report = Report {
        units: UNITS,
        scene: scene.source.clone(),
        order: problem.mesh.order,
        tol_relative,
        tolerance_met: eta_relative <= tol_relative,
        steps: rows,
        unknowns: record.unknowns,
        eta_tot: record.eta.tot,
        eta_relative,
        best_step: run.best.clone(),
        newton_stalled: record.newton_stalled,
        joint_line: line,
        contact_length: forces.contact_length,
        crack_length: solution.crack_from_heel(&line),
        bond_lengths: joint.has_bond_on(&plane).then(|| BondLengths::of(&solution.faces_on(&line))),
        crack_rule: (solution.nitsche.uplift.iter())
            .find(|up| up.curves.iter().any(|&c| plane[c]))
            .map(|up| up.diagram.rule),
        resultant: resultant(&solution, &line),
        base_stresses: base_stresses(&solution, &problem, &disc, &line, average),
        sliding_safety_factor: forces.sliding_safety_factor,
        strength_reduction: strength,
        safety_factor_note: note,
        crack_note: plane_crack_note(&solution, &plane),
        requirements,
        classical,
        classical_note,
        checks: Vec::new(),
        verdict: verdict(&[]),
    };
    report.checks = checks(&finite_elements(&report), report.classical.as_ref(), &requirements);
    report.verdict = verdict(&report.checks);
    warn(&report, &progress);
    let table = table(&report);
    let joint = joint_rows(&solution, &line);
    write_output(&dir.join("joint.csv"), joint_csv(&joint).as_bytes())?;
    let drains = plane_drains(&solution, &plane);
    write_linear_figure(&dir.join("base_stresses"), &base_figure(&joint, &report, drains))
        .context("writing the figure")?;
    Ok((report, table))
}

/// The finite-element numbers of `r` that the code check judges.
fn finite_elements(r: &Report) -> FiniteElements {
    let f = r.resultant;
    FiniteElements {
        length: r.joint_line.length,
        sliding: r.sliding_safety_factor,
        strength_reduction: r.strength_reduction.as_ref().map(|s| s.held),
        flotation: f.filter(|f| f.uplift_force > 0.0).map(|f| (f.normal_force + f.uplift_force) / f.uplift_force),
        resultant: f.map(|f| f.position),
        contact: r.contact_length,
        crack: r.crack_length,
        heel: r.base_stresses.heel,
        heel_closed: r.base_stresses.heel_closed,
        toe: r.base_stresses.toe,
    }
}

/// The progress line of FS_SR.
fn describe_strength(s: &StrengthReduction) -> String {
    format!("FS_SR in [{:.4}, {:.4}] after {} solves", s.held, s.failed, s.solves)
}

/// The warnings of a report: the tolerance not met, no safety factor.
fn warn(r: &Report, progress: &Progress) {
    if !r.tolerance_met {
        progress.say(&format!(
            "warning: eta_tot / ||sigma_h|| = {:.3e} after {} meshes is above --tol-relative {}: raise --max-steps",
            r.eta_relative,
            r.steps.len(),
            r.tol_relative
        ));
    }
    if let Some(note) = &r.safety_factor_note {
        progress.say(&format!("warning: {note}"));
    }
    if r.newton_stalled {
        progress.say(&format!("warning: {STALLED}"));
    }
    if let Some(note) = &r.crack_note {
        progress.say(&format!("note: {note}"));
    }
    if let Some(note) = &r.classical_note {
        progress.say(&format!("note: {note}"));
    }
}

/// The note on the crack of a diagram on the `plane`'s curves that stopped at the drain line.
fn plane_crack_note(solution: &ContactSolution, plane: &[bool]) -> Option<String> {
    let on_plane = |d: &usize| solution.nitsche.uplift[*d].curves.iter().any(|&c| plane[c]);
    (0..solution.cracks.len())
        .filter(on_plane)
        .find_map(|d| solution.cracks[d].and_then(|c| drain_note("the sliding plane", &c)))
}

/// What the report says of a last mesh whose Newton run stalled before the residual tolerance.
const STALLED: &str = "on the last mesh Newton stalled before the residual tolerance: its numbers are those of \
     the iterate where eta_lin met its share (S_lin), whose eta_tot still bounds the error";

/// What `safety.json` says without friction.
const FRICTIONLESS: &str = "the joint is frictionless (no [contact] friction, cohesion or threshold, or none \
     in the [joints] table of the sliding plane): it has no sliding resistance of its own, so FS_LE and FS_SR are not computed";

/// Why FS_LE may lie outside FS_SR's bracket (docs/method.md §1.9, §1.13), said where it does;
/// `bonded`: the sliding plane has a bond.
fn outside_note(fs_le: f64, sr: &StrengthReduction, bonded: bool) -> Option<String> {
    let side = if fs_le > sr.failed { "above" } else { "below" };
    let bond = match bonded {
        true => {
            "; on a bonded joint FS_LE counts the whole N, the bond's tension included, while the friction \
                 acts on the compressed part only, which carries N and that tension, so FS_SR may lie above it"
        }
        false => "",
    };
    (fs_le < sr.held || fs_le > sr.failed).then(|| {
        format!(
            "FS_LE = {fs_le:.4} lies {side} FS_SR's bracket [{:.4}, {:.4}]: FS_LE counts the cohesion over the joint's \
             contact length under the loads, while FS_SR follows the joint as its strength is divided by k, and with \
             the cohesion the contact length may change with k (the joint opens or closes){bond}; with friction alone \
             on a straight joint without a bond the two agree within 0.5 %, or the run stops",
            sr.held, sr.failed
        )
    })
}

/// What `safety.json` says when the joint holds at every reduction.
const UNBOUNDED: &str = "the joint still held with its strength divided by";

/// The straight joint of the scene on its first mesh, refused with a reason when there is none,
/// and the warnings of its uplift tables.
fn joint_line(scene: &Scene, input: &Input) -> Result<(JointLine, Vec<String>)> {
    let (problem, joint) = scene.problem(input.mesh(scene)?)?;
    anyhow::ensure!(
        joint.is_some(),
        "{}: the safety analysis needs a joint: give the dam–rock curve role = \"contact\" (a rigid \
         foundation) or a [joints.<curve>] table (a meshed rock block)",
        scene.source.display()
    );
    let line = scene.joint_line(&problem).with_context(|| {
        format!(
            "{}: the safety analysis needs a straight joint whose heel is known: the contact curves on one line, \
             and a hydrostatic curve (or the heel of [uplift] or of the joint's uplift table) at its upstream end",
            scene.source.display()
        )
    })?;
    Ok((line, scene.uplift_warnings(&problem.mesh, joint.as_ref())))
}

/// `--average-length`, or a tenth of the joint; it must lie in (0, L/2].
fn average_length(given: Option<f64>, line: &JointLine) -> Result<f64> {
    let length = given.unwrap_or(AVERAGE_FRACTION * line.length);
    anyhow::ensure!(
        length > 0.0 && length <= 0.5 * line.length,
        "--average-length {length}: must be positive and at most half the joint ({:.3} m)",
        0.5 * line.length
    );
    Ok(length)
}
