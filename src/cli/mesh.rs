//! `damfem mesh`: mesh a scene's geometry and write the .msh and a .vtu of the mesh.

use super::common::{remove_earlier_outputs, stem, Input, Output};
use crate::io::atomic::Provisional;
use crate::io::gmsh::{self, AnyMesh};
use crate::io::vtu::{write_boundary_vtu, write_mesh_vtu};
use crate::mesh::Mesh;
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    #[command(flatten)]
    output: Output,
}

pub fn run(args: Args) -> Result<()> {
    let input = &args.input;
    let progress = input.progress();
    if let Some(name) = &input.combination {
        anyhow::bail!(
            "--combination {name}: a load combination changes loads, not the mesh, so `damfem mesh` has no use for it; \
             leave the flag out"
        );
    }
    let scene = input.scene()?;
    let dir = args.output.dir(&scene)?;
    let name = stem(&scene.source);
    let msh = dir.join(format!("{name}.msh"));
    let (mesh, _) = progress.stage(
        "mesh",
        || {
            Ok(gmsh::save_geo_mesh(
                &scene.geometry,
                &scene.mesh_options(),
                &msh,
                input.verbose,
                input.allow_system_calls,
            )?)
        },
        AnyMesh::describe,
    )?;
    // the .msh and the .vtu files are removed again if a later one fails
    let mut provisional = Provisional::default();
    provisional.add(&msh);
    let mut written = vec![msh.clone(), dir.join(format!("{name}_mesh.vtu"))];
    if scene.output.boundary {
        written.push(dir.join(format!("{name}_boundary.vtu")));
    }
    match &mesh {
        AnyMesh::Plane(mesh) => write_vtus(mesh, &written[1..], &mut provisional)?,
        AnyMesh::Solid(mesh) => write_vtus(mesh, &written[1..], &mut provisional)?,
    }
    remove_earlier_outputs(&dir, &name, &written)?;
    provisional.keep();
    progress.result(&msh.display().to_string());
    Ok(())
}

/// The mesh's cells to `files[0]` and, if named, its boundary facets to `files[1]`.
fn write_vtus<const D: usize>(mesh: &Mesh<D>, files: &[PathBuf], provisional: &mut Provisional) -> Result<()> {
    write_mesh_vtu(&files[0], mesh, &[], &[])?;
    provisional.add(&files[0]);
    if let Some(boundary) = files.get(1) {
        write_boundary_vtu(boundary, mesh, &[], &[])?;
        provisional.add(boundary);
    }
    Ok(())
}
