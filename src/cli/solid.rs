//! `damfem solve` on a solid (a geometry with volumes): assemble and solve its elasticity,
//! write `<name>.vtu` (tetrahedra), `<name>_boundary.vtu` (triangles) and `summary.json`.

use super::common::{remove_earlier_outputs, stem, Progress};
use super::output::{ProblemSize, TagNames, Units, SINGULAR_MAXIMUM, SOLID_UNITS};
use crate::elasticity::solid::kernels::{principal, von_mises};
use crate::elasticity::solid::{Solid, SolidSolution, SolidSystem, Solver};
use crate::geometry::{norm3, Point3, Vector3};
use crate::io::atomic::{write_output, Provisional};
use crate::io::vtu::{write_boundary_vtu, write_mesh_vtu, Field};
use crate::mesh::Mesh;
use crate::scene::Scene;
use anyhow::Result;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What `summary.json` records of a solid's solution.
#[derive(Serialize)]
struct SolidSummary {
    units: Units,
    scene: PathBuf,
    dimension: usize,
    #[serde(flatten)]
    size: ProblemSize,
    /// "direct" (sparse Cholesky) or "iterative" (CG with algebraic multigrid).
    solver: &'static str,
    /// CG iterations of the iterative solver.
    iterations: Option<usize>,
    /// The processes that solved (the iterative solver's MPI ranks).
    processes: usize,
    max_displacement: f64,
    max_displacement_at: Point3,
    max_von_mises: f64,
    /// The centroid of the cell of `max_von_mises`, and what that value is worth.
    max_von_mises_at: Point3,
    max_von_mises_note: &'static str,
    min_principal_stress: f64,
    max_principal_stress: f64,
    /// The reaction force of each Dirichlet surface [N], by name (a node that two surfaces fix
    /// counts for the first).
    reactions: BTreeMap<String, Vector3>,
    seconds: Seconds,
    files: Vec<PathBuf>,
    tags: TagNames,
}

#[derive(Serialize)]
struct Seconds {
    mesh: f64,
    assemble: f64,
    solve: f64,
    reactions: f64,
    output: f64,
}

/// Solves the solid of `scene` on `mesh` (meshed in `mesh_seconds`) by `solver` (by default
/// the solver of its size) and writes its files to `dir`.
pub fn solve(
    scene: &Scene,
    mesh: Mesh<3>,
    solver: Option<Solver>,
    mesh_seconds: f64,
    dir: &Path,
    progress: &Progress,
) -> Result<()> {
    let solid = scene.solid(mesh)?;
    progress.warn(&scene.solid_warnings(&solid.mesh)?);
    let (system, assemble_seconds) = progress.stage(
        "assemble",
        || Ok(solid.system()?),
        |s: &SolidSystem| format!("{} unknowns, {} nonzeros", s.dofs.n_free, s.pattern.nnz()),
    )?;
    let (solution, solve_seconds) = progress.stage("solve", || Ok(solid.solve_system(&system, solver)?), describe)?;
    drop(system);
    let u = &solution.displacement;
    let sigma = solid.cell_stress(u);
    let (reactions, reactions_seconds) =
        progress.stage("reactions", || Ok(solid.reactions(u)?), |r| describe_reactions(&solid.mesh, r))?;
    let name = stem(&scene.source);
    let mut provisional = Provisional::default();
    let (files, output_seconds) = progress.stage(
        "output",
        || write_files(dir, &name, scene, &solid.mesh, u, &sigma, &mut provisional),
        |f| format!("{} files in {}", f.len(), dir.display()),
    )?;
    let seconds = Seconds {
        mesh: mesh_seconds,
        assemble: assemble_seconds,
        solve: solve_seconds,
        reactions: reactions_seconds,
        output: output_seconds,
    };
    let reactions = reactions.iter().map(|&(tag, r)| (surface_name(&solid.mesh, tag), r)).collect();
    let summary = SolidSummary::new(scene, &solid, &solution, (&sigma, reactions), files.clone(), seconds);
    let json = dir.join("summary.json");
    write_output(&json, serde_json::to_string_pretty(&summary)?.as_bytes())?;
    provisional.add(&json);
    remove_earlier_outputs(dir, &name, &[files, vec![json]].concat())?;
    provisional.keep();
    progress.say(&format!("results in {}", dir.display()));
    progress.result(&format!(
        "max |u| = {:.4e} m at ({:.3}, {:.3}, {:.3})",
        summary.max_displacement,
        summary.max_displacement_at[0],
        summary.max_displacement_at[1],
        summary.max_displacement_at[2]
    ));
    Ok(())
}

/// The name of the physical surface `tag`.
fn surface_name(mesh: &Mesh<3>, tag: i32) -> String {
    mesh.groups.iter().find(|g| g.dim == 2 && g.tag == tag).map_or_else(|| tag.to_string(), |g| g.name.clone())
}

