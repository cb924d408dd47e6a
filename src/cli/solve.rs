//! `damfem solve`: mesh, assemble, solve (with Nitsche contact when the scene has Γ_C),
//! write ParaView files, `summary.json` and `history.json`.

use super::common::{remove_earlier_outputs, stem, Input, Output, Progress, SolverFailed};
use super::output::{write_results, EstimateSummary, Results, Summary, Units, UNITS};
use super::settings::{self, Given, Setting};
use super::solid;
use crate::contact::{ContactError, ContactJoint, ContactSolution, Continuation, Solution, Stage};
use crate::elasticity::solid::Solver;
use crate::elasticity::stress::cell_mean_stress;
use crate::elasticity::{Discretisation, Problem};
use crate::estimate::reference::{effectivity, Effectivity};
use crate::estimate::{estimate_displacement, Estimate};
use crate::io::atomic::{write_output, Provisional};
use crate::io::gmsh::AnyMesh;
use crate::safety::strength::{reduce_strength, StrengthReduction, STRENGTH_TOLERANCE};
use crate::scene::{ProjectionKind, Scene};
use crate::solve::{diverged, NewtonError};
use anyhow::Result;
use serde::Serialize;
use std::path::Path;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    #[command(flatten)]
    output: Output,
    /// Nitsche parameter γ₀ (γ = γ₀ E / h_F); overrides contact.gamma0 (default 10)
    #[arg(long, allow_negative_numbers = true)]
    gamma0: Option<f64>,
    /// Nitsche variant θ: 1 symmetric, 0 incomplete, -1 skew-symmetric; overrides contact.theta
    #[arg(long, allow_hyphen_values = true)]
    theta: Option<f64>,
    /// Regularisation δ [Pa]; overrides contact.delta (default 1e-4 × the stress scale)
    #[arg(long, allow_negative_numbers = true)]
    delta: Option<f64>,
    /// Coulomb friction coefficient F = tan φ on Γ_C; overrides contact.friction (default 0)
    #[arg(long, allow_negative_numbers = true)]
    friction: Option<f64>,
    /// Cohesion c [Pa] of a Mohr–Coulomb joint (with --friction); overrides contact.cohesion
    #[arg(long, allow_negative_numbers = true)]
    cohesion: Option<f64>,
    /// Tresca threshold s [Pa]; overrides contact.threshold
    #[arg(long, allow_negative_numbers = true)]
    threshold: Option<f64>,
    /// Use the plain projection min(x, 0) with its semismooth derivative (δ = 0)
    #[arg(long)]
    semismooth: bool,
    /// Also find the sliding safety factor FS_SR by strength reduction to 0.2 %: F, c and s of
    /// every joint divided by k, so with several joints FS_SR is the weakest plane's (for one
    /// plane: `damfem safety` with `[safety] joint`)
    #[arg(long)]
    strength_reduction: bool,
    /// Estimate the error: equilibrated stress reconstruction and the six estimators
    #[arg(long)]
    estimate: bool,
    /// Estimate and print each equilibration check of the reconstructed stress (the checks always
    /// run with --estimate, and an estimate that fails one is refused)
    #[arg(long)]
    check_equilibration: bool,
    /// Linear solver of a solid: direct (sparse Cholesky) or iterative (CG with PETSc's
    /// algebraic multigrid, on one MPI process per thread: RAYON_NUM_THREADS, by default the
    /// cores); default by size, iterative from 100 000 unknowns. A plane section is solved
    /// directly
    #[arg(long, value_enum)]
    solver: Option<SolverArg>,
    /// Also compute a sharp lower bound of the error's dual norm and I_eff = eta_tot / bound,
    /// an upper bound of the true effectivity index (implies --estimate; costly)
    #[arg(long)]
    effectivity: bool,
}

/// `--solver`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum SolverArg {
    Direct,
    Iterative,
}

