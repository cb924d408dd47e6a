//! The six local error estimators and their global values (docs/method.md §5).
//!
//! For a cell T with diameter h_T, its Neumann faces F_T^N and contact faces F_T^C:
//!
//! - η_osc,T  = (h_T/π) ‖f − Π^{p−1} f‖_T
//! - η_flux,T = ‖σ_h1 − σ(u_h)‖_T
//! - η_Neu,T  = Σ_{F_T^N} C_{t,T,F} h_F^{1/2} ‖g_N − Π_F^p g_N‖_F,  C² = (h_T²/|T|)(1/π)(1/π + 1)
//! - η_disc,T = Σ_{F_T^C} h_F^{1/2} ‖t₁ − Π_F^p t₁‖_F
//! - η_reg,T  = ‖σ_h2‖_T + Σ_{F_T^C} h_F^{1/2} ‖σ_h2 n‖_F
//! - η_lin,T  = ‖σ_h3‖_T + Σ_{F_T^C} h_F^{1/2} ‖σ_h3 n‖_F
//!
//! and η_tot,T is their sum; a global value is (Σ_T η_T²)^{1/2}. Then the dual norm of the
//! residual is at most η_tot. Terms a scene cannot have are exactly 0 and not computed:
//! η_osc for piecewise constant f, η_Neu for tractions that are polynomials of degree ≤ p on
//! every face, and the contact terms without Γ_C.

use super::afw::{self, COMPONENTS};
use super::face::FaceProjection;
use super::facets::{sampled_facets, SampledFacet};
use super::reconstruction::Reconstruction;
use crate::contact::Linearisation;
use crate::elasticity::kernels::{displacement_gradient, stress};
use crate::elasticity::{BodyForce, Displacement, Problem, Traction};
use crate::fem::lagrange;
use crate::fem::quadrature::{gauss_segment_cached, split_rule, triangle_cached};
use crate::geometry::{AffineMap, Point, Segment, Vector, D};
use crate::mesh::Topology;
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::PI;

/// Names of the components, in the order of [`Estimators::components`].
pub const NAMES: [&str; 7] = ["eta_osc", "eta_flux", "eta_Neu", "eta_disc", "eta_reg", "eta_lin", "eta_tot"];

/// Per-cell estimators.
#[derive(Debug, Clone)]
pub struct Estimators {
    pub osc: Vec<f64>,
    pub flux: Vec<f64>,
    pub neu: Vec<f64>,
    pub disc: Vec<f64>,
    pub reg: Vec<f64>,
    pub lin: Vec<f64>,
    pub tot: Vec<f64>,
}

/// Global values (Σ_T η_T²)^{1/2} of each component.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct GlobalEstimators {
    pub osc: f64,
    pub flux: f64,
    pub neu: f64,
    pub disc: f64,
    pub reg: f64,
    pub lin: f64,
    pub tot: f64,
}

impl Estimators {
    /// The seven per-cell arrays, in the order of [`NAMES`].
    pub fn components(&self) -> [&Vec<f64>; 7] {
        [&self.osc, &self.flux, &self.neu, &self.disc, &self.reg, &self.lin, &self.tot]
    }

    pub fn global(&self) -> GlobalEstimators {
        let g = |v: &Vec<f64>| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        GlobalEstimators {
            osc: g(&self.osc),
            flux: g(&self.flux),
            neu: g(&self.neu),
            disc: g(&self.disc),
            reg: g(&self.reg),
            lin: g(&self.lin),
            tot: g(&self.tot),
        }
    }
}

/// Computes every estimator for the iterate `u` and its reconstruction.
pub fn estimate(
    problem: &Problem,
    topology: &Topology,
    u: &Displacement,
    rec: &Reconstruction,
    contact: Option<&Linearisation>,
) -> Estimators {
    let facets = contact.map(|c| sampled_facets(&problem.mesh, topology, c, u));
    estimate_sampled(problem, topology, u, rec, facets.as_deref())
}