/// "their sum (R_x, R_y, R_z) N over k surfaces".
fn describe_reactions(mesh: &Mesh<3>, reactions: &[(i32, Vector3)]) -> String {
    let total = reactions.iter().fold([0.0; 3], |s, (_, r)| [s[0] + r[0], s[1] + r[1], s[2] + r[2]]);
    let names: Vec<String> = reactions.iter().map(|&(tag, _)| surface_name(mesh, tag)).collect();
    format!("({:.4e}, {:.4e}, {:.4e}) N on {}", total[0], total[1], total[2], names.join(", "))
}

/// "sparse Cholesky" or "CG with algebraic multigrid on p processes, k iterations".
fn describe(s: &SolidSolution) -> String {
    match s.iterations {
        Some(k) if s.processes > 1 => {
            format!("CG with algebraic multigrid on {} processes, {k} iterations", s.processes)
        }
        Some(k) => format!("CG with algebraic multigrid, {k} iterations"),
        None => "sparse Cholesky".into(),
    }
}

/// The cell fields of the stresses: the six components, von Mises and the principal stresses.
fn stress_fields(sigma: &[[f64; 6]]) -> Vec<Field> {
    const NAMES: [&str; 6] = ["sigma_xx", "sigma_yy", "sigma_zz", "sigma_yz", "sigma_xz", "sigma_xy"];
    let principal: Vec<[f64; 3]> = sigma.iter().map(|&s| principal(s)).collect();
    let mut fields: Vec<Field> =
        NAMES.iter().enumerate().map(|(k, n)| Field::scalar(*n, "Pa", sigma.iter().map(|s| s[k]).collect())).collect();
    fields.push(Field::scalar("von_mises", "Pa", sigma.iter().map(|&s| von_mises(s)).collect()));
    for (k, n) in ["sigma_1", "sigma_2", "sigma_3"].iter().enumerate() {
        fields.push(Field::scalar(*n, "Pa", principal.iter().map(|p| p[k]).collect()));
    }
    fields
}

/// Writes `<name>.vtu` and, as the scene asks, `<name>_boundary.vtu`, each added to `written`.
fn write_files(
    dir: &Path,
    name: &str,
    scene: &Scene,
    mesh: &Mesh<3>,
    u: &[Vector3],
    sigma: &[[f64; 6]],
    written: &mut Provisional,
) -> Result<Vec<PathBuf>> {
    let mut files = vec![dir.join(format!("{name}.vtu"))];
    let displacement = [Field::vector3("displacement", "m", u.to_vec())];
    write_mesh_vtu(&files[0], mesh, &displacement, &stress_fields(sigma))?;
    written.add(&files[0]);
    if scene.output.boundary {
        files.push(dir.join(format!("{name}_boundary.vtu")));
        write_boundary_vtu(&files[1], mesh, &displacement, &[])?;
        written.add(&files[1]);
    }
    Ok(files)
}

impl SolidSummary {
    fn new(
        scene: &Scene,
        solid: &Solid,
        solution: &SolidSolution,
        (sigma, reactions): (&[[f64; 6]], BTreeMap<String, Vector3>),
        files: Vec<PathBuf>,
        seconds: Seconds,
    ) -> Self {
        let mesh = &solid.mesh;
        let u = &solution.displacement;
        let largest = |values: &mut dyn Iterator<Item = f64>| {
            values.enumerate().fold((0, f64::NEG_INFINITY), |best, (k, v)| if v > best.1 { (k, v) } else { best })
        };
        let (node, max_u) = largest(&mut u.iter().map(|&v| norm3(v)));
        let (peak, max_vm) = largest(&mut sigma.iter().map(|&s| von_mises(s)));
        let principal: Vec<[f64; 3]> = sigma.iter().map(|&s| principal(s)).collect();
        let v = mesh.cell_vertices(peak);
        SolidSummary {
            units: SOLID_UNITS,
            scene: scene.source.clone(),
            dimension: 3,
            size: ProblemSize {
                order: mesh.order,
                nodes: mesh.n_points(),
                cells: mesh.n_cells(),
                unknowns: 3 * mesh.n_points(),
                free_unknowns: solution.unknowns,
                matrix_nonzeros: solution.nonzeros,
            },
            solver: match solution.solver {
                Solver::Direct => "direct",
                Solver::Iterative => "iterative",
            },
            iterations: solution.iterations,
            processes: solution.processes,
            max_displacement: max_u,
            max_displacement_at: mesh.points[node],
            max_von_mises: max_vm,
            max_von_mises_at: std::array::from_fn(|r| v.iter().map(|x| x[r]).sum::<f64>() / 4.0),
            max_von_mises_note: SINGULAR_MAXIMUM,
            min_principal_stress: principal.iter().map(|p| p[2]).fold(f64::INFINITY, f64::min),
            max_principal_stress: principal.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
            reactions,
            seconds,
            files,
            tags: TagNames::new(mesh),
        }
    }
}
