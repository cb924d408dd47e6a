//! The `--estimate` part of `damfem solve`: reconstruction, estimators, checks and their
//! output fields.

use crate::contact::projection::QuadraticSmoothing;
use crate::contact::ContactSolution;
use crate::elasticity::{Discretisation, Problem};
use crate::estimate::afw::{self, COMPONENTS};
use crate::estimate::checks::{check, Equilibration};
use crate::estimate::estimators::{estimate, Estimators, GlobalEstimators, NAMES};
use crate::estimate::reconstruction::{reconstruct, ContactState, Reconstruction};
use crate::fem::lagrange;
use crate::io::vtu::{write_mesh_vtu, Field};
use crate::mesh::Mesh;
use anyhow::Result;
use serde::Serialize;
use std::path::Path;

/// Names of the reconstructed stress components.
const SIGMA_H: [&str; 4] = ["sigma_h_xx", "sigma_h_xy", "sigma_h_yx", "sigma_h_yy"];

/// Everything the estimator produced.
pub struct Estimate {
    pub reconstruction: Reconstruction,
    pub estimators: Estimators,
    pub equilibration: Option<Equilibration>,
}

/// What `summary.json` records of the estimate.
#[derive(Serialize)]
pub struct EstimateSummary {
    pub global: GlobalEstimators,
    pub equilibration: Option<Equilibration>,
}

/// Reconstructs σ_h for the solution `x` (and the contact state), computes the estimators
/// and, if asked, the equilibration checks.
pub fn run(
    problem: &Problem,
    disc: &Discretisation,
    x: &[f64],
    contact: Option<(&ContactSolution, f64)>,
    checks: bool,
) -> Result<Estimate> {
    let u = problem.displacement(disc, x);
    let u_prev = contact.map(|(c, _)| problem.displacement(disc, &c.x_prev));
    let projection = QuadraticSmoothing { delta: contact.map_or(0.0, |c| c.1) };
    let state = contact.zip(u_prev.as_ref()).map(|((c, _), u_prev)| ContactState {
        nitsche: &c.nitsche,
        projection: &projection,
        u_prev,
    });
    let reconstruction = reconstruct(problem, &disc.topology, &u, state.as_ref())?;
    let estimators = estimate(problem, &disc.topology, &u, &reconstruction, state.as_ref());
    let equilibration = checks.then(|| check(problem, &disc.topology, &u, &reconstruction, state.as_ref()));
    Ok(Estimate { reconstruction, estimators, equilibration })
}

impl Estimate {
    pub fn summary(&self) -> EstimateSummary {
        EstimateSummary { global: self.estimators.global(), equilibration: self.equilibration }
    }

    /// Cell fields: every η component and the cell means of σ_h.
    pub fn cell_fields(&self, mesh: &Mesh) -> Vec<Field> {
        let mut fields: Vec<Field> =
            NAMES.iter().zip(self.estimators.components()).map(|(n, v)| Field::scalar(*n, v.clone())).collect();
        let order = self.reconstruction.order;
        let nb = lagrange::n_basis(order);
        // ∫_T φ_k / |T|: 1/3 per vertex for P1; 0 at vertices and 1/3 at midpoints for P2
        let mean: Vec<f64> = (0..nb)
            .map(|k| {
                if order == 1 {
                    1.0 / 3.0
                } else if k < 3 {
                    0.0
                } else {
                    1.0 / 3.0
                }
            })
            .collect();
        for (c, name) in SIGMA_H.iter().enumerate() {
            let values = (0..mesh.n_cells())
                .map(|t| (0..nb).map(|k| self.reconstruction.total(t)[c * nb + k] * mean[k]).sum())
                .collect();
            fields.push(Field::scalar(*name, values));
        }
        fields
    }

    /// Writes σ_h as a discontinuous field: each cell with its own copies of its vertices.
    pub fn write_discontinuous(&self, path: &Path, mesh: &Mesh) -> Result<()> {
        let order = self.reconstruction.order;
        let reference = lagrange::reference_nodes(1);
        let mut points = Vec::with_capacity(3 * mesh.n_cells());
        let mut values = vec![Vec::with_capacity(3 * mesh.n_cells()); COMPONENTS];
        for c in 0..mesh.n_cells() {
            let sigma = self.reconstruction.total(c);
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
}
