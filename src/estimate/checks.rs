//! Equilibration checks of a reconstruction (docs/method.md §4.1, §5.2).
//!
//! Each check returns its largest relative violation and where it occurs; all should be at
//! round-off level. They are the hypotheses of the bound (docs/method.md §5): when every one
//! holds, η_tot ≥ ‖R(u_h)‖ whatever the iterate u_h.

use super::afw::{self, COMPONENTS};
use super::face::FaceProjection;
use super::facets::{sampled_facets, SampledFacet};
use super::reconstruction::Reconstruction;
use super::volume_degree;
use crate::contact::Linearisation;
use crate::elasticity::problem::traction_rule;
use crate::elasticity::stress::cell_mean_stress;
use crate::elasticity::{Displacement, Problem};
use crate::fem::lagrange;
use crate::fem::quadrature::{gauss_segment_cached, triangle_cached};
use crate::geometry::{distance, dot, AffineMap, Point, Segment, Vector, D};
use crate::mesh::topology::NONE;
use crate::mesh::Topology;
use rayon::prelude::*;
use serde::Serialize;

/// Largest relative violation of each equilibration condition.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Equilibration {
    /// max_T ‖∇·σ_h + Π^{p−1} f‖_T / max_T (‖Π^{p−1} f‖_T + ‖σ_h‖_T / h_T).
    pub divergence: f64,
    /// max_F ‖[[σ_h n]]‖_F / max_F ‖σ_h n‖_F over interior faces.
    pub normal_continuity: f64,
    /// max_F ‖σ_h n − Π_F^p g_N‖_F / max_F ‖σ_h n‖_F over Neumann faces.
    pub neumann: f64,
    /// max_F ‖σ_hi n − Π_F^p t_i‖_F / max_F ‖σ_h n‖_F over contact faces, i = 1, 2, 3, with
    /// t_i the Γ_C traction vectors (normal and tangential).
    pub contact: f64,
    /// max_T |(σ_h, ψ J)_T| / (‖σ_h‖_T ‖ψ‖_T), ψ ∈ P_{p−1}; only meaningful for p ≥ 2.
    pub weak_symmetry: f64,
    /// Largest relative residual of the compatibility condition on patches.
    pub compatibility: f64,
    /// Where each condition above is violated most: a cell centroid, an edge midpoint or a
    /// patch vertex, in the order of the fields.
    #[serde(skip)]
    pub at: [Point; 6],
}

/// The condition of each [`Equilibration`] field, in their order.
const CONDITIONS: [&str; 6] = [
    "divergence (div sigma_h + f = 0 in a cell)",
    "normal continuity (sigma_h n continuous across an interior edge)",
    "Neumann traction (sigma_h n = g_N on a Neumann edge)",
    "contact traction (sigma_h n = the Nitsche traction on a contact edge)",
    "weak symmetry (sigma_h symmetric against P_{p-1} rotations in a cell)",
    "compatibility (the data of a vertex patch balance its rigid motions)",
];

/// The largest violation of one condition and where it occurs.
#[derive(Debug, Clone, Copy, Default)]
struct Worst {
    value: f64,
    at: Point,
}

impl Worst {
    fn max(self, value: f64, at: Point) -> Worst {
        if value > self.value {
            Worst { value, at }
        } else {
            self
        }
    }

    /// The larger of two, the first on ties: reducing in order, as rayon does, gives the
    /// place that a sequential scan finds, on any number of threads.
    fn larger(self, other: Worst) -> Worst {
        self.max(other.value, other.at)
    }
}

/// The worst violated condition of a reconstruction, as [`Equilibration::violation`] finds it.
#[derive(Debug, Clone, Copy)]
pub struct Violation {
    pub condition: &'static str,
    /// Relative size of the violation.
    pub value: f64,
    pub at: Point,
}

impl Equilibration {
    /// The largest of all violations (weak symmetry only for p ≥ 2).
    pub fn worst(&self, order: usize) -> f64 {
        self.violation(order).value
    }