/// What `summary.json` records of `solve` beside the solution.
#[derive(Serialize)]
struct SolveSummary {
    /// With --strength-reduction: the largest k that held and the smallest that did not.
    strength_reduction: Option<StrengthReduction>,
    effectivity: Option<Effectivity>,
    seconds: Timings,
}

/// What `history.json` records: the Newton steps at each δ and the estimate of the solution.
#[derive(Serialize)]
struct History<'a> {
    units: Units,
    newton: Vec<&'a Stage>,
    estimate: Option<&'a EstimateSummary>,
}

#[derive(Serialize, Default)]
struct Timings {
    mesh: f64,
    assemble: f64,
    solve: f64,
    estimate: Option<f64>,
    effectivity: Option<f64>,
    output: f64,
}

pub fn run(args: Args) -> Result<()> {
    let input = &args.input;
    let progress = input.progress();
    let mut seconds = Timings::default();
    // 1. Scene and mesh
    let mut scene = input.scene()?;
    let given = override_contact(&args, &mut scene)?;
    if args.strength_reduction && !scene.has_friction() {
        anyhow::bail!("--strength-reduction needs a frictional joint: give --friction, --cohesion or --threshold");
    }
    let scene = input.before_earthquake(scene)?;
    let dir = args.output.dir(&scene)?;
    let (mesh, t) = progress.stage("mesh", || input.model(&scene), AnyMesh::describe)?;
    seconds.mesh = t;
    let mesh = match mesh {
        AnyMesh::Plane(mesh) => mesh,
        AnyMesh::Solid(mesh) => {
            if let Some(flag) = plane_only_flag(&args) {
                anyhow::bail!("{flag}: {} is a solid (it has volumes), which has no contact or error estimate yet; leave the flag out", scene.geometry.display());
            }
            let solver = args.solver.map(|s| match s {
                SolverArg::Direct => Solver::Direct,
                SolverArg::Iterative => Solver::Iterative,
            });
            return solid::solve(&scene, mesh, solver, t, &dir, &progress);
        }
    };
    if args.solver == Some(SolverArg::Iterative) {
        anyhow::bail!(
            "--solver iterative: {} is a plane section, which damfem solves by sparse Cholesky; leave the flag out",
            scene.geometry.display()
        );
    }
    // 2. Problem: the elasticity problem, its contact joint, dofs and pattern
    let (problem, joint) = match scene.problem(mesh) {
        Ok(problem) => problem,
        // an error, blamed on the flag of a key it names
        Err(e) => return input.in_combination(given.blame(Err(e))),
    };
    progress.warn(&scene.warnings(&problem.mesh, joint.as_ref())?);
    let (disc, t) = progress.stage(
        "assemble",
        || Ok(problem.discretise()),
        |d| format!("{} unknowns, {} nonzeros", d.dofs.n_free, d.pattern.nnz()),
    )?;
    seconds.assemble = t;
    // 3. Solve: one Cholesky solve, or Newton along the δ path with contact
    let mut continuation = scene.continuation(&problem, &disc.topology);
    continuation.newton.trace = input.newton_trace();
    if let Some(path) = continuation.path.as_mut() {
        path.trace = input.path_trace();
    }
    let (solution, t) = progress
        .stage("solve", || solve(&scene, input, &problem, &disc, joint.as_ref(), &continuation), describe_solution)
        .map_err(|e| match e.downcast_ref::<ContactError>() {
            Some(ContactError::Newton(newton)) => newton_failure(&scene, &continuation, newton, &dir),
            _ => e,
        })?;
    seconds.solve = t;
    // strength reduction from the solution at k = 1 just found
    let strength = match joint.as_ref().zip(solution.contact()).filter(|_| args.strength_reduction) {
        Some((joint, start)) => Some(strength_stage(&progress, &problem, &disc, joint, start, &continuation)?),
        None => None,
    };
    // 4. Estimate
    let estimate = estimate_stage(&args, &progress, &problem, &disc, &solution, &mut seconds)?;
    let effectivity = match estimate.as_ref().filter(|_| args.effectivity) {
        Some(e) => {
            let (reference, t) = effectivity_stage(&progress, &problem, &disc, joint.as_ref(), &solution, e)?;
            seconds.effectivity = Some(t);
            Some(reference)
        }
        None => None,
    };
    // 5. Write the ParaView files, the summary and the history
    let u = problem.displacement(&disc, solution.x());
    let sigma = cell_mean_stress(&problem, &u);
    let results =
        Results { problem: &problem, u: &u, sigma: &sigma, contact: solution.contact(), estimate: estimate.as_ref() };
    let name = stem(&scene.source);
    // every file of the result is removed again if a later one fails
    let mut provisional = Provisional::default();
    let (files, t) = progress.stage(
        "output",
        || write_results(&dir, &name, &scene, &results, &mut provisional),
        |f| format!("{} files in {}", f.len(), dir.display()),
    )?;
    seconds.output = t;
    let line = scene.joint_line(&problem);
    let solve = SolveSummary { strength_reduction: strength.map(|(s, _)| s), effectivity, seconds };
    let mut written = [files.clone(), vec![dir.join("summary.json")]].concat();
    let summary = Summary::new(&scene, &disc, &results, line, files, solve);
    write_output(&dir.join("summary.json"), serde_json::to_string_pretty(&summary)?.as_bytes())?;
    provisional.add(&dir.join("summary.json"));
    if solution.contact().is_some() || summary.estimate.is_some() {
        let history = History {
            units: UNITS,
            newton: solution.contact().map(|c| c.stages.iter().collect()).unwrap_or_default(),
            estimate: summary.estimate.as_ref(),
        };
        write_output(&dir.join("history.json"), serde_json::to_string_pretty(&history)?.as_bytes())?;
        provisional.add(&dir.join("history.json"));
        written.push(dir.join("history.json"));
    }
    remove_earlier_outputs(&dir, &name, &written)?;
    provisional.keep();
    progress.say(&format!("results in {}", dir.display()));
    for line in summary.headline() {
        progress.result(&line);
    }
    Ok(())
}

