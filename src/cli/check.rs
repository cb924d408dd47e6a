//! `damfem check`: validate a scene and each of its load combinations against its geometry
//! without solving.

use super::common::Input;
use crate::mesh::Mesh;
use crate::scene::Scene;
use anyhow::{Context, Result};

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    /// Treat the warnings (curves without a role, surfaces without a material, parameters
    /// outside their known range) as errors
    #[arg(long)]
    strict: bool,
}

pub fn run(args: Args) -> Result<()> {
    let input = &args.input;
    let progress = input.progress();
    let scene = input.scene()?;
    let (mesh, _) = progress.stage(
        "mesh",
        || input.mesh(&scene),
        |m| format!("{} nodes, {} cells, P{}", m.n_points(), m.n_cells(), m.order),
    )?;
    let (problem, contact) = scene.problem(mesh.clone())?;
    let mut warnings = scene.warnings(&problem.mesh, contact.as_ref())?;
    for name in scene.combinations.keys() {
        let own = combination_warnings(&scene, name, &mesh).with_context(|| format!("combination {name}"))?;
        let new = own.into_iter().filter(|w| !warnings.contains(w)).map(|w| format!("combination {name}: {w}"));
        warnings.extend(new.collect::<Vec<_>>());
    }
    let mesh = &problem.mesh;
    progress.warn(&warnings);
    if args.strict && !warnings.is_empty() {
        anyhow::bail!("{}: --strict: {}", scene.source.display(), warnings.join("; "));
    }
    let roles = scene.roles(mesh)?;
    for (tag, name, b) in &roles {
        progress.result(&format!("curve    {name:<20} {:?}, length {:.4}", b.role, mesh.boundary_length(*tag)));
    }
    // the joint curves are those of the contact joint, in order
    for (curve, (name, joint)) in scene.joints.iter().enumerate() {
        let Some(tag) = mesh.group(1, name).map(|g| g.tag) else { continue };
        let uplift = (contact.iter().flat_map(|c| &c.uplift)).find(|up| up.curves.contains(&curve)).map_or(
            String::new(),
            |up| {
                let p = &up.diagram;
                format!(", uplift {:.4e} Pa at the heel {:?}", p.pressure(0.0, 0.0), p.line.heel)
            },
        );
        progress.result(&format!(
            "joint    {name:<20} {:?}, length {:.4}{uplift}",
            joint.law(),
            mesh.boundary_length(tag)
        ));
    }
    for g in mesh.groups.iter().filter(|g| g.dim == 2) {
        let m = problem.materials[mesh.cell_tags.iter().position(|&t| t == g.tag).unwrap_or(0)];
        progress
            .result(&format!("region   {:<20} E = {:.4e}, nu = {}, rho = {}", g.name, m.young, m.poisson, m.density));
    }
    progress.result(&format!("{}: ok", scene.source.display()));
    Ok(())
}

/// The warnings of the load combination `name` of `scene`, whose scene and problem on `mesh`
/// are built as `damfem safety` builds them.
fn combination_warnings(scene: &Scene, name: &str, mesh: &Mesh) -> Result<Vec<String>> {
    let combined = scene.combination(name)?;
    let (problem, joint) = combined.problem(mesh.clone())?;
    Ok(combined.warnings(&problem.mesh, joint.as_ref())?)
}