    /// One line per condition: its relative violation and where it is largest.
    pub fn table(&self, order: usize) -> String {
        let values = [
            self.divergence,
            self.normal_continuity,
            self.neumann,
            self.contact,
            self.weak_symmetry,
            self.compatibility,
        ];
        let line = |i: usize| match i {
            4 if order < 2 => format!("  {:<72} not applicable (P1)", CONDITIONS[i]),
            _ => format!("  {:<72} {:.1e} at ({:.4}, {:.4})", CONDITIONS[i], values[i], self.at[i][0], self.at[i][1]),
        };
        (0..6).map(line).collect::<Vec<_>>().join("\n")
    }

    /// The condition violated most, with its relative size and place (weak symmetry only for
    /// p ≥ 2, where the reconstruction is tested against P_{p−1} rotations).
    pub fn violation(&self, order: usize) -> Violation {
        let symmetry = if order >= 2 { self.weak_symmetry } else { 0.0 };
        let values =
            [self.divergence, self.normal_continuity, self.neumann, self.contact, symmetry, self.compatibility];
        // a NaN check counts as the worst
        let i = (0..6).fold(0, |best, i| if values[i] > values[best] || values[i].is_nan() { i } else { best });
        Violation { condition: CONDITIONS[i], value: values[i], at: self.at[i] }
    }
}

/// Runs every check on the reconstruction `rec` of the iterate `u`.
pub fn check(
    problem: &Problem,
    topology: &Topology,
    u: &Displacement,
    rec: &Reconstruction,
    contact: Option<&Linearisation>,
) -> Equilibration {
    let facets = contact.map_or_else(Vec::new, |c| sampled_facets(&problem.mesh, topology, c, u));
    check_sampled(problem, topology, rec, &facets)
}

/// [`check`] with the facets of Γ_C sampled at the iterate ([`sampled_facets`]; none without
/// Γ_C).
pub(crate) fn check_sampled(
    problem: &Problem,
    topology: &Topology,
    rec: &Reconstruction,
    facets: &[SampledFacet],
) -> Equilibration {
    let traces = Traces::new(problem, topology, rec);
    let (divergence, weak_symmetry) = cell_checks(problem, rec);
    let checks = [
        divergence,
        traces.relative(traces.continuity()),
        traces.relative(traces.neumann()),
        traces.relative(contact_traces(problem, rec, facets)),
        weak_symmetry,
        Worst { value: rec.compatibility, at: rec.compatibility_at },
    ];
    Equilibration {
        divergence: checks[0].value,
        normal_continuity: checks[1].value,
        neumann: checks[2].value,
        contact: checks[3].value,
        weak_symmetry: checks[4].value,
        compatibility: checks[5].value,
        at: checks.map(|w| w.at),
    }
}

/// The relative violation that the representation of `u` alone may cause (docs/method.md §5.2):
/// ε_u max_T w_T |u|_T (λ + 2μ)_T / h_T over max_T |σ(u_h)|_T, with |u|_T the largest nodal
/// |u| of cell T, |σ(u_h)|_T its largest cell-mean component and w_T = γ₀ on the cells of Γ_C
/// (whose Nitsche term weighs nodal values by γ₀ E / h), else 1. A double u_h resolves nodal
/// differences only to ε |u_h| (ε_u = ε), so no double vector solves the discrete equation
/// better than about ε E |u_h| per vertex, and a patch's data balance only to that; a refined
/// pair hi + lo resolves them to ε² |u_h| (ε_u = ε²) besides the rounding ε |u_k − u_0| of the
/// difference itself, which does not grow with |u_h| / h.
pub fn representation_bound(problem: &Problem, u: &Displacement, contact: Option<&Linearisation>) -> f64 {
    let mesh = &problem.mesh;
    let mut weight = vec![1.0; mesh.n_cells()];
    if let Some(state) = contact {
        let gamma0 = state.nitsche.laws.iter().map(|c| c.parameters.gamma0).fold(1.0, f64::max);
        for face in &state.nitsche.faces {
            weight[face.cell] = gamma0;
            face.opposite.iter().for_each(|opposite| weight[opposite.cell] = gamma0);
        }
    }
    let stress = cell_mean_stress(problem, &u.hi).into_iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
    let defect = (0..mesh.n_cells())
        .map(|c| {
            let (lambda, mu) = problem.materials[c].lame();
            weight[c] * u.size(mesh.cell(c)) * (lambda + 2.0 * mu) / mesh.cell_diameter(c)
        })
        .fold(0.0, f64::max);
    let resolution = if u.lo.is_some() { f64::EPSILON * f64::EPSILON } else { f64::EPSILON };
    resolution * defect / stress.max(f64::MIN_POSITIVE)
}