/// The first flag of contact or of the estimate given, which a solid has no use for yet.
fn plane_only_flag(args: &Args) -> Option<&'static str> {
    let values = [args.gamma0, args.theta, args.delta, args.friction, args.cohesion, args.threshold];
    let names = ["--gamma0", "--theta", "--delta", "--friction", "--cohesion", "--threshold"];
    let switches = [
        (args.semismooth, "--semismooth"),
        (args.strength_reduction, "--strength-reduction"),
        (args.estimate, "--estimate"),
        (args.check_equilibration, "--check-equilibration"),
        (args.effectivity, "--effectivity"),
    ];
    (names.iter().zip(values).find(|(_, v)| v.is_some()).map(|(n, _)| *n))
        .or_else(|| switches.iter().find(|s| s.0).map(|s| s.1))
}

/// The strength reduction from the contact solution `start` at k = 1, with its wall time.
fn strength_stage(
    progress: &Progress,
    problem: &Problem,
    disc: &Discretisation,
    joint: &ContactJoint,
    start: &ContactSolution,
    continuation: &Continuation,
) -> Result<(StrengthReduction, f64)> {
    progress.stage(
        "strength",
        || {
            let curves = joint.every_curve();
            Ok(reduce_strength(problem, disc, joint, &curves, start, &continuation.newton, STRENGTH_TOLERANCE)?)
        },
        |s: &StrengthReduction| format!("FS_SR in [{:.4}, {:.4}] after {} solves", s.held, s.failed, s.solves),
    )
}

