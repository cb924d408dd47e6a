//! ParaView files and summaries of one solution, shared by `solve` and `adapt`.

use crate::contact::{ContactSolution, FaceState};
use crate::elasticity::kernels::{principal, von_mises};
use crate::elasticity::Problem;
use crate::estimate::estimators::{GlobalEstimators, NAMES};
use crate::estimate::Estimate;
use crate::io::vtu::{write_boundary_vtu, write_mesh_vtu, Field};
use crate::mesh::Mesh;
use crate::scene::{OutputSection, Scene};
use anyhow::Result;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Names of the reconstructed stress components.
const SIGMA_H: [&str; 4] = ["sigma_h_xx", "sigma_h_xy", "sigma_h_yx", "sigma_h_yy"];

/// One solution as the output files need it.
pub struct Results<'a> {
    pub problem: &'a Problem,
    /// Nodal displacements.
    pub u: &'a [[f64; 2]],
    /// Cell means of σ(u_h) [xx, yy, xy, zz].
    pub sigma: &'a [[f64; 4]],
    pub contact: Option<&'a ContactSolution>,
    pub estimate: Option<&'a Estimate>,
}

/// What `summary.json` records of an estimate.
#[derive(Serialize)]
pub struct EstimateSummary {
    pub global: GlobalEstimators,
    pub equilibration: serde_json::Value,
}

impl EstimateSummary {
    /// The global estimators and checks of `e` on a mesh of degree `order`; the weak symmetry
    /// is tested against P_{p−1} rotations, so for P1 it is "not applicable".
    pub fn new(e: &Estimate, order: usize) -> Self {
        let mut equilibration = serde_json::json!(e.equilibration);
        if order < 2 {
            equilibration["weak_symmetry"] = NOT_APPLICABLE.into();
        }
        EstimateSummary { global: e.estimators.global(), equilibration }
    }
}

/// The units of the numbers in the JSON files: SI, per metre of dam (plane strain).
#[derive(Serialize, Clone, Copy)]
pub struct Units {
    length: &'static str,
    stress: &'static str,
    force: &'static str,
    residual: &'static str,
    estimator: &'static str,
    time: &'static str,
}

/// The units every JSON file states.
pub const UNITS: Units = Units {
    length: "m (coordinates, lengths, displacements, mesh sizes)",
    stress: "Pa (stresses, pressures, delta, stress_scale)",
    force: "N/m (forces per metre of dam)",
    residual: "N/m (Newton residuals; relative residuals have no unit)",
    estimator: "Pa m (eta_* and stress norms: L2 norms of stresses over the section)",
    time: "s",
};

/// The physical names of the numeric tags of the VTU files: `material` (cells) and
/// `physical_tag` (boundary facets).
#[derive(Serialize)]
pub struct TagNames {
    material: BTreeMap<i32, String>,
    physical_tag: BTreeMap<i32, String>,
}

impl TagNames {
    pub fn new(mesh: &Mesh) -> Self {
        let names = |dim| mesh.groups.iter().filter(|g| g.dim == dim).map(|g| (g.tag, g.name.clone())).collect();
        TagNames { material: names(2), physical_tag: names(1) }
    }
}

/// What `summary.json` says of the weak-symmetry check on P1 meshes.
const NOT_APPLICABLE: &str = "not applicable (P1)";

/// Writes `<name>.vtu`, and as the scene asks `<name>_boundary.vtu` and `<name>_dg.vtu`;
/// returns their paths.
pub fn write_results(dir: &Path, name: &str, scene: &Scene, results: &Results) -> Result<Vec<PathBuf>> {
    let Results { problem, u, sigma, contact, estimate } = *results;
    let mut files = vec![dir.join(format!("{name}.vtu"))];
    let mut cells = stress_fields(sigma);
    if let Some(e) = estimate {
        cells.extend(estimate_fields(e, &scene.output));
        if scene.output.reconstruction {
            let dg = dir.join(format!("{name}_dg.vtu"));
            let fields: Vec<Field> =
                SIGMA_H.iter().zip(e.reconstruction.vertex_values()).map(|(n, v)| Field::scalar(*n, v)).collect();
            write_mesh_vtu(&dg, &problem.mesh.discontinuous(), &fields, &[])?;
            files.push(dg);
        }
    }
    write_mesh_vtu(&files[0], &problem.mesh, &[Field::vector("displacement", u.to_vec())], &cells)?;
    if scene.output.boundary {
        let boundary = dir.join(format!("{name}_boundary.vtu"));
        let facet_fields = contact.map(|c| contact_fields(problem.mesh.n_facets(), c)).unwrap_or_default();
        write_boundary_vtu(&boundary, &problem.mesh, &[Field::vector("displacement", u.to_vec())], &facet_fields)?;
        files.push(boundary);
    }
    Ok(files)
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

/// Cell fields the output section asks for: every η component and the cell means of σ_h.
fn estimate_fields(e: &Estimate, output: &OutputSection) -> Vec<Field> {
    let mut fields = Vec::new();
    if output.estimators {
        fields.extend(NAMES.iter().zip(e.estimators.components()).map(|(n, v)| Field::scalar(*n, v.clone())));
    }
    if output.reconstruction {
        fields.extend(SIGMA_H.iter().zip(e.reconstruction.cell_means()).map(|(n, v)| Field::scalar(*n, v)));
    }
    fields
}

/// Facet fields of Γ_C: mean pressure, mean normal displacement, status (−1 not a contact
/// facet, 0 open, 1 closed: stick with friction, 2 slip), the regularisation error; with
/// friction the mean tangential traction and slip; with uplift the mean pore pressure and the
/// mean effective normal stress σ'^n = −p_c.
fn contact_fields(n_facets: usize, contact: &ContactSolution) -> Vec<Field> {
    type Column = (&'static str, fn(&FaceState) -> f64);
    let mut columns: Vec<Column> = vec![
        ("contact_pressure", |f| f.pressure),
        ("normal_displacement", |f| f.normal_displacement),
        ("contact_status", FaceState::status),
        ("regularisation_error", |f| f.regularisation_error),
    ];
    if contact.nitsche.law.has_friction() {
        columns.extend([
            ("tangential_traction", (|f| f.tangential_traction) as fn(&FaceState) -> f64),
            ("slip", |f| f.slip),
        ]);
    }
    if contact.nitsche.uplift.is_some() {
        columns.extend([
            ("uplift_pressure", (|f| f.uplift) as fn(&FaceState) -> f64),
            ("effective_normal_stress", |f| -f.pressure),
        ]);
    }
    columns
        .into_iter()
        .map(|(name, value)| {
            let mut field = vec![if name == "contact_status" { -1.0 } else { 0.0 }; n_facets];
            for (face, state) in contact.nitsche.faces.iter().zip(&contact.faces) {
                field[face.facet] = value(state);
            }
            Field::scalar(name, field)
        })
        .collect()
}
