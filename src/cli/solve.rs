//! `damfem solve`: mesh, assemble, solve (with Nitsche contact when the scene has Γ_C),
//! write ParaView files, `summary.json` and `history.json`.

use super::common::{output_dir, stem, Input};
use super::estimate::{self, EstimateSummary};
use super::output::write_results;
use crate::contact::{solve_contact, ContactSettings, ContactSolution, Stage};
use crate::elasticity::kernels::{principal, von_mises};
use crate::elasticity::stress::cell_mean_stress;
use crate::elasticity::{Discretisation, Problem};
use crate::estimate::{estimate_iterate, Linearisation};
use crate::io::atomic::write_output;
use crate::scene::{ProjectionKind, Scene};
use crate::solve::Cholesky;
use anyhow::Result;
use serde::Serialize;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    /// Output directory; overrides the scene's [output] directory (default: out)
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Nitsche parameter γ₀ (γ = γ₀ E / h_F); overrides contact.gamma0 (default 100)
    #[arg(long)]
    gamma0: Option<f64>,
    /// Nitsche variant θ: 1 symmetric, 0 incomplete, -1 skew-symmetric; overrides contact.theta
    #[arg(long, allow_hyphen_values = true)]
    theta: Option<f64>,
    /// Regularisation δ [Pa]; overrides contact.delta (default 1e-4 × the stress scale)
    #[arg(long)]
    delta: Option<f64>,
    /// Use the plain projection min(x, 0) with its semismooth derivative (δ = 0)
    #[arg(long)]
    semismooth: bool,
    /// Estimate the error: equilibrated stress reconstruction and the six estimators
    #[arg(long)]
    estimate: bool,
    /// Also check the equilibration of the reconstructed stress (implies --estimate)
    #[arg(long)]
    check_equilibration: bool,
}

/// What `summary.json` records of a run.
#[derive(Serialize)]
struct Summary {
    scene: PathBuf,
    order: usize,
    nodes: usize,
    cells: usize,
    unknowns: usize,
    free_unknowns: usize,
    matrix_nonzeros: usize,
    max_displacement: f64,
    max_von_mises: f64,
    min_principal_stress: f64,
    max_principal_stress: f64,
    contact: Option<ContactSummary>,
    estimate: Option<EstimateSummary>,
    seconds: Timings,
    files: Vec<PathBuf>,
}

/// What `history.json` records: the Newton steps at each δ and the estimate of the solution.
#[derive(Serialize)]
struct History<'a> {
    newton: Vec<&'a Stage>,
    estimate: Option<&'a EstimateSummary>,
}

/// Contact part of the summary.
#[derive(Serialize)]
struct ContactSummary {
    faces: usize,
    gamma0: f64,
    theta: f64,
    delta: f64,
    stress_scale: f64,
    /// Length of the zone where P_γ(u_h) < 0, and its bounding box [[x, y], [x, y]].
    contact_length: f64,
    contact_extent: Option<[[f64; 2]; 2]>,
    newton_steps: usize,
    /// Newton steps at each δ of the continuation path.
    stages: Vec<(f64, usize)>,
    max_pressure: f64,
    max_regularisation_error: f64,
}

#[derive(Serialize, Default)]
struct Timings {
    mesh: f64,
    assemble: f64,
    solve: f64,
    estimate: Option<f64>,
    output: f64,
}