/// The estimate of `solution` where a flag asks for it, its wall time in `seconds`; with
/// `--check-equilibration`, its checks printed.
fn estimate_stage(
    args: &Args,
    progress: &Progress,
    problem: &Problem,
    disc: &Discretisation,
    solution: &Solution,
    seconds: &mut Timings,
) -> Result<Option<Estimate>> {
    if !(args.estimate || args.check_equilibration || args.effectivity) {
        return Ok(None);
    }
    let (e, t) = progress.stage(
        "estimate",
        || estimate(problem, disc, solution),
        |e| describe_estimate(e, problem.mesh.order),
    )?;
    seconds.estimate = Some(t);
    if args.check_equilibration {
        eprintln!("{}", e.equilibration.table(problem.mesh.order));
    }
    Ok(Some(e))
}

/// I_eff of the estimate `e` against the sharp reference, with its wall time.
fn effectivity_stage(
    progress: &Progress,
    problem: &Problem,
    disc: &Discretisation,
    joint: Option<&ContactJoint>,
    solution: &Solution,
    e: &Estimate,
) -> Result<(Effectivity, f64)> {
    progress.stage(
        "effectivity",
        || {
            let u = problem.displacement(disc, solution.x());
            let solved = joint.zip(solution.contact()).map(|(j, c)| j.as_solved(c));
            Ok(effectivity(problem, &u, solved.as_ref(), e.estimators.global().tot)?)
        },
        |r| {
            let agree = if r.converged { "agree within 2 %" } else { "do NOT agree within 2 % (size limit)" };
            format!(
                "I_eff = {:.3} (eta_tot {:.4e}, reference {:.4e}; the last two of {} references {agree})",
                r.i_eff,
                r.eta_tot,
                r.reference,
                r.references.len()
            )
        },
    )
}

/// What `history.json` records of a Newton run that did not converge: the error and the
/// relative residuals of the failing stage.
#[derive(Serialize)]
struct FailedHistory {
    units: Units,
    error: String,
    /// The target δ \[Pa\] of the continuation path.
    delta_target: f64,
    relative_residuals: Vec<f64>,
}

/// The error of a Newton run that did not converge: names the scene and the parameters that
/// most often cause it, and writes what was done to `history.json`.
fn newton_failure(scene: &Scene, continuation: &Continuation, error: &NewtonError, dir: &Path) -> anyhow::Error {
    let c = &scene.contact;
    let residuals = match error {
        NewtonError::NotConverged { history, scale } => history.iter().map(|it| it.residual / scale).collect(),
        _ => Vec::new(),
    };
    let mut causes = Vec::new();
    let grew = matches!(error, NewtonError::NotConverged { history, .. } if diverged(history));
    let falling = residuals.len() >= 4 && residuals[residuals.len() - 1] < 0.5 * residuals[residuals.len() / 2];
    if residuals.len() >= c.max_iter && falling && !grew {
        causes.push(format!("contact.max_iter = {} may be too small (the residual still falls)", c.max_iter));
    }
    if c.theta != -1.0 && c.gamma0 < 10.0 {
        causes.push(format!(
            "contact.gamma0 = {} is small for theta = {} (use at least 10, or theta = -1)",
            c.gamma0, c.theta
        ));
    }
    if continuation.delta == 0.0 && continuation.delta_start == 0.0 {
        causes.push("delta = 0 without a continuation path (set contact.delta_start)".to_string());
    }
    if causes.is_empty() {
        causes.push("the Nitsche parameters or the regularisation (contact.gamma0, theta, delta)".to_string());
    }
    let used = format!("gamma0 = {}, theta = {}, delta = {:.3e} Pa", c.gamma0, c.theta, continuation.delta);
    let history = FailedHistory {
        units: UNITS,
        error: error.to_string(),
        delta_target: continuation.delta,
        relative_residuals: residuals,
    };
    let path = dir.join("history.json");
    let kept = serde_json::to_string_pretty(&history).map_err(anyhow::Error::from).and_then(|text| {
        write_output(&path, text.as_bytes())?;
        remove_earlier_outputs(dir, &stem(&scene.source), std::slice::from_ref(&path))?;
        Ok(format!("\nthe residuals are in {}", path.display()))
    });
    anyhow::Error::new(SolverFailed(format!(
        "{}: {error}\nlikely causes: {} (with {used}){}",
        scene.source.display(),
        causes.join("; "),
        kept.unwrap_or_default()
    )))
}

