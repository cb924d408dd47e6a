//! Numerical stability stress test of the Nitsche contact solver and the linear solver.
//!
//! What it shows: how the Newton/LU solve of Scene A (dam on a rigid foundation, Nitsche
//! contact on the base) behaves when one factor at a time moves away from a base case:
//! the Nitsche parameter γ₀ (1 … 10⁴) and the variant θ, the regularisation δ over eight
//! decades (S·10⁻¹ … S·10⁻⁸, S the stress scale of the loads), Poisson's ratio up to 0.499,
//! the mesh size over three levels, a randomly distorted mesh (the manufactured Signorini
//! problem V3 on the unit square, interior nodes moved by up to 35 % of h, fixed seed) and
//! SI against dimensionless units. Scene B (dam bonded to a deformable rock) measures the
//! material contrast up to 10³ through the sparse Cholesky solve, checked by its residual and
//! by an independent LU solve. Every combination reports its Newton steps, final relative
//! residual, status (or the solver's own error text), a Hager–Higham estimate of the 1-norm
//! condition number of the final Jacobian, and the difference to a reference answer.
//!
//! Run: `cargo run --release --example stability -- [--quick] [OUTPUT.md]`
//! (default `out/stability.md`; the CSV goes next to it as `out/stability.csv`). `--quick`
//! runs a P1, coarse-mesh subset in seconds. The exit status is non-zero if any combination
//! panicked or produced a NaN/inf.
//!
//! Key number: the count of combinations that converged, stopped with a reason, or missed
//! their reference, printed on the last line ("N combinations: …").

use anyhow::{Context, Result};
use damfem::contact::nitsche::NitscheParameters;
use damfem::contact::projection::Smoothing;
use damfem::contact::{continuation, ContactJoint, ContactProblem};
use damfem::elasticity::stress::cell_mean_stress;
use damfem::elasticity::{BodyForce, Material, Problem, Traction};
use damfem::fem::lagrange;
use damfem::fem::norms::errors;
use damfem::fem::sparse::SparsePattern;
use damfem::io::atomic::write_output;
use damfem::io::gmsh::{mesh_geo, MeshOptions};
use damfem::mesh::structured::{unit_square, BOTTOM};
use damfem::mesh::Mesh;
use damfem::scene::Scene;
use damfem::solve::{Cholesky, NewtonError, NewtonOptions, NonlinearSystem, SparseLu};
use std::collections::HashMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// Water density ρ_w, gravity g and dam height H of Scene A: σ₀ = ρ_w g H.
const RHO_W: f64 = 1000.0;
const GRAVITY: f64 = 9.81;
const DAM_HEIGHT: f64 = 50.0;

/// Probe points of the dams: upstream and downstream crest corners, heel, a point of the
/// contact base (Scene A) or the toe (Scene B), and an interior point.
const PROBES_A: [[f64; 2]; 5] = [[0.0, 50.0], [5.0, 50.0], [0.0, 0.0], [16.0, 0.0], [20.0, 20.0]];
const PROBES_B: [[f64; 2]; 5] = [[0.0, 50.0], [5.0, 50.0], [0.0, 0.0], [40.0, 0.0], [20.0, -25.0]];
const PROBES_V3: [[f64; 2]; 5] = [[1.0, 1.0], [0.5, 1.0], [1.0, 0.0], [0.75, 0.0], [0.25, 0.5]];

/// Seed of the mesh distortion.
const SEED: u64 = 20240611;

/// Which values each factor takes.
#[derive(Debug, Clone)]
pub struct Plan {
    pub quick: bool,
    /// Degree and gmsh size factor of the base case (Scene A).
    pub order: usize,
    pub size: f64,
    pub gamma0: Vec<f64>,
    /// (θ, γ₀) pairs besides the base θ = 0.
    pub theta: Vec<(f64, f64)>,
    /// δ = S·10^−k for these k, solved directly from zero.
    pub delta_exponents: Vec<i32>,
    /// δ = S·10^−k reached by continuation from S·10⁻¹.
    pub continuation_exponents: Vec<i32>,
    /// Also δ = 0 (plain projection, semismooth Newton).
    pub semismooth: bool,
    pub nu: Vec<f64>,
    pub nu_orders: Vec<usize>,
    /// Degree and size factor of the reference solution at each ν.
    pub nu_reference: (usize, f64),
    /// γ₀ of an extra row at the largest ν (γ scaled up with the bulk modulus).
    pub nu_gamma0: f64,
    /// Size factors; the reference is the finest at the highest degree.
    pub sizes: Vec<f64>,
    pub size_orders: Vec<usize>,
    /// V3 on an n × n structured mesh, interior nodes moved by up to fraction · h.
    pub v3_n: usize,
    pub v3_orders: Vec<usize>,
    pub distortions: Vec<f64>,
    /// Scene B: the rock's E is divided by these factors.
    pub rock_divisors: Vec<f64>,
    pub scene_b: (usize, f64),
}

impl Plan {
    /// The full sweep (P2 base) or the quick subset (P1, coarse meshes, fewer values).
    pub fn new(quick: bool) -> Plan {
        if quick {
            Plan {
                quick,
                order: 1,
                size: 2.0,
                gamma0: vec![1.0, 1e2, 1e4],
                theta: vec![(1.0, 1.0), (-1.0, 1.0)],
                delta_exponents: vec![1, 4, 8],
                continuation_exponents: vec![8],
                semismooth: false,
                nu: vec![0.3, 0.499],
                nu_orders: vec![1],
                nu_reference: (2, 2.0),
                nu_gamma0: 1e4,
                sizes: vec![4.0, 2.0, 1.0],
                size_orders: vec![1],
                v3_n: 8,
                v3_orders: vec![1],
                distortions: vec![0.0, 0.35],
                rock_divisors: vec![1.0, 1e3],
                scene_b: (1, 2.0),
            }
        } else {
            Plan {
                quick,
                order: 2,
                size: 1.0,
                gamma0: vec![1.0, 1e1, 1e2, 1e3, 1e4],
                theta: vec![(1.0, 1.0), (1.0, 1e2), (-1.0, 1.0), (-1.0, 1e2)],
                delta_exponents: (1..=8).collect(),
                continuation_exponents: vec![8],
                semismooth: true,
                nu: vec![0.0, 0.3, 0.49, 0.499],
                nu_orders: vec![1, 2],
                nu_reference: (2, 0.5),
                nu_gamma0: 1e4,
                sizes: vec![2.0, 1.0, 0.5],
                size_orders: vec![1, 2],
                v3_n: 16,
                v3_orders: vec![1, 2],
                distortions: vec![0.0, 0.2, 0.35],
                rock_divisors: vec![1.0, 1e1, 1e2, 1e3],
                scene_b: (2, 1.0),
            }
        }
    }
}