/// The divergence check, ‖∇·σ_h + Π^{p−1} f‖_T relative to the scale of the terms, and the
/// weak-symmetry check, max_T |(σ_h, ψ_m J)_T| / (‖σ_h‖_T ‖ψ_m‖_T), cell by cell in parallel.
fn cell_checks(problem: &Problem, rec: &Reconstruction) -> (Worst, Worst) {
    let identity = || (Worst::default(), 0.0, Worst::default());
    let (divergence, scale, symmetry) = (0..problem.mesh.n_cells())
        .into_par_iter()
        .map(|c| {
            let map = AffineMap::new(problem.mesh.cell_vertices(c));
            let ints = afw::cell_integrals(problem.mesh.order, &map);
            let sigma = rec.total(c);
            let (defect, scale) = divergence(problem, c, &map, &ints, &sigma);
            let at = problem.mesh.cell_centroid(c);
            (Worst::default().max(defect, at), scale, Worst::default().max(weak_symmetry(problem, &ints, &sigma), at))
        })
        .reduce(identity, |a, b| (a.0.larger(b.0), a.1.max(b.1), a.2.larger(b.2)));
    (Worst { value: divergence.value / scale.max(f64::MIN_POSITIVE), at: divergence.at }, symmetry)
}

/// ‖∇·σ_h + Π^{p−1} f‖_T on cell c with the coefficients `sigma`, and the scale
/// ‖Π^{p−1} f‖_T + ‖σ_h‖_T / h_T of its terms.
fn divergence(problem: &Problem, c: usize, map: &AffineMap, ints: &afw::CellIntegrals, sigma: &[f64]) -> (f64, f64) {
    let mesh = &problem.mesh;
    let order = mesh.order;
    let nl = afw::n_lower(order);
    let rule = triangle_cached(volume_degree(problem));
    let gram = nalgebra::DMatrix::from_row_slice(nl, nl, &ints.lower_gram).cholesky().expect("positive definite");
    let f = |x: Point| problem.body_force_at(c, x);
    let mut psi = [0.0; 3];
    let mut moments = [nalgebra::DVector::zeros(nl), nalgebra::DVector::zeros(nl)];
    let (mut defect, mut size, mut norm_sigma) = (0.0, 0.0, 0.0);
    for (&xi, &w) in rule.points.iter().zip(&rule.weights) {
        afw::lower_values(order, xi, &mut psi[..nl]);
        let fx = f(map.to_physical(xi));
        for i in 0..D {
            for m in 0..nl {
                moments[i][m] += fx[i] * psi[m] * w * map.det.abs();
            }
        }
    }
    let alpha = [gram.solve(&moments[0]), gram.solve(&moments[1])];
    for (&xi, &w) in rule.points.iter().zip(&rule.weights) {
        afw::lower_values(order, xi, &mut psi[..nl]);
        let div = afw::divergence(order, map, sigma, xi);
        let t = afw::evaluate(order, sigma, xi);
        let w = w * map.det.abs();
        for i in 0..D {
            let pf: f64 = (0..nl).map(|m| alpha[i][m] * psi[m]).sum();
            defect += (div[i] + pf).powi(2) * w;
            size += pf * pf * w;
        }
        norm_sigma += t.iter().map(|v| v * v).sum::<f64>() * w;
    }
    (defect.sqrt(), size.sqrt() + norm_sigma.sqrt() / mesh.cell_diameter(c))
}

