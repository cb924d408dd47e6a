//! `damfem mesh`: mesh a scene's geometry and write the .msh and a .vtu of the mesh.

use super::common::{output_dir, stem, Input};
use crate::io::gmsh::Session;
use crate::io::vtu::{write_boundary_vtu, write_mesh_vtu};
use anyhow::{Context, Result};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    /// Output directory; overrides the scene's [output] directory (default: out)
    #[arg(short, long)]
    output: Option<PathBuf>,
}

pub fn run(args: Args) -> Result<()> {
    let input = &args.input;
    let progress = input.progress();
    let scene = input.scene()?;
    let dir = output_dir(&args.output, &scene)?;
    let name = stem(&scene.source);
    let msh = dir.join(format!("{name}.msh"));
    let (mesh, _) = progress.stage(
        "mesh",
        || {
            let mut session = Session::new(input.verbose)?;
            session.open_geo(&scene.geometry, input.allow_system_calls)?;
            session.set_options(&scene.mesh_options())?;
            session.generate()?;
            let mesh = session.mesh()?;
            // gmsh picks the format from the extension: write a hidden .msh, then rename
            let partial = dir.join(format!(".{name}.{}.partial.msh", std::process::id()));
            if let Err(e) = session.write(&partial) {
                std::fs::remove_file(&partial).ok();
                return Err(e.into());
            }
            std::fs::rename(&partial, &msh).with_context(|| format!("cannot write {}", msh.display()))?;
            Ok(mesh)
        },
        |m| format!("{} nodes, {} cells, P{}", m.n_points(), m.n_cells(), m.order),
    )?;
    write_mesh_vtu(&dir.join(format!("{name}_mesh.vtu")), &mesh, &[], &[])?;
    write_boundary_vtu(&dir.join(format!("{name}_boundary.vtu")), &mesh, &[], &[])?;
    println!("{}", msh.display());
    Ok(())
}