/// [`estimate`] with the facets of Γ_C sampled at `u` ([`sampled_facets`]), None without Γ_C.
pub(crate) fn estimate_sampled(
    problem: &Problem,
    topology: &Topology,
    u: &Displacement,
    rec: &Reconstruction,
    facets: Option<&[SampledFacet]>,
) -> Estimators {
    let n = problem.mesh.n_cells();
    let norms = |i: usize, u: Option<&Displacement>| -> Vec<f64> {
        (0..n).into_par_iter().map(|c| volume_norm(problem, rec.cell(i, c), c, u)).collect()
    };
    let mut e = Estimators {
        osc: oscillation(problem),
        flux: norms(0, Some(u)),
        neu: neumann(problem, topology),
        disc: vec![0.0; n],
        reg: vec![0.0; n],
        lin: vec![0.0; n],
        tot: vec![0.0; n],
    };
    if let Some(facets) = facets {
        e.reg = norms(1, None);
        e.lin = norms(2, None);
        contact_facet_terms(problem, rec, facets, &mut e);
    }
    for c in 0..n {
        e.tot[c] = e.osc[c] + e.flux[c] + e.neu[c] + e.disc[c] + e.reg[c] + e.lin[c];
    }
    e
}

/// ‖σ_h‖ = (Σ_T ‖σ_h1 + σ_h2 + σ_h3‖_T²)^{1/2}: the scale of a relative tolerance on η.
pub fn stress_norm(problem: &Problem, rec: &Reconstruction) -> f64 {
    (0..problem.mesh.n_cells()).map(|c| volume_norm(problem, &rec.total(c), c, None).powi(2)).sum::<f64>().sqrt()
}

/// ‖τ − σ(u_h)‖_T (or ‖τ‖_T without u) for the stress with coefficients `tau` on cell c.
fn volume_norm(problem: &Problem, tau: &[f64], c: usize, u: Option<&Displacement>) -> f64 {
    let mesh = &problem.mesh;
    let order = mesh.order;
    let map = AffineMap::new(mesh.cell_vertices(c));
    let (lambda, mu) = problem.materials[c].lame();
    let mut nodal = Vec::new();
    if let Some(u) = u {
        u.relative(mesh.cell(c), &mut nodal);
    }
    let mut grads = [[0.0; 2]; 6];
    let rule = triangle_cached(2 * order);
    let mut sum = 0.0;
    for (&xi, &w) in rule.points.iter().zip(&rule.weights) {
        let t = afw::evaluate(order, tau, xi);
        let s = if u.is_some() {
            let s = stress(
                displacement_gradient(&map, order, xi, &nodal, &mut grads[..lagrange::n_basis(order)]),
                lambda,
                mu,
            );
            [s[0], s[2], s[2], s[1]]
        } else {
            [0.0; 4]
        };
        sum += (0..COMPONENTS).map(|k| (t[k] - s[k]).powi(2)).sum::<f64>() * w * map.det.abs();
    }
    sum.sqrt()
}

/// η_osc,T; zero without computation unless f is a general field.
fn oscillation(problem: &Problem) -> Vec<f64> {
    let mesh = &problem.mesh;
    let BodyForce::Field(f) = &problem.body_force else {
        return vec![0.0; mesh.n_cells()];
    };
    let order = mesh.order;
    let nl = afw::n_lower(order);
    let rule = triangle_cached(2 * order + 6);
    (0..mesh.n_cells())
        .into_par_iter()
        .map(|c| {
            let map = AffineMap::new(mesh.cell_vertices(c));
            let ints = afw::cell_integrals(order, &map);
            let gram =
                nalgebra::DMatrix::from_row_slice(nl, nl, &ints.lower_gram).cholesky().expect("positive definite");
            let mut psi = [0.0; 3];
            let samples: Vec<(Vector, [f64; 3], f64)> = rule
                .points
                .iter()
                .zip(&rule.weights)
                .map(|(&xi, &w)| {
                    afw::lower_values(order, xi, &mut psi[..nl]);
                    (f(map.to_physical(xi)), psi, w * map.det.abs())
                })
                .collect();
            let mut error = 0.0;
            for i in 0..D {
                let moments =
                    nalgebra::DVector::from_fn(nl, |m, _| samples.iter().map(|(fx, p, w)| fx[i] * p[m] * w).sum());
                let alpha = gram.solve(&moments);
                error += samples
                    .iter()
                    .map(|(fx, p, w)| (fx[i] - (0..nl).map(|m| alpha[m] * p[m]).sum::<f64>()).powi(2) * w)
                    .sum::<f64>();
            }
            mesh.cell_diameter(c) / PI * error.sqrt()
        })
        .collect()
}