/// max_m |(σ_h, ψ_m J)_T| / (‖σ_h‖_T ‖ψ_m‖_T) on a cell with the integrals `ints` and the
/// coefficients `sigma`.
fn weak_symmetry(problem: &Problem, ints: &afw::CellIntegrals, sigma: &[f64]) -> f64 {
    let order = problem.mesh.order;
    let (nb, nl) = (lagrange::n_basis(order), afw::n_lower(order));
    let norm: f64 = (0..COMPONENTS)
        .map(|comp| {
            (0..nb)
                .flat_map(|k| (0..nb).map(move |l| (k, l)))
                .map(|(k, l)| sigma[comp * nb + k] * ints.mass[k * nb + l] * sigma[comp * nb + l])
                .sum::<f64>()
        })
        .sum::<f64>()
        .sqrt();
    (0..nl).fold(0.0, |worst, m| {
        let skew: f64 = (0..nb).map(|k| (sigma[nb + k] - sigma[2 * nb + k]) * ints.lower_mass[m * nb + k]).sum();
        let psi_norm = ints.lower_gram[m * nl + m].sqrt();
        let value = skew.abs() / (norm * psi_norm).max(f64::MIN_POSITIVE);
        if value > worst {
            value
        } else {
            worst
        }
    })
}

/// Normal traces of σ_h on every face.
struct Traces<'a> {
    problem: &'a Problem,
    topology: &'a Topology,
    rec: &'a Reconstruction,
    /// max_F ‖σ_h n‖_F.
    scale: f64,
}

impl<'a> Traces<'a> {
    fn new(problem: &'a Problem, topology: &'a Topology, rec: &'a Reconstruction) -> Self {
        let mut t = Traces { problem, topology, rec, scale: 0.0 };
        t.scale = (0..topology.n_facets())
            .into_par_iter()
            .map(|e| t.norm(e, topology.facet_cells[e][0], |_| [0.0; 2]))
            .reduce(|| f64::MIN_POSITIVE, f64::max);
        t
    }

    /// Points of facet e: (s, weight · |F|) and the physical ends.
    fn rule(&self, e: usize) -> (Vec<(f64, f64)>, [Point; 2]) {
        let mesh = &self.problem.mesh;
        let [a, b] = self.topology.facets[e];
        let ends = [mesh.points[a], mesh.points[b]];
        let length = distance(ends[0], ends[1]);
        let rule = gauss_segment_cached(mesh.order + 2);
        (rule.points.iter().zip(&rule.weights).map(|(&s, &w)| (s, w * length)).collect(), ends)
    }

    /// σ_h n_e (n_e the normal of the facet's ends a → b, rotated clockwise) of cell c, with
    /// the coefficients `sigma` of σ_h there, at s.
    fn trace(&self, e: usize, c: usize, sigma: &[f64], s: f64) -> Vector {
        let mesh = &self.problem.mesh;
        let [a, b] = self.topology.facets[e];
        let (pa, pb) = (mesh.points[a], mesh.points[b]);
        let length = distance(pa, pb);
        let n = [(pb[1] - pa[1]) / length, -(pb[0] - pa[0]) / length];
        let t = afw::evaluate(mesh.order, sigma, reference_point(mesh.cell(c), a, b, s));
        [t[0] * n[0] + t[1] * n[1], t[2] * n[0] + t[3] * n[1]]
    }

    /// ‖σ_h n − g‖_F on facet e from cell c, for a field g(s).
    fn norm(&self, e: usize, c: usize, g: impl Fn(f64) -> Vector) -> f64 {
        let (rule, _) = self.rule(e);
        let sigma = self.rec.total(c);
        rule.iter()
            .map(|&(s, w)| {
                let (t, v) = (self.trace(e, c, &sigma, s), g(s));
                ((t[0] - v[0]).powi(2) + (t[1] - v[1]).powi(2)) * w
            })
            .sum::<f64>()
            .sqrt()
    }

    /// `worst` relative to max_F ‖σ_h n‖_F.
    fn relative(&self, worst: Worst) -> Worst {
        Worst { value: worst.value / self.scale, at: worst.at }
    }

    /// The midpoint of facet e.
    fn midpoint(&self, e: usize) -> Point {
        let [a, b] = self.topology.facets[e].map(|n| self.problem.mesh.points[n]);
        Segment::new(a, b).point(0.5)
    }

