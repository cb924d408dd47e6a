//! `damfem solve`: mesh, assemble, solve, write ParaView files and a JSON summary.

use super::common::{output_dir, stem, Input};
use crate::elasticity::kernels::{principal, von_mises};
use crate::elasticity::stress::cell_mean_stress;
use crate::io::atomic::write_output;
use crate::io::vtu::{write_boundary_vtu, write_mesh_vtu, Field};
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
    seconds: Timings,
    files: Vec<PathBuf>,
}

#[derive(Serialize, Default)]
struct Timings {
    mesh: f64,
    assemble: f64,
    solve: f64,
    output: f64,
}

pub fn run(args: Args) -> Result<()> {
    let input = &args.input;
    let progress = input.progress();
    let scene = input.scene()?;
    let dir = output_dir(&args.output, &scene)?;
    let mut seconds = Timings::default();
    let (mesh, t) = progress.stage(
        "mesh",
        || input.mesh(&scene),
        |m| {
            format!(
                "{} nodes, {} cells, P{}",
                m.n_points(),
                m.n_cells(),
                m.order
            )
        },
    )?;
    seconds.mesh = t;
    let problem = scene.problem(mesh)?;
    let ((disc, system), t) = progress.stage(
        "assemble",
        || {
            let disc = problem.discretise();
            let system = problem.assemble(&disc);
            Ok((disc, system))
        },
        |(d, _)| format!("{} unknowns, {} nonzeros", d.dofs.n_free, d.pattern.nnz()),
    )?;
    seconds.assemble = t;
    let (x, t) = progress.stage(
        "solve",
        || {
            Ok(Cholesky::analyse(&disc.pattern)?.solve(
                &disc.pattern,
                &system.values,
                &system.rhs,
            )?)
        },
        |_| "sparse Cholesky".into(),
    )?;
    seconds.solve = t;
    let u = problem.displacement(&disc, &x);
    let sigma = cell_mean_stress(&problem, &u);
    let name = stem(&scene.source);
    let (files, t) = progress.stage(
        "output",
        || {
            let mut files = vec![dir.join(format!("{name}.vtu"))];
            write_mesh_vtu(
                &files[0],
                &problem.mesh,
                &[Field::vector("displacement", u.clone())],
                &stress_fields(&sigma),
            )?;
            if scene.output.boundary {
                files.push(dir.join(format!("{name}_boundary.vtu")));
                write_boundary_vtu(&files[1], &problem.mesh, &[], &[])?;
            }
            Ok(files)
        },
        |f| format!("{} files in {}", f.len() + 1, dir.display()),
    )?;
    seconds.output = t;
    let principal_stresses: Vec<[f64; 2]> = sigma.iter().map(|&s| principal(s)).collect();
    let summary = Summary {
        scene: scene.source.clone(),
        order: problem.mesh.order,
        nodes: problem.mesh.n_points(),
        cells: problem.mesh.n_cells(),
        unknowns: problem.n_dofs(),
        free_unknowns: disc.dofs.n_free,
        matrix_nonzeros: disc.pattern.nnz(),
        max_displacement: u.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max),
        max_von_mises: sigma.iter().map(|&s| von_mises(s)).fold(0.0, f64::max),
        min_principal_stress: principal_stresses
            .iter()
            .map(|p| p[1])
            .fold(f64::INFINITY, f64::min),
        max_principal_stress: principal_stresses
            .iter()
            .map(|p| p[0])
            .fold(f64::NEG_INFINITY, f64::max),
        seconds,
        files,
    };
    write_output(
        &dir.join("summary.json"),
        serde_json::to_string_pretty(&summary)?.as_bytes(),
    )?;
    progress.say(&format!(
        "max |u| = {:.4e} m, max von Mises = {:.4e} Pa; results in {}",
        summary.max_displacement,
        summary.max_von_mises,
        dir.display()
    ));
    Ok(())
}

/// Cell fields: σ components, von Mises and principal stresses.
fn stress_fields(sigma: &[[f64; 4]]) -> Vec<Field> {
    let component = |k: usize| sigma.iter().map(|s| s[k]).collect();
    let principal: Vec<[f64; 2]> = sigma.iter().map(|&s| principal(s)).collect();
    vec![
        Field::scalar("sigma_xx", component(0)),
        Field::scalar("sigma_yy", component(1)),
        Field::scalar("sigma_xy", component(2)),
        Field::scalar("sigma_zz", component(3)),
        Field::scalar("von_mises", sigma.iter().map(|&s| von_mises(s)).collect()),
        Field::scalar("sigma_1", principal.iter().map(|p| p[0]).collect()),
        Field::scalar("sigma_2", principal.iter().map(|p| p[1]).collect()),
    ]
}