/// How a combination ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Newton reached ‖F‖ ≤ rtol·‖b‖, or the Cholesky solve succeeded.
    Converged,
    /// Newton stopped because the increment reached round-off, above rtol.
    Stagnated,
    /// The solver returned an error (its text is the reason).
    Failed,
    /// The code panicked: a failure of the example.
    Panicked,
}

impl Status {
    pub fn name(&self) -> &'static str {
        match self {
            Status::Converged => "converged",
            Status::Stagnated => "stagnated",
            Status::Failed => "failed",
            Status::Panicked => "PANIC",
        }
    }
}

/// What a reference comparison allows.
#[derive(Debug, Clone, Copy)]
pub struct Tolerance {
    /// On max(probe difference / max probe |u_ref|, |max|u| − max|u_ref|| / max|u_ref|).
    pub u: f64,
    /// On |L_c − L_c,ref| [m], when both have a contact zone.
    pub length: Option<f64>,
}

/// The computed displacement and the quantities compared, in the original units.
#[derive(Debug, Clone)]
pub struct Solution {
    /// Nodal displacements.
    pub u: Vec<[f64; 2]>,
    /// u at the probe points (None if a probe lies outside the mesh).
    pub probes: Vec<Option<[f64; 2]>>,
    pub max_u: f64,
    pub contact_length: Option<f64>,
    /// Length of the longest contact face.
    pub contact_face: Option<f64>,
    /// First NaN/inf found in u, the stresses or the contact states, if any.
    pub nonfinite: Option<String>,
}

/// One combination of the sweep.
#[derive(Debug, Clone)]
pub struct Row {
    pub group: String,
    pub case: String,
    pub order: usize,
    pub dofs: usize,
    pub iterations: Option<usize>,
    pub rel_residual: Option<f64>,
    /// Smallest relative residual of a Newton run that ran out of steps.
    pub min_rel_residual: Option<f64>,
    pub status: Status,
    /// The solver's message when it did not converge (full text).
    pub reason: String,
    /// A shortened reason for the markdown table.
    pub reason_short: String,
    /// Hager–Higham estimate of κ₁ of the final Jacobian (or stiffness matrix).
    pub cond: Option<f64>,
    pub solution: Option<Solution>,
    /// Differences to the reference: displacement (relative) and contact length [m].
    pub du: Option<f64>,
    pub dl: Option<f64>,
    pub tolerance: Option<Tolerance>,
    /// None: no comparison (reference row, or no answer).
    pub matches: Option<bool>,
    pub is_reference: bool,
    /// A retry of the combination in the row above.
    pub is_retry: bool,
    pub seconds: f64,
    pub note: String,
}

impl Row {
    fn new(group: &str, case: String, order: usize) -> Row {
        Row {
            group: group.into(),
            case,
            order,
            dofs: 0,
            iterations: None,
            rel_residual: None,
            min_rel_residual: None,
            status: Status::Failed,
            reason: String::new(),
            reason_short: String::new(),
            cond: None,
            solution: None,
            du: None,
            dl: None,
            tolerance: None,
            matches: None,
            is_reference: false,
            is_retry: false,
            seconds: 0.0,
            note: String::new(),
        }
    }

    /// Whether the answer is free of NaN/inf (None: there is no answer).
    pub fn finite(&self) -> Option<bool> {
        self.solution.as_ref().map(|s| s.nonfinite.is_none() && self.rel_residual.is_none_or(f64::is_finite))
    }

    /// Compares with `reference` under `tolerance`.
    fn compare(&mut self, reference: Option<&Solution>, tolerance: Tolerance) {
        self.tolerance = Some(tolerance);
        let (Some(s), Some(r)) = (&self.solution, reference) else { return };
        let scale = r.probes.iter().flatten().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
        let probe = s
            .probes
            .iter()
            .zip(&r.probes)
            .filter_map(|(a, b)| Some((a.as_ref()?, b.as_ref()?)))
            .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]) / scale)
            .fold(0.0, f64::max);
        let du = probe.max((s.max_u - r.max_u).abs() / r.max_u);
        self.du = Some(du);
        self.dl = match (s.contact_length, r.contact_length) {
            (Some(a), Some(b)) => Some((a - b).abs()),
            _ => None,
        };
        let length_ok = match (self.dl, tolerance.length) {
            (Some(d), Some(t)) => d <= t,
            _ => true,
        };
        self.matches = Some(du <= tolerance.u && length_ok);
    }
}

// ---------------------------------------------------------------------------------------
// Problems

/// Path of a repository file.
fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// gmsh meshes by (scene, degree, size factor), meshed once each.
#[derive(Default)]
struct Meshes {
    cache: HashMap<(PathBuf, usize, u64), Mesh>,
}

impl Meshes {
    fn get(&mut self, scene: &Scene, order: usize, size: f64) -> Result<Mesh> {
        let key = (scene.geometry.clone(), order, size.to_bits());
        if let Some(mesh) = self.cache.get(&key) {
            return Ok(mesh.clone());
        }
        let options = MeshOptions {
            order,
            size_factor: size,
            size_min: scene.mesh.size_min,
            size_max: scene.mesh.size_max,
            algorithm: scene.mesh.algorithm,
        };
        let mesh = mesh_geo(&scene.geometry, &options, false, false)
            .with_context(|| format!("meshing {}", scene.geometry.display()))?;
        self.cache.insert(key, mesh.clone());
        Ok(mesh)
    }
}

/// Scene A with Poisson's ratio `nu` (None: as given) on a mesh of degree `order`.
fn scene_a(meshes: &mut Meshes, order: usize, size: f64, nu: Option<f64>) -> Result<(Problem, Vec<i32>)> {
    let mut scene = Scene::load(&repo("geo/scene_a.toml"))?;
    if let Some(nu) = nu {
        scene.materials.values_mut().for_each(|m| m.poisson = nu);
    }
    let mesh = meshes.get(&scene, order, size)?;
    let (problem, joint) = scene.problem(mesh)?;
    Ok((problem, joint.map(|j| j.tags).unwrap_or_default()))
}