    fn continuity(&self) -> Worst {
        (0..self.topology.n_facets())
            .into_par_iter()
            .filter(|&e| self.topology.facet_cells[e][1] != NONE)
            .map(|e| {
                let [c1, c2] = self.topology.facet_cells[e];
                let sigma = self.rec.total(c2);
                Worst::default().max(self.norm(e, c1, |s| self.trace(e, c2, &sigma, s)), self.midpoint(e))
            })
            .reduce(Worst::default, Worst::larger)
    }

    /// ‖σ_h n − Π_F^p g_N‖_F on Neumann faces.
    fn neumann(&self) -> Worst {
        let mesh = &self.problem.mesh;
        let mut worst = Worst::default();
        for f in 0..mesh.n_facets() {
            let tag = mesh.facet_tags[f];
            let fixed = self.problem.dirichlet.iter().any(|bc| bc.tag == tag);
            let Some(bc) = self.problem.neumann.iter().find(|bc| bc.tag == tag) else { continue };
            if fixed {
                continue;
            }
            let e = self.topology.tagged_facet[f];
            let c = self.topology.tagged_cell(f);
            let (_, ends) = self.rule(e);
            let length = distance(ends[0], ends[1]);
            let rule: Vec<(f64, f64)> =
                traction_rule(&bc.traction, ends, mesh.order).into_iter().map(|(s, w)| (s, w * length)).collect();
            let normal = self.topology.outward_normal(mesh, f);
            let projection = FaceProjection::new(mesh.order, &rule);
            // σ_h n along the edge's own normal, which is ± the outward normal
            let [a, b] = ends;
            let own = [(b[1] - a[1]), -(b[0] - a[0])];
            let sign = if dot(own, normal) > 0.0 { 1.0 } else { -1.0 };
            let sigma = self.rec.total(c);
            let mut defect = 0.0;
            for i in 0..D {
                let w: Vec<f64> = rule.iter().map(|&(s, _)| sign * self.trace(e, c, &sigma, s)[i]).collect();
                let g: Vec<f64> = rule
                    .iter()
                    .map(|&(s, _)| bc.traction.at([a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])], normal)[i])
                    .collect();
                defect += projection.trace_defect(&w, &g).powi(2);
            }
            worst = worst.max(defect.sqrt(), self.midpoint(e));
        }
        worst
    }
}

/// Reference coordinates of the point x_a + s (x_b − x_a) of the edge (a, b) of a cell with
/// the nodes `cell`, from the reference vertices of a and b: exact, where J⁻¹(x − x₀) loses
/// ε |x| / h_T relative to a cell of size h_T far from the origin.
fn reference_point(cell: &[usize], a: usize, b: usize, s: f64) -> Point {
    let (xa, xb) = (lagrange::reference_vertex(cell, a), lagrange::reference_vertex(cell, b));
    [xa[0] + s * (xb[0] - xa[0]), xa[1] + s * (xb[1] - xa[1])]
}

/// max over the facets of Γ_C (on both sides of a joint) and i = 1, 2, 3 of
/// ‖σ_hi n − Π_F^p t_i‖_F, t_i the facet's datum ([`super::facets::ContactFacet::samples`]).
fn contact_traces(problem: &Problem, rec: &Reconstruction, facets: &[SampledFacet]) -> Worst {
    let mesh = &problem.mesh;
    let mut worst = Worst::default();
    for SampledFacet { facet, samples } in facets {
        let rule: Vec<(f64, f64)> = samples.iter().map(|p| (p.r, p.weight)).collect();
        let projection = FaceProjection::new(mesh.order, &rule);
        for i in 0..3 {
            let mut defect = 0.0;
            for j in 0..D {
                let w: Vec<f64> = samples
                    .iter()
                    .map(|p| {
                        let tau = afw::evaluate(mesh.order, rec.cell(i, facet.cell), facet.reference_point(mesh, p.r));
                        tau[2 * j] * facet.normal[0] + tau[2 * j + 1] * facet.normal[1]
                    })
                    .collect();
                let g: Vec<f64> = samples.iter().map(|p| p.t[i][j]).collect();
                defect += projection.trace_defect(&w, &g).powi(2);
            }
            worst = worst.max(defect.sqrt(), facet.midpoint(mesh));
        }
    }
    worst
}