/// One Cholesky solve without a joint; with one, Newton to the δ of `continuation`
/// ([`Scene::solve_contact`]).
fn solve(
    scene: &Scene,
    input: &Input,
    problem: &Problem,
    disc: &Discretisation,
    joint: Option<&ContactJoint>,
    continuation: &Continuation,
) -> Result<Solution> {
    Ok(match joint {
        None => Solution::Linear(problem.solve_refined(disc)?),
        Some(joint) => Solution::Contact(Box::new(scene.solve_contact(
            problem,
            disc,
            joint,
            continuation,
            input.allow_system_calls,
        )?)),
    })
}

fn describe_solution(solution: &Solution) -> String {
    match solution.contact() {
        None => "sparse Cholesky".into(),
        Some(c) => {
            let coarse: Vec<String> = c
                .coarse
                .iter()
                .map(|s| format!("{} on {} P{} unknowns", s.newton_steps, s.unknowns, s.order))
                .collect();
            let started = if coarse.is_empty() { String::new() } else { format!(" (after {})", coarse.join(", ")) };
            format!(
                "Newton, {} steps{started}, δ = {:.3e}, contact length {:.4}",
                c.newton_steps(),
                c.smoothing.delta,
                c.contact_length()
            )
        }
    }
}

/// The estimate of the solution.
fn estimate(problem: &Problem, disc: &Discretisation, solution: &Solution) -> Result<Estimate> {
    let state = solution.contact().map(|c| c.linearisation(problem, disc));
    Ok(estimate_displacement(problem, &disc.topology, &solution.displacement(problem, disc), state.as_ref())?)
}

fn describe_estimate(e: &Estimate, order: usize) -> String {
    format!("eta = {:.4e}, equilibrated to {:.1e}", e.estimators.global().tot, e.equilibration.worst(order))
}

/// The flags of `solve` that override `[contact]` keys.
fn contact_settings(args: &Args) -> Vec<Setting<'static>> {
    vec![
        Setting::value("--gamma0", "contact.gamma0", args.gamma0, |s, v| s.contact.gamma0 = v),
        Setting::value("--theta", "contact.theta", args.theta, |s, v| s.contact.theta = v),
        Setting::value("--delta", "contact.delta", args.delta, |s, v| s.contact.delta = Some(v)),
        Setting::value("--friction", "contact.friction", args.friction, |s, v| s.contact.friction = v),
        Setting::value("--cohesion", "contact.cohesion", args.cohesion, |s, v| s.contact.cohesion = v),
        Setting::value("--threshold", "contact.threshold", args.threshold, |s, v| s.contact.threshold = Some(v)),
        Setting::switch("--semismooth", "contact.projection", args.semismooth, |s| {
            s.contact.projection = ProjectionKind::Semismooth
        }),
    ]
}

/// The flags of [`contact_settings`] that a joint between two bodies takes from its own table.
const RIGID_ONLY: [&str; 5] = ["--gamma0", "--theta", "--friction", "--cohesion", "--threshold"];

/// The scene with the flags' `[contact]` keys, checked; returns the flags given.
fn override_contact(args: &Args, scene: &mut Scene) -> Result<Given> {
    let given = settings::write(scene, contact_settings(args));
    if let (Some(joint), Some(flag)) = (scene.joints.keys().next(), given.among(&RIGID_ONLY).next()) {
        anyhow::bail!(
            "{flag} sets a [contact] key, which applies to curves of role contact only; set the joint's key in \
             [joints.{joint}] of {}",
            scene.source.display()
        );
    }
    given.validate(scene)?;
    if args.estimate || args.check_equilibration || args.effectivity {
        let estimate = "the error estimate of --estimate, --check-equilibration and --effectivity";
        given.blame(scene.check_estimable(estimate))?;
    }
    Ok(given)
}