pub fn run(args: Args) -> Result<()> {
    let input = &args.input;
    let progress = input.progress();
    let mut scene = input.scene()?;
    override_contact(&args, &mut scene)?;
    let dir = output_dir(&args.output, &scene)?;
    let mut seconds = Timings::default();
    let (mesh, t) = progress.stage(
        "mesh",
        || input.mesh(&scene),
        |m| format!("{} nodes, {} cells, P{}", m.n_points(), m.n_cells(), m.order),
    )?;
    seconds.mesh = t;
    let problem = scene.problem(mesh)?;
    let tags = scene.contact_tags(&problem.mesh)?;
    let (disc, t) = progress.stage(
        "assemble",
        || Ok(problem.discretise()),
        |d| format!("{} unknowns, {} nonzeros", d.dofs.n_free, d.pattern.nnz()),
    )?;
    seconds.assemble = t;
    let (solution, t) = if tags.is_empty() {
        progress.stage("solve", || Ok((linear_solve(&problem, &disc)?, None)), |_| "sparse Cholesky".into())?
    } else {
        let settings = scene.contact_settings(&problem, &disc.topology);
        progress.stage(
            "solve",
            || Ok(solve_contact(&problem, &disc, &tags, &settings).map(|s| (s.x.clone(), Some((s, settings))))?),
            |(_, c)| match c {
                Some((s, st)) => format!(
                    "Newton, {} steps, δ = {:.3e}, contact length {:.4}",
                    s.newton_steps(),
                    st.delta,
                    s.contact_length()
                ),
                None => String::new(),
            },
        )?
    };
    seconds.solve = t;
    let (x, contact) = solution;
    let estimate = if args.estimate || args.check_equilibration {
        let state =
            contact.as_ref().map(|(c, s)| Linearisation { nitsche: &c.nitsche, x_prev: &c.x_prev, delta: s.delta });
        let (e, t) = progress.stage(
            "estimate",
            || Ok(estimate_iterate(&problem, &disc, &x, state, args.check_equilibration)?),
            |e| {
                let checks = e
                    .equilibration
                    .map_or(String::new(), |q| format!(", equilibrated to {:.1e}", q.worst(problem.mesh.order)));
                format!("eta = {:.4e}{checks}", e.estimators.global().tot)
            },
        )?;
        seconds.estimate = Some(t);
        Some(e)
    } else {
        None
    };
    let u = problem.displacement(&disc, &x);
    let sigma = cell_mean_stress(&problem, &u);
    let name = stem(&scene.source);
    let (files, t) = progress.stage(
        "output",
        || {
            let faces = contact.as_ref().map(|(c, _)| (&c.nitsche, &c.faces[..]));
            write_results(&dir, &name, &scene, &problem, &u, &sigma, faces, estimate.as_ref())
        },
        |f| format!("{} files in {}", f.len(), dir.display()),
    )?;
    seconds.output = t;
    let mut summary = summary(&scene, &problem, &disc, &u, &sigma, contact.as_ref(), seconds, files);
    summary.estimate = estimate.as_ref().map(estimate::summary);
    write_output(&dir.join("summary.json"), serde_json::to_string_pretty(&summary)?.as_bytes())?;
    if contact.is_some() || summary.estimate.is_some() {
        let history = History {
            newton: contact.as_ref().map(|(c, _)| c.stages.iter().collect()).unwrap_or_default(),
            estimate: summary.estimate.as_ref(),
        };
        write_output(&dir.join("history.json"), serde_json::to_string_pretty(&history)?.as_bytes())?;
    }
    progress.say(&format!(
        "max |u| = {:.4e} m, max von Mises = {:.4e} Pa; results in {}",
        summary.max_displacement,
        summary.max_von_mises,
        dir.display()
    ));
    Ok(())
}

fn linear_solve(problem: &Problem, disc: &Discretisation) -> Result<Vec<f64>> {
    let system = problem.assemble(disc);
    Ok(Cholesky::analyse(&disc.pattern)?.solve(&disc.pattern, &system.values, &system.rhs)?)
}

/// The scene's `[contact]` table with the command-line overrides.
fn override_contact(args: &Args, scene: &mut Scene) -> Result<()> {
    let c = &mut scene.contact;
    c.gamma0 = args.gamma0.unwrap_or(c.gamma0);
    c.theta = args.theta.unwrap_or(c.theta);
    c.delta = args.delta.or(c.delta);
    if args.semismooth {
        c.projection = ProjectionKind::Semismooth;
    }
    Ok(scene.validate()?)
}

#[allow(clippy::too_many_arguments)]
fn summary(
    scene: &Scene,
    problem: &Problem,
    disc: &Discretisation,
    u: &[[f64; 2]],
    sigma: &[[f64; 4]],
    contact: Option<&(ContactSolution, ContactSettings)>,
    seconds: Timings,
    files: Vec<PathBuf>,
) -> Summary {
    let principal_stresses: Vec<[f64; 2]> = sigma.iter().map(|&s| principal(s)).collect();
    Summary {
        scene: scene.source.clone(),
        order: problem.mesh.order,
        nodes: problem.mesh.n_points(),
        cells: problem.mesh.n_cells(),
        unknowns: problem.n_dofs(),
        free_unknowns: disc.dofs.n_free,
        matrix_nonzeros: disc.pattern.nnz(),
        max_displacement: u.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max),
        max_von_mises: sigma.iter().map(|&s| von_mises(s)).fold(0.0, f64::max),
        min_principal_stress: principal_stresses.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
        max_principal_stress: principal_stresses.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
        contact: contact.map(|(c, settings)| contact_summary(problem, disc, c, settings)),
        estimate: None,
        seconds,
        files,
    }
}

fn contact_summary(
    problem: &Problem,
    disc: &Discretisation,
    c: &ContactSolution,
    s: &ContactSettings,
) -> ContactSummary {
    let mesh = &problem.mesh;
    let in_contact = c.nitsche.faces.iter().zip(&c.faces).filter(|(_, state)| state.contact_length > 0.0);
    let extent = in_contact.flat_map(|(face, _)| mesh.facet(face.facet)[..2].iter().map(|&n| mesh.points[n])).fold(
        None,
        |b: Option<[[f64; 2]; 2]>, p| {
            let [lo, hi] = b.unwrap_or([p, p]);
            Some([[lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])]])
        },
    );
    ContactSummary {
        faces: c.faces.len(),
        gamma0: s.parameters.gamma0,
        theta: s.parameters.theta,
        delta: s.delta,
        stress_scale: problem.stress_scale(&disc.topology),
        contact_length: c.contact_length(),
        contact_extent: extent,
        newton_steps: c.newton_steps(),
        stages: c.stages.iter().map(|st| (st.delta, st.report.iterations.len())).collect(),
        max_pressure: c.faces.iter().map(|f| f.pressure).fold(0.0, f64::max),
        max_regularisation_error: c.faces.iter().map(|f| f.regularisation_error).fold(0.0, f64::max),
    }
}
