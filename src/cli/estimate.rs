//! Output of an error estimate: summary, cell fields and the discontinuous σ_h.

use crate::estimate::afw::{self, COMPONENTS};
use crate::estimate::checks::Equilibration;
use crate::estimate::estimators::{GlobalEstimators, NAMES};
use crate::estimate::Estimate;
use crate::fem::lagrange;
use crate::io::vtu::{write_mesh_vtu, Field};
use crate::mesh::Mesh;
use crate::scene::OutputSection;
use anyhow::Result;
use serde::Serialize;
use std::path::Path;

/// Names of the reconstructed stress components.
const SIGMA_H: [&str; 4] = ["sigma_h_xx", "sigma_h_xy", "sigma_h_yx", "sigma_h_yy"];

/// What `summary.json` records of the estimate.
#[derive(Serialize)]
pub struct EstimateSummary {
    pub global: GlobalEstimators,
    pub equilibration: Option<Equilibration>,
}

pub fn summary(e: &Estimate) -> EstimateSummary {
    EstimateSummary { global: e.estimators.global(), equilibration: e.equilibration }
}

/// Cell fields the output section asks for: every η component and the cell means of σ_h.
pub fn cell_fields(e: &Estimate, mesh: &Mesh, output: &OutputSection) -> Vec<Field> {
    let mut fields = Vec::new();
    if output.estimators {
        fields.extend(NAMES.iter().zip(e.estimators.components()).map(|(n, v)| Field::scalar(*n, v.clone())));
    }
    if output.reconstruction {
        let order = e.reconstruction.order;
        let nb = lagrange::n_basis(order);
        // ∫_T φ_k / |T|: 1/3 per vertex for P1; 0 at vertices and 1/3 at midpoints for P2
        let mean = |k: usize| if order == 2 && k < 3 { 0.0 } else { 1.0 / 3.0 };
        for (c, name) in SIGMA_H.iter().enumerate() {
            let values = (0..mesh.n_cells())
                .map(|t| (0..nb).map(|k| e.reconstruction.total(t)[c * nb + k] * mean(k)).sum())
                .collect();
            fields.push(Field::scalar(*name, values));
        }
    }
    fields
}

/// Writes σ_h as a discontinuous field: each cell with its own copies of its vertices.
pub fn write_discontinuous(path: &Path, e: &Estimate, mesh: &Mesh) -> Result<()> {
    let order = e.reconstruction.order;
    let reference = lagrange::reference_nodes(1);
    let mut points = Vec::with_capacity(3 * mesh.n_cells());
    let mut values: Vec<Vec<f64>> = (0..COMPONENTS).map(|_| Vec::with_capacity(3 * mesh.n_cells())).collect();
    for c in 0..mesh.n_cells() {
        let sigma = e.reconstruction.total(c);
        for (v, &xi) in mesh.cell_vertices(c).iter().zip(reference) {
            points.push(*v);
            let tau = afw::evaluate(order, &sigma, xi);
            for (k, column) in values.iter_mut().enumerate() {
                column.push(tau[k]);
            }
        }
    }
    let dg = Mesh {
        points,
        order: 1,
        cell_nodes: (0..3 * mesh.n_cells()).collect(),
        cell_tags: mesh.cell_tags.clone(),
        facet_nodes: Vec::new(),
        facet_tags: Vec::new(),
        groups: mesh.groups.clone(),
    };
    let fields: Vec<Field> = SIGMA_H.iter().zip(values).map(|(n, v)| Field::scalar(*n, v)).collect();
    write_mesh_vtu(path, &dg, &fields, &[])?;
    Ok(())
}