/// Whether a traction is a polynomial of degree ≤ p on the face with end points `ends`.
fn polynomial_on_face(traction: &Traction, ends: [Point; 2]) -> bool {
    match traction {
        Traction::Constant(_) => true,
        Traction::Hydrostatic { level, .. } | Traction::Silt { level, .. } => {
            (ends[0][1] <= *level) == (ends[1][1] <= *level)
        }
        Traction::Ice { .. } => traction.kinks(ends).is_empty(),
        Traction::Sum(parts) => parts.iter().all(|t| polynomial_on_face(t, ends)),
        Traction::Field(_) | Traction::Westergaard { .. } => false,
    }
}

/// η_Neu,T, computed only on faces where g_N is not a polynomial of degree ≤ p.
fn neumann(problem: &Problem, topology: &Topology) -> Vec<f64> {
    let mesh = &problem.mesh;
    let mut eta = vec![0.0; mesh.n_cells()];
    let rule = gauss_segment_cached(mesh.order + 6);
    for bc in &problem.neumann {
        for f in (0..mesh.n_facets()).filter(|&f| mesh.facet_tags[f] == bc.tag) {
            let nodes = mesh.facet(f);
            let ends = [mesh.points[nodes[0]], mesh.points[nodes[1]]];
            if polynomial_on_face(&bc.traction, ends) {
                continue;
            }
            let c = topology.tagged_cell(f);
            let (h_t, area, h_f) = (mesh.cell_diameter(c), mesh.cell_area(c).abs(), mesh.facet_length(f));
            let trace_constant = (h_t * h_t / area / PI * (1.0 / PI + 1.0)).sqrt();
            let normal = topology.outward_normal(mesh, f);
            let points: Vec<(f64, f64)> =
                split_rule(rule, bc.traction.kinks(ends)).into_iter().map(|(s, w)| (s, w * h_f)).collect();
            let projection = FaceProjection::new(mesh.order, &points);
            let g: Vec<Vector> =
                points.iter().map(|&(s, _)| bc.traction.at(Segment::new(ends[0], ends[1]).point(s), normal)).collect();
            let error = (0..D)
                .map(|i| projection.oscillation(&g.iter().map(|v| v[i]).collect::<Vec<_>>()).powi(2))
                .sum::<f64>()
                .sqrt();
            eta[c] += trace_constant * h_f.sqrt() * error;
        }
    }
    eta
}

/// The parts of η_disc, η_reg and η_lin on the facets of Γ_C (on both sides of a joint):
/// h_F^{1/2} ‖t₁ − Π_F^p t₁‖_F and h_F^{1/2} ‖σ_hi n‖_F, i = 2, 3, added to the facet's cell.
fn contact_facet_terms(problem: &Problem, rec: &Reconstruction, facets: &[SampledFacet], e: &mut Estimators) {
    let mesh = &problem.mesh;
    for SampledFacet { facet, samples } in facets {
        let rule: Vec<(f64, f64)> = samples.iter().map(|p| (p.r, p.weight)).collect();
        let projection = FaceProjection::new(mesh.order, &rule);
        let root_h = facet.length.sqrt();
        let t1 = |j: usize| samples.iter().map(|p| p.t[0][j]).collect::<Vec<_>>();
        e.disc[facet.cell] += root_h * projection.oscillation(&t1(0)).hypot(projection.oscillation(&t1(1)));
        for (i, eta) in [(1, &mut e.reg), (2, &mut e.lin)] {
            let traction: Vec<Vector> = samples
                .iter()
                .map(|p| {
                    let t = afw::evaluate(mesh.order, rec.cell(i, facet.cell), facet.reference_point(mesh, p.r));
                    [t[0] * facet.normal[0] + t[1] * facet.normal[1], t[2] * facet.normal[0] + t[3] * facet.normal[1]]
                })
                .collect();
            let norm = (0..D)
                .map(|j| projection.norm(&traction.iter().map(|v| v[j]).collect::<Vec<_>>()).powi(2))
                .sum::<f64>()
                .sqrt();
            eta[facet.cell] += root_h * norm;
        }
    }
}
