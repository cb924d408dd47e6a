//! ParaView files of one solution, shared by `solve` and `adapt`.

use super::estimate::{cell_fields, write_discontinuous};
use crate::contact::nitsche::Nitsche;
use crate::contact::FaceState;
use crate::elasticity::kernels::{principal, von_mises};
use crate::elasticity::Problem;
use crate::estimate::Estimate;
use crate::io::vtu::{write_boundary_vtu, write_mesh_vtu, Field};
use crate::scene::Scene;
use anyhow::Result;
use std::path::{Path, PathBuf};

/// The contact faces and their states.
pub type ContactFaces<'a> = (&'a Nitsche, &'a [FaceState]);

/// Writes `<name>.vtu`, and as the scene asks `<name>_boundary.vtu` and `<name>_dg.vtu`;
/// returns their paths.
#[allow(clippy::too_many_arguments)]
pub fn write_results(
    dir: &Path,
    name: &str,
    scene: &Scene,
    problem: &Problem,
    u: &[[f64; 2]],
    sigma: &[[f64; 4]],
    contact: Option<ContactFaces>,
    estimate: Option<&Estimate>,
) -> Result<Vec<PathBuf>> {
    let mut files = vec![dir.join(format!("{name}.vtu"))];
    let mut cells = stress_fields(sigma);
    if let Some(e) = estimate {
        cells.extend(cell_fields(e, &problem.mesh, &scene.output));
        if scene.output.reconstruction {
            let dg = dir.join(format!("{name}_dg.vtu"));
            write_discontinuous(&dg, e, &problem.mesh)?;
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

/// Facet fields of Γ_C: mean pressure, mean normal displacement, status (1 contact,
/// 0 separation, −1 not a contact facet) and the regularisation error.
fn contact_fields(n_facets: usize, (nitsche, states): ContactFaces) -> Vec<Field> {
    let mut fields = [vec![0.0; n_facets], vec![0.0; n_facets], vec![-1.0; n_facets], vec![0.0; n_facets]];
    for (face, state) in nitsche.faces.iter().zip(states) {
        let f = face.facet;
        fields[0][f] = state.pressure;
        fields[1][f] = state.normal_displacement;
        fields[2][f] = if state.contact_length > 0.0 { 1.0 } else { 0.0 };
        fields[3][f] = state.regularisation_error;
    }
    let names = ["contact_pressure", "normal_displacement", "contact_status", "regularisation_error"];
    names.into_iter().zip(fields).map(|(n, v)| Field::scalar(n, v)).collect()
}