/// Scene B with the rock's Young's modulus divided by `divisor`.
fn scene_b(meshes: &mut Meshes, order: usize, size: f64, divisor: f64) -> Result<Problem> {
    let mut scene = Scene::load(&repo("geo/scene_b.toml"))?;
    let rock = scene.materials.get_mut("rock").context("scene B has no material 'rock'")?;
    rock.young /= divisor;
    let mesh = meshes.get(&scene, order, size)?;
    Ok(scene.problem(mesh)?.0)
}

/// The same problem in units where stresses are divided by `sigma0` and lengths by `length`:
/// x' = x/L, u' = u/L, E' = E/σ₀, g_N' = g_N/σ₀, f' = f L/σ₀. Hydrostatic pressure
/// ρ_w g (H_w − y) becomes (ρ_w L/σ₀) g (H_w/L − y'), self-weight ρ g becomes (ρ L/σ₀) g.
/// The displacement times L must equal the original one.
fn rescale(problem: &Problem, sigma0: f64, length: f64) -> Problem {
    let mut scaled = problem.clone();
    for p in &mut scaled.mesh.points {
        *p = [p[0] / length, p[1] / length];
    }
    for m in &mut scaled.materials {
        *m = Material { young: m.young / sigma0, poisson: m.poisson, density: m.density * length / sigma0 };
    }
    for bc in &mut scaled.neumann {
        bc.traction = match bc.traction.clone() {
            Traction::Constant(t) => Traction::Constant([t[0] / sigma0, t[1] / sigma0]),
            Traction::Hydrostatic { density, gravity, level } => {
                Traction::Hydrostatic { density: density * length / sigma0, gravity, level: level / length }
            }
            Traction::Field(f) => Traction::Field(Arc::new(move |x| {
                let t = f([x[0] * length, x[1] * length]);
                [t[0] / sigma0, t[1] / sigma0]
            })),
        };
    }
    if let BodyForce::Field(f) = scaled.body_force.clone() {
        scaled.body_force = BodyForce::Field(Arc::new(move |x| {
            let v = f([x[0] * length, x[1] * length]);
            [v[0] * length / sigma0, v[1] * length / sigma0]
        }));
    }
    for bc in &mut scaled.dirichlet {
        let value = bc.value.clone();
        bc.value = Arc::new(move |x| {
            let g = value([x[0] * length, x[1] * length]);
            [g[0] / length, g[1] / length]
        });
    }
    scaled
}

/// V3: manufactured Signorini solution (docs/method.md §7), shared with the tests.
#[path = "../tests/common/v3.rs"]
mod v3;

/// splitmix64: a small deterministic generator for the distortion.
struct SplitMix(u64);

impl SplitMix {
    /// Uniform in [0, 1).
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z ^ (z >> 31)) as f64 / 2f64.powi(64)
    }
}

/// Moves every interior vertex by a random vector of length up to `fraction · h` (uniform
/// direction and radius), then puts P2 midpoints back at the middle of their edges. On the
/// diagonal-split grid, fraction < 1/(2√2) ≈ 0.354 keeps every triangle positively oriented.
fn distort(mesh: &mut Mesh, fraction: f64, h: f64, seed: u64) {
    let mut on_boundary = vec![false; mesh.n_points()];
    for &n in &mesh.facet_nodes {
        on_boundary[n] = true;
    }
    let mut vertices: Vec<usize> = (0..mesh.n_cells()).flat_map(|c| mesh.cell(c)[..3].to_vec()).collect();
    vertices.sort_unstable();
    vertices.dedup();
    let mut rng = SplitMix(seed);
    for &v in vertices.iter().filter(|&&v| !on_boundary[v]) {
        let (r, angle) = (fraction * h * rng.next(), 2.0 * std::f64::consts::PI * rng.next());
        let p = mesh.points[v];
        mesh.points[v] = [p[0] + r * angle.cos(), p[1] + r * angle.sin()];
    }
    if mesh.order == 2 {
        for c in 0..mesh.n_cells() {
            let cell = mesh.cell(c).to_vec();
            for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                let (a, b) = (mesh.points[cell[i]], mesh.points[cell[j]]);
                mesh.points[cell[3 + k]] = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
            }
        }
    }
}

/// Smallest interior angle over the cells, in degrees, and the smallest signed area.
fn mesh_quality(mesh: &Mesh) -> (f64, f64) {
    let mut min_angle = 180.0f64;
    let mut min_area = f64::INFINITY;
    for c in 0..mesh.n_cells() {
        let v = mesh.cell_vertices(c);
        min_area = min_area.min(mesh.cell_area(c));
        for i in 0..3 {
            let (a, b, d) = (v[i], v[(i + 1) % 3], v[(i + 2) % 3]);
            let (e, f) = ([b[0] - a[0], b[1] - a[1]], [d[0] - a[0], d[1] - a[1]]);
            let cos = (e[0] * f[0] + e[1] * f[1]) / (e[0].hypot(e[1]) * f[0].hypot(f[1]));
            min_angle = min_angle.min(cos.clamp(-1.0, 1.0).acos().to_degrees());
        }
    }
    (min_angle, min_area)
}

/// V3 on an n × n grid of degree `order`, interior vertices moved by up to `fraction · h`.
fn v3_problem(n: usize, order: usize, fraction: f64) -> Problem {
    let mut mesh = unit_square(n, order);
    if fraction > 0.0 {
        distort(&mut mesh, fraction, 1.0 / n as f64, SEED);
    }
    v3::problem(mesh)
}

// ---------------------------------------------------------------------------------------
// Solves and checks

/// u_h at point `p` (None outside the mesh).
fn evaluate_at(mesh: &Mesh, u: &[[f64; 2]], p: [f64; 2]) -> Option<[f64; 2]> {
    let nb = lagrange::n_basis(mesh.order);
    let mut phi = [0.0; 6];
    for c in 0..mesh.n_cells() {
        let [a, b, d] = mesh.cell_vertices(c);
        let j = [[b[0] - a[0], d[0] - a[0]], [b[1] - a[1], d[1] - a[1]]];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let r = [p[0] - a[0], p[1] - a[1]];
        let xi = [(r[0] * j[1][1] - j[0][1] * r[1]) / det, (j[0][0] * r[1] - j[1][0] * r[0]) / det];
        let tol = 1e-9;
        if xi[0] >= -tol && xi[1] >= -tol && xi[0] + xi[1] <= 1.0 + tol {
            lagrange::values(mesh.order, xi, &mut phi[..nb]);
            let nodes = mesh.cell(c);
            let mut v = [0.0; 2];
            for (i, &n) in nodes.iter().enumerate() {
                v[0] += phi[i] * u[n][0];
                v[1] += phi[i] * u[n][1];
            }
            return Some(v);
        }
    }
    None
}

/// The first non-finite entry of u or of the cell stresses, if any.
fn nonfinite_fields(problem: &Problem, u: &[[f64; 2]]) -> Option<String> {
    if let Some(n) = u.iter().position(|v| !(v[0].is_finite() && v[1].is_finite())) {
        return Some(format!("u at node {n} = {:?}", u[n]));
    }
    let sigma = cell_mean_stress(problem, u);
    sigma.iter().position(|s| !s.iter().all(|v| v.is_finite())).map(|c| format!("stress in cell {c} = {:?}", sigma[c]))
}

/// The solution in the original units (displacements times `length`), with its checks.
fn solution(problem: &Problem, u: Vec<[f64; 2]>, length: f64, probes: &[[f64; 2]]) -> Solution {
    let nonfinite = nonfinite_fields(problem, &u);
    let u: Vec<[f64; 2]> = u.into_iter().map(|v| [v[0] * length, v[1] * length]).collect();
    let points: Vec<[f64; 2]> = probes.iter().map(|p| [p[0] / length, p[1] / length]).collect();
    Solution {
        probes: points.iter().map(|&p| evaluate_at(&problem.mesh, &u, p)).collect(),
        max_u: u.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max),
        u,
        contact_length: None,
        contact_face: None,
        nonfinite,
    }
}

/// ‖A‖₁ of a matrix on `pattern`.
fn norm_1(pattern: &SparsePattern, values: &[f64]) -> f64 {
    let col_ptr = pattern.symbolic().col_ptr();
    (0..pattern.n())
        .map(|c| values[col_ptr[c]..col_ptr[c + 1]].iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Hager–Higham (LAPACK dlacon) estimate of κ₁(A) = ‖A‖₁ ‖A⁻¹‖₁, a lower bound that is
/// almost always within a factor 3, from a few solves with A and Aᵀ. None if A is singular.
pub fn condition_1(pattern: &SparsePattern, values: &[f64]) -> Option<f64> {
    let n = pattern.n();
    if n == 0 {
        return None;
    }
    let symbolic = SparseLu::analyse(pattern).ok()?;
    let lu = symbolic.factor(pattern, values).ok()?;
    let solve = |rhs: &[f64], transpose: bool| if transpose { lu.solve_transpose(rhs) } else { lu.solve(rhs) };
    let norm1 = |v: &[f64]| v.iter().map(|a| a.abs()).sum::<f64>();
    let mut x = vec![1.0 / n as f64; n];
    let mut estimate = 0.0;
    for iteration in 0..5 {
        let y = solve(&x, false);
        let new = norm1(&y);
        if iteration > 0 && new <= estimate {
            break;
        }
        estimate = new;
        let signs: Vec<f64> = y.iter().map(|v| if *v >= 0.0 { 1.0 } else { -1.0 }).collect();
        let z = solve(&signs, true);
        let (j, z_max) = z.iter().enumerate().fold((0, 0.0), |m, (i, v)| if v.abs() > m.1 { (i, v.abs()) } else { m });
        let ztx: f64 = z.iter().zip(&x).map(|(a, b)| a * b).sum();
        if z_max <= ztx {
            break;
        }
        x.fill(0.0);
        x[j] = 1.0;
    }
    // Higham's alternative vector b_i = (−1)^i (1 + i/(n−1)) guards against bad cases
    let b: Vec<f64> = (0..n)
        .map(|i| {
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            sign * (1.0 + i as f64 / (n.max(2) - 1) as f64)
        })
        .collect();
    let alternative = 2.0 * norm1(&solve(&b, false)) / (3.0 * n as f64);
    let estimate = estimate.max(alternative);
    estimate.is_finite().then_some(norm_1(pattern, values) * estimate)
}

/// Nitsche and regularisation settings of one contact solve.
#[derive(Debug, Clone, Copy)]
pub struct Knobs {
    pub gamma0: f64,
    pub theta: f64,
    /// δ = delta · S (0: plain projection).
    pub delta: f64,
    /// First δ of the continuation path as a multiple of S (None: direct solve at δ).
    pub start: Option<f64>,
    /// Newton's relative residual tolerance and step limit.
    pub rtol: f64,
    pub max_iter: usize,
}

impl Default for Knobs {
    /// The CLI's defaults: γ₀ = 100, θ = 0, δ = 10⁻⁴ S, no continuation, rtol 10⁻¹⁰,
    /// 50 Newton steps.
    fn default() -> Self {
        Knobs { gamma0: 100.0, theta: 0.0, delta: 1e-4, start: None, rtol: 1e-10, max_iter: 50 }
    }
}

/// Steps, last and smallest relative residual and a short text of a Newton error.
fn describe_error(error: &NewtonError) -> (Option<usize>, Option<f64>, Option<f64>, String) {
    match error {
        NewtonError::NotConverged { history, scale } => {
            let rel: Vec<f64> = history.iter().map(|it| it.residual / scale).collect();
            let tail: Vec<String> = rel.iter().rev().take(3).rev().map(|r| format!("{r:.1e}")).collect();
            let min = rel.iter().copied().fold(f64::INFINITY, f64::min);
            let short = format!(
                "Newton did not converge in {} steps: last relative residuals {} (min {min:.1e})",
                history.len(),
                tail.join(", ")
            );
            (Some(history.len()), rel.last().copied(), Some(min), short)
        }
        NewtonError::NonFinite { step } => (Some(*step), None, None, error.to_string()),
        NewtonError::Solve { step, .. } => (Some(*step), None, None, error.to_string()),
    }
}

/// Solves the contact problem on the facets `tags` of `problem`; `length` scales the
/// displacement back to the original units.
fn contact_row(row: &mut Row, problem: &Problem, tags: &[i32], knobs: Knobs, length: f64, probes: &[[f64; 2]]) {
    let disc = problem.discretise();
    row.dofs = disc.dofs.n_free;
    let scale = problem.stress_scale(&disc.topology);
    let delta = knobs.delta * scale;
    let start = knobs.start.map_or(delta, |s| (s * scale).max(delta));
    let parameters = NitscheParameters { gamma0: knobs.gamma0, theta: knobs.theta, ..Default::default() };
    let joint = ContactJoint::frictionless(tags.to_vec(), parameters);
    let mut contact = ContactProblem::new(problem, &disc, &joint, Smoothing { delta });
    let contact_face = contact.nitsche.faces.iter().map(|f| f.length).fold(0.0, f64::max) * length;
    let options = NewtonOptions { rtol: knobs.rtol, max_iter: knobs.max_iter, ..NewtonOptions::default() };
    match continuation(&mut contact, delta, start, vec![0.0; disc.dofs.n_free], &options) {
        Ok((x, stages)) => {
            let last = &stages.last().expect("at least one stage").report;
            let rel = last.residual / last.scale;
            row.iterations = Some(stages.iter().map(|s| s.report.iterations.len()).sum());
            row.rel_residual = Some(rel);
            if rel <= options.rtol {
                row.status = Status::Converged;
            } else {
                row.status = Status::Stagnated;
                row.reason = format!(
                    "the Newton increment reached round-off (‖Δ‖ ≤ 1e-13‖x‖) at relative residual {rel:.2e} > rtol {:.0e}",
                    options.rtol
                );
                row.reason_short = row.reason.clone();
            }
            if stages.len() > 1 {
                let per: Vec<String> = stages.iter().map(|s| s.report.iterations.len().to_string()).collect();
                row.note = format!("{} stages, steps {}", stages.len(), per.join("+"));
            }
            // the Jacobian at the answer, with the projection of the last stage
            let mut residual = vec![0.0; disc.dofs.n_free];
            let mut jacobian = vec![0.0; disc.pattern.nnz()];
            contact.evaluate(&x, &mut residual, Some(&mut jacobian));
            row.cond = condition_1(&disc.pattern, &jacobian);
            let faces = contact.face_states(&x);
            let mut sol = solution(problem, problem.displacement(&disc, &x), length, probes);
            let bad_face = faces.iter().position(|f| {
                ![f.pressure, f.normal_displacement, f.contact_length, f.regularisation_error]
                    .iter()
                    .all(|v| v.is_finite())
            });
            if let (None, Some(k)) = (&sol.nonfinite, bad_face) {
                sol.nonfinite = Some(format!("contact face {k}: {:?}", faces[k]));
            }
            sol.contact_length = Some(faces.iter().map(|f| f.contact_length).sum::<f64>() * length);
            sol.contact_face = Some(contact_face);
            row.solution = Some(sol);
        }
        Err(error) => {
            let (steps, rel, min, short) = describe_error(&error);
            row.iterations = steps;
            row.rel_residual = rel;
            row.min_rel_residual = min;
            row.status = Status::Failed;
            row.reason = error.to_string();
            row.reason_short = short;
            if start > delta {
                row.note = "steps and residual of the failing continuation stage".into();
            }
        }
    }
}

/// Linear solve of `problem` by sparse Cholesky, checked by its residual and by an LU
/// solve of the same system; returns the LU answer as the reference.
fn linear_row(row: &mut Row, problem: &Problem, probes: &[[f64; 2]]) -> Option<Solution> {
    let disc = problem.discretise();
    row.dofs = disc.dofs.n_free;
    let system = problem.assemble(&disc);
    let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
    let residual = |x: &[f64]| {
        let mut r = vec![0.0; x.len()];
        disc.pattern.multiply(&system.values, x, &mut r);
        let r: Vec<f64> = r.iter().zip(&system.rhs).map(|(a, b)| a - b).collect();
        norm(&r) / norm(&system.rhs)
    };
    row.cond = condition_1(&disc.pattern, &system.values);
    let lu = SparseLu::analyse(&disc.pattern)
        .and_then(|lu| lu.factor(&disc.pattern, &system.values).map(|f| f.solve(&system.rhs)));
    let reference = match &lu {
        Ok(x) => {
            row.note = format!("LU residual {:.1e}", residual(x));
            Some(solution(problem, problem.displacement(&disc, x), 1.0, probes))
        }
        Err(e) => {
            row.note = format!("LU failed: {e}");
            None
        }
    };
    match Cholesky::analyse(&disc.pattern).and_then(|c| c.solve(&disc.pattern, &system.values, &system.rhs)) {
        Ok(x) => {
            row.status = Status::Converged;
            row.iterations = None;
            row.rel_residual = Some(residual(&x));
            row.solution = Some(solution(problem, problem.displacement(&disc, &x), 1.0, probes));
        }
        Err(e) => {
            row.status = Status::Failed;
            row.reason = format!("Cholesky: {e}");
            row.reason_short = row.reason.clone();
        }
    }
    reference
}

/// Runs `body` on a fresh row, timing it; a panic or an error becomes the row's reason.
fn run_row(group: &str, case: String, order: usize, body: impl FnOnce(&mut Row) -> Result<()>) -> Row {
    let mut row = Row::new(group, case, order);
    let start = Instant::now();
    let outcome = catch_unwind(AssertUnwindSafe(|| body(&mut row)));
    row.seconds = start.elapsed().as_secs_f64();
    match outcome {
        Ok(Ok(())) => {}
        Ok(Err(e)) => {
            row.status = Status::Failed;
            row.reason = format!("{e:#}");
            row.reason_short = row.reason.clone();
        }
        Err(panic) => {
            let message = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
            row.status = Status::Panicked;
            row.reason = format!("panic: {message}");
            row.reason_short = row.reason.clone();
        }
    }
    eprintln!("  {:<10} {:<44} {:<9} {:>6.2} s", row.group, row.case, row.status.name(), row.seconds);
    row
}

// ---------------------------------------------------------------------------------------
// The sweep

/// Parameter sweeps on the base mesh: displacement within 1 %, contact length within two
/// contact faces of the base answer.
fn parameter_tolerance(reference: Option<&Solution>) -> Tolerance {
    Tolerance { u: 1e-2, length: reference.and_then(|r| r.contact_face).map(|h| 2.0 * h) }
}

/// Discretisation changes (mesh, degree, distortion): 5 % and two contact faces of the
/// coarser mesh.
fn discretisation_tolerance(row: &Row, reference: Option<&Solution>) -> Tolerance {
    let face = row.solution.as_ref().and_then(|s| s.contact_face).or(reference.and_then(|r| r.contact_face));
    Tolerance { u: 5e-2, length: face.map(|h| 2.0 * h) }
}

/// Builds a contact problem and its contact tags.
type Build<'a> = &'a dyn Fn(&mut Meshes) -> Result<(Problem, Vec<i32>)>;

/// One contact combination and, if Newton ran out of steps, retries until one succeeds:
/// with rtol 10⁻⁸ when the residual had come below 10⁻⁸ (a round-off floor); otherwise by
/// δ-continuation from 10⁻¹ S, then directly with 200 Newton steps instead of 50. The last
/// row is the combination's answer. `length` scales u back to metres.
#[allow(clippy::too_many_arguments)]
fn contact_rows(
    meshes: &mut Meshes,
    group: &str,
    case: &str,
    order: usize,
    knobs: Knobs,
    length: f64,
    probes: &[[f64; 2]],
    build: Build,
) -> Vec<Row> {
    let mut solve = |case: String, knobs: Knobs| {
        run_row(group, case, order, |row| {
            let (problem, tags) = build(meshes)?;
            contact_row(row, &problem, &tags, knobs, length, probes);
            Ok(())
        })
    };
    let first = solve(case.to_string(), knobs);
    let retries = match (first.status, first.min_rel_residual) {
        (Status::Failed, Some(min)) if min <= 1e-8 && knobs.rtol < 1e-8 => {
            vec![("rtol 1e-8", Knobs { rtol: 1e-8, ..knobs })]
        }
        (Status::Failed, Some(_)) => {
            let mut list = Vec::new();
            if knobs.start.is_none() {
                list.push(("δ-continuation from 1e-1·S", Knobs { start: Some(0.1), ..knobs }));
            }
            list.push(("200 Newton steps", Knobs { max_iter: 200, ..knobs }));
            list
        }
        _ => Vec::new(),
    };
    let mut rows = vec![first];
    for (what, knobs) in retries {
        let mut row = solve(format!("{case} ↳ retry: {what}"), knobs);
        row.is_retry = true;
        let done = row.status != Status::Failed || row.min_rel_residual.is_none();
        rows.push(row);
        if done {
            break;
        }
    }
    rows
}

/// The answer of a combination: the solution of its last row.
fn answer(rows: &[Row]) -> Option<Solution> {
    rows.last().and_then(|r| r.solution.clone())
}

/// Runs every combination of `plan`, in order: base, γ₀, θ, δ, ν, mesh size, distortion,
/// units, material contrast.
pub fn run(plan: &Plan) -> Vec<Row> {
    let mut meshes = Meshes::default();
    let mut rows = Vec::new();
    let (p, size) = (plan.order, plan.size);
    let base_build = |m: &mut Meshes| scene_a(m, p, size, None);

    // 1. Base case: Scene A, γ₀ = 100, θ = 0, δ = 10⁻⁴ S, direct Newton from zero
    let base_case = format!("Scene A P{p}, size {size}, γ₀=100, θ=0, δ=1e-4·S");
    let mut base = contact_rows(&mut meshes, "base", &base_case, p, Knobs::default(), 1.0, &PROBES_A, &base_build);
    base.iter_mut().for_each(|r| r.is_reference = true);
    let reference = answer(&base);
    rows.extend(base);
    let ptol = parameter_tolerance(reference.as_ref());
    let sweep = |meshes: &mut Meshes, rows: &mut Vec<Row>, group: &str, case: String, knobs: Knobs| {
        for mut row in contact_rows(meshes, group, &case, p, knobs, 1.0, &PROBES_A, &base_build) {
            row.compare(reference.as_ref(), ptol);
            rows.push(row);
        }
    };

    // 2. γ₀ sweep at θ = 0, then the θ variants at a small and the default γ₀
    for &gamma0 in &plan.gamma0 {
        sweep(&mut meshes, &mut rows, "gamma0", format!("γ₀ = {gamma0:.0e}"), Knobs { gamma0, ..Knobs::default() });
    }
    for &(theta, gamma0) in &plan.theta {
        let knobs = Knobs { gamma0, theta, ..Knobs::default() };
        sweep(&mut meshes, &mut rows, "theta", format!("θ = {theta}, γ₀ = {gamma0:.0e}"), knobs);
    }

    // 3. δ over eight decades, direct; the smallest also by continuation; δ = 0
    for &k in &plan.delta_exponents {
        let knobs = Knobs { delta: 10f64.powi(-k), ..Knobs::default() };
        sweep(&mut meshes, &mut rows, "delta", format!("δ = 1e-{k}·S"), knobs);
    }
    for &k in &plan.continuation_exponents {
        let knobs = Knobs { delta: 10f64.powi(-k), start: Some(0.1), ..Knobs::default() };
        sweep(&mut meshes, &mut rows, "delta", format!("δ = 1e-{k}·S, continuation from 1e-1·S"), knobs);
    }
    if plan.semismooth {
        sweep(&mut meshes, &mut rows, "delta", "δ = 0 (semismooth)".into(), Knobs { delta: 0.0, ..Knobs::default() });
    }

    // 4. Poisson's ratio towards incompressibility, against P2 on a finer mesh at the same ν
    let (ref_order, ref_size) = plan.nu_reference;
    let largest_nu = plan.nu.iter().copied().fold(f64::MIN, f64::max);
    for &nu in &plan.nu {
        let case = format!("ν = {nu}, reference P{ref_order} size {ref_size}");
        let build = |m: &mut Meshes| scene_a(m, ref_order, ref_size, Some(nu));
        let mut nu_rows = contact_rows(&mut meshes, "nu", &case, ref_order, Knobs::default(), 1.0, &PROBES_A, &build);
        nu_rows.iter_mut().for_each(|r| r.is_reference = true);
        let nu_reference = answer(&nu_rows);
        rows.extend(nu_rows);
        let mut variants: Vec<(usize, f64)> = plan.nu_orders.iter().map(|&o| (o, 100.0)).collect();
        if nu == largest_nu {
            variants.extend(plan.nu_orders.iter().map(|&o| (o, plan.nu_gamma0)));
        }
        for (order, gamma0) in variants {
            let case = format!("ν = {nu}, P{order} size {size}, γ₀ = {gamma0:.0e}");
            let build = |m: &mut Meshes| scene_a(m, order, size, Some(nu));
            let knobs = Knobs { gamma0, ..Knobs::default() };
            for mut row in contact_rows(&mut meshes, "nu", &case, order, knobs, 1.0, &PROBES_A, &build) {
                let tol = discretisation_tolerance(&row, nu_reference.as_ref());
                row.compare(nu_reference.as_ref(), tol);
                rows.push(row);
            }
        }
    }

    // 5. Mesh size over three levels; the reference is the finest mesh at the highest degree
    let finest = plan.sizes.iter().copied().fold(f64::INFINITY, f64::min);
    let top = plan.size_orders.iter().copied().max().unwrap_or(p);
    let mut mesh_rows = Vec::new();
    let mut mesh_reference = None;
    for &order in &plan.size_orders {
        for &s in &plan.sizes {
            let build = |m: &mut Meshes| scene_a(m, order, s, None);
            let case = format!("P{order}, size factor {s}");
            let mut combination =
                contact_rows(&mut meshes, "mesh", &case, order, Knobs::default(), 1.0, &PROBES_A, &build);
            if order == top && s == finest {
                combination.iter_mut().for_each(|r| r.is_reference = true);
                mesh_reference = answer(&combination);
            }
            mesh_rows.extend(combination);
        }
    }
    for mut row in mesh_rows {
        if !row.is_reference {
            let tol = discretisation_tolerance(&row, mesh_reference.as_ref());
            row.compare(mesh_reference.as_ref(), tol);
        }
        rows.push(row);
    }

    // 6. Distorted meshes: V3 with interior vertices moved by up to a fraction of h
    let n = plan.v3_n;
    for &order in &plan.v3_orders {
        let mut v3_reference = None;
        for &fraction in &plan.distortions {
            let case = format!("V3 {n}×{n} P{order}, vertices moved ≤ {:.0} % of h", 100.0 * fraction);
            let build = |_: &mut Meshes| Ok((v3_problem(n, order, fraction), vec![BOTTOM]));
            let mut combination =
                contact_rows(&mut meshes, "distorted", &case, order, Knobs::default(), 1.0, &PROBES_V3, &build);
            let problem = v3_problem(n, order, fraction);
            let (angle, area) = mesh_quality(&problem.mesh);
            for row in &mut combination {
                let h1 = row.solution.as_ref().map(|s| errors(&problem.mesh, &s.u, v3::u, v3::grad_u).1);
                let mut note = format!("min angle {angle:.1}°, min area {area:.1e}");
                if let Some(e) = h1 {
                    note += &format!(", |u−u_exact|_H1 = {e:.2e}");
                }
                row.note = if row.note.is_empty() { note } else { format!("{}; {note}", row.note) };
            }
            if fraction == 0.0 {
                combination.iter_mut().for_each(|r| r.is_reference = true);
                v3_reference = answer(&combination);
            } else {
                for row in &mut combination {
                    let tol = discretisation_tolerance(row, v3_reference.as_ref());
                    row.compare(v3_reference.as_ref(), tol);
                }
            }
            rows.extend(combination);
        }
    }

    // 7. SI units against dimensionless ones (σ₀ = ρ_w g H, lengths by H), scaled back
    let sigma0 = RHO_W * GRAVITY * DAM_HEIGHT;
    // L_c counts the Gauss points with P_γ < 0; in P1 one of them sits on P_γ = 0 exactly
    // (the middle of the piece |P_γ| < δ), so round-off may flip it: allow 10⁻⁵ L_c
    let length_tol = reference.as_ref().and_then(|r| r.contact_length).map(|l| 1e-5 * l.max(1.0));
    for (label, length) in [("stresses / σ₀ = ρ_w g H", 1.0), ("stresses / σ₀, lengths / H", DAM_HEIGHT)] {
        let build = |m: &mut Meshes| {
            let (problem, tags) = scene_a(m, p, size, None)?;
            Ok((rescale(&problem, sigma0, length), tags))
        };
        let case = format!("{label} (vs base in SI)");
        for mut row in contact_rows(&mut meshes, "units", &case, p, Knobs::default(), length, &PROBES_A, &build) {
            row.compare(reference.as_ref(), Tolerance { u: 1e-8, length: length_tol });
            rows.push(row);
        }
    }

    // 8. Material contrast: Scene B (bonded interface) with a softer rock, Cholesky vs LU
    let (b_order, b_size) = plan.scene_b;
    for &divisor in &plan.rock_divisors {
        let mut lu_reference = None;
        let case =
            format!("Scene B P{b_order} size {b_size}, E_rock / {divisor:.0e} (E_c/E_r = {:.1e})", 1.5 * divisor);
        let mut row = run_row("contrast", case, b_order, |row| {
            let problem = scene_b(&mut meshes, b_order, b_size, divisor)?;
            lu_reference = linear_row(row, &problem, &PROBES_B);
            Ok(())
        });
        row.compare(lu_reference.as_ref(), Tolerance { u: 1e-8, length: None });
        rows.push(row);
    }
    rows
}

// ---------------------------------------------------------------------------------------
// Tables

fn sci(v: Option<f64>) -> String {
    v.map_or("n/a".into(), |v| format!("{v:.2e}"))
}

/// The columns of both tables, as text.
fn cells(row: &Row) -> Vec<String> {
    let s = row.solution.as_ref();
    let tol = row.tolerance.map_or("—".into(), |t| match t.length {
        Some(l) => format!("{:.0e}; {l:.1e} m", t.u),
        None => format!("{:.0e}", t.u),
    });
    let matches = if row.is_reference {
        "ref".to_string()
    } else {
        row.matches.map_or("n/a".into(), |m| if m { "yes".into() } else { "NO".into() })
    };
    let finite = row.finite().map_or("n/a".into(), |f| if f { "yes".into() } else { "NO".into() });
    vec![
        row.group.clone(),
        row.case.clone(),
        row.dofs.to_string(),
        row.iterations.map_or(if row.group == "contrast" { "direct".into() } else { "n/a".into() }, |n| n.to_string()),
        sci(row.rel_residual),
        row.status.name().into(),
        sci(row.cond),
        sci(s.map(|s| s.max_u)),
        s.and_then(|s| s.contact_length).map_or("—".into(), |l| format!("{l:.3}")),
        sci(row.du),
        row.dl.map_or("—".into(), |d| format!("{d:.2e}")),
        tol,
        matches,
        finite,
        format!("{:.2}", row.seconds),
    ]
}

const HEADER: [&str; 17] = [
    "group",
    "case",
    "free dofs",
    "Newton steps",
    "final rel. residual",
    "status",
    "cond₁ est.",
    "max |u| [m]",
    "contact length [m]",
    "Δu (rel.)",
    "ΔL_c [m]",
    "tol (u; L_c)",
    "matches ref",
    "finite",
    "time [s]",
    "reason",
    "note",
];

/// The markdown table with a short preamble.
pub fn markdown(plan: &Plan, rows: &[Row]) -> String {
    let escape = |s: &str| s.replace('|', "\\|").replace('\n', " ");
    let mut out = String::new();
    out.push_str(&format!(
        "# Stability sweep ({} mode)\n\n\
         Base: Scene A (dam on a rigid foundation, Nitsche contact on the base), P{} with gmsh size factor {}, \
         γ₀ = 100, θ = 0, δ = 10⁻⁴ S (S = stress scale of the loads), direct Newton from u = 0 \
         (≤ 50 steps, rtol 10⁻¹⁰). One factor varies per row.\n\n\
         - Δu = max(max over the probe points |u − u_ref| / max |u_ref(probe)|, relative difference of max |u|); \
         ΔL_c = difference of contact lengths.\n\
         - Reference and tolerance: γ₀/θ/δ rows against the base (1 %, two contact faces); ν rows against P{} \
         size {} at the same ν and mesh rows against the finest P{} mesh (5 %, two faces of the coarser mesh); \
         distorted V3 against the undistorted grid (5 %); units against the base in SI (10⁻⁸ on u, 10⁻⁵ L_c on L_c); \
         Scene B Cholesky against an LU solve of the same system (10⁻⁸).\n\
         - cond₁: Hager–Higham estimate of ‖J‖₁‖J⁻¹‖₁ for the Jacobian at the answer (stiffness matrix for Scene B).\n\
         - finite: u, cell stresses and contact-face states free of NaN/inf.\n\
         - A combination whose Newton runs out of steps is retried (rows marked ↳): with rtol 10⁻⁸ if the \
         residual had reached 10⁻⁸, else by δ-continuation from 10⁻¹ S, then with 200 steps.\n\n",
        if plan.quick { "quick" } else { "full" },
        plan.order,
        plan.size,
        plan.nu_reference.0,
        plan.nu_reference.1,
        plan.size_orders.iter().max().unwrap_or(&plan.order),
    ));
    out.push_str(&format!("| {} |\n", HEADER.join(" | ")));
    out.push_str(&format!("|{}\n", "---|".repeat(HEADER.len())));
    for row in rows {
        let mut c = cells(row);
        c.push(escape(&row.reason_short));
        c.push(escape(&row.note));
        out.push_str(&format!("| {} |\n", c.join(" | ")));
    }
    out.push_str(&format!("\n{}\n", summary(rows)));
    out
}

/// The CSV table (full reasons).
pub fn csv(rows: &[Row]) -> String {
    let quote = |s: &str| {
        if s.contains([',', '"', '\n']) {
            format!("\"{}\"", s.replace('"', "\"\""))
        } else {
            s.to_string()
        }
    };
    let mut out = HEADER.iter().map(|h| quote(h)).collect::<Vec<_>>().join(",") + "\n";
    for row in rows {
        let mut c = cells(row);
        c.push(row.reason.clone());
        c.push(row.note.clone());
        out.push_str(&(c.iter().map(|s| quote(s)).collect::<Vec<_>>().join(",") + "\n"));
    }
    out
}

/// "N combinations: …": the key number.
pub fn summary(rows: &[Row]) -> String {
    let count = |s: Status| rows.iter().filter(|r| r.status == s).count();
    let mismatched = rows.iter().filter(|r| r.matches == Some(false)).count();
    let nonfinite = rows.iter().filter(|r| r.finite() == Some(false)).count();
    let retries = rows.iter().filter(|r| r.is_retry).count();
    // the last row of each combination (the first row or its last retry)
    let last = (0..rows.len()).filter(|&i| rows.get(i + 1).is_none_or(|next| !next.is_retry));
    let unsolved = last.filter(|&i| !matches!(rows[i].status, Status::Converged | Status::Stagnated)).count();
    format!(
        "{} combinations ({} rows with {retries} retries): {} rows converged, {} stagnated at round-off, \
         {} stopped with a solver error, {} panicked; {unsolved} combinations without an answer after the \
         retries; {} rows outside their reference tolerance; {} rows with NaN/inf.",
        rows.len() - retries,
        rows.len(),
        count(Status::Converged),
        count(Status::Stagnated),
        count(Status::Failed),
        count(Status::Panicked),
        mismatched,
        nonfinite
    )
}

/// Whether the sweep itself failed: a panic, a NaN/inf, or a stop without a reason.
pub fn broken(rows: &[Row]) -> Vec<String> {
    rows.iter()
        .filter(|r| {
            r.status == Status::Panicked
                || r.finite() == Some(false)
                || (!matches!(r.status, Status::Converged) && r.reason.trim().is_empty())
        })
        .map(|r| format!("{} / {}: {} {}", r.group, r.case, r.status.name(), r.reason))
        .collect()
}

/// Writes the markdown table to `path` and the CSV next to it, atomically.
pub fn write_tables(plan: &Plan, rows: &[Row], path: &Path) -> Result<PathBuf> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    let csv_path = path.with_extension("csv");
    write_output(path, markdown(plan, rows).as_bytes())?;
    write_output(&csv_path, csv(rows).as_bytes())?;
    Ok(csv_path)
}

#[derive(clap::Parser, Debug)]
#[command(about = "Stability sweep of the Nitsche contact solver (γ₀, θ, δ, ν, mesh, distortion, units, contrast)")]
struct Args {
    /// Fast subset: P1, coarse meshes, a few values of each factor
    #[arg(long)]
    quick: bool,
    /// Markdown output; the CSV is written next to it with extension .csv
    #[arg(default_value = "out/stability.md")]
    output: PathBuf,
}

fn main() -> Result<()> {
    use clap::Parser;
    let args = Args::parse();
    let plan = Plan::new(args.quick);
    eprintln!("stability sweep ({} mode)", if plan.quick { "quick" } else { "full" });
    let rows = run(&plan);
    let table = markdown(&plan, &rows);
    println!("{table}");
    let csv_path = write_tables(&plan, &rows, &args.output)?;
    eprintln!("wrote {} and {}", args.output.display(), csv_path.display());
    let broken = broken(&rows);
    if !broken.is_empty() {
        anyhow::bail!("{} combination(s) panicked or produced NaN/inf:\n{}", broken.len(), broken.join("\n"));
    }
    Ok(())
}
