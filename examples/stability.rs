//! Numerical stability stress test of the Nitsche contact solver and the linear solver.
//!
//! What it shows: how the Newton/LU solve of Scene A (dam on a rigid foundation, Nitsche
//! contact on the base) behaves when one factor at a time moves away from a base case:
//! the Nitsche parameter γ₀ (1 … 10⁴) and the variant θ, the regularisation δ over eight
//! decades (S·10⁻¹ … S·10⁻⁸, S the stress scale of the loads), Poisson's ratio up to 0.499,
//! the mesh size over three levels, a randomly distorted mesh (the manufactured Signorini
//! problem V3 on the unit square, interior nodes moved by up to 35 % of h, fixed seed) and
//! SI against dimensionless units, and Coulomb friction over a decade of F and Mohr–Coulomb
//! cohesion on the frictional dam (Scene A held by its joint alone). Scene B (dam bonded to a deformable rock) measures the
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
use damfem::contact::JointLaw;
use damfem::elasticity::Problem;
use damfem::fem::norms::errors;
use damfem::io::atomic::write_output;
use damfem::io::gmsh::{mesh_geo, MeshOptions};
use damfem::mesh::structured::{unit_square, BOTTOM};
use damfem::mesh::Mesh;
use damfem::scene::Scene;
use damfem::verify::meshes::{distort, quality};
use damfem::verify::sweep::{
    answer, broken, contact_row, csv, linear_row, markdown_rows, run_row, summary, Answer, Knobs, Row, Status,
    Tolerance,
};
use damfem::verify::units::rescale;
use damfem::verify::v3;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

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
    /// Coulomb coefficients F, and cohesions c [Pa] at the smallest F, on the frictional dam.
    pub friction: Vec<f64>,
    pub cohesion: Vec<f64>,
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
                friction: vec![0.8391, 8.391],
                cohesion: vec![1e5],
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
                friction: vec![0.8391, 1.2, 2.5, 8.391],
                cohesion: vec![1e5, 1e6],
                rock_divisors: vec![1.0, 1e1, 1e2, 1e3],
                scene_b: (2, 1.0),
            }
        }
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

/// The frictional dam (geo/scene_a_friction.toml), its joint law set by the knobs.
fn frictional_dam(meshes: &mut Meshes, order: usize, size: f64) -> Result<(Problem, Vec<i32>)> {
    let scene = Scene::load(&repo("geo/scene_a_friction.toml"))?;
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

// ---------------------------------------------------------------------------------------
// The sweep

/// Parameter sweeps on the base mesh: displacement within 1 %, contact length within two
/// contact faces of the base answer.
fn parameter_tolerance(reference: Option<&Answer>) -> Tolerance {
    Tolerance { u: 1e-2, length: reference.and_then(|r| r.contact_face).map(|h| 2.0 * h) }
}

/// Discretisation changes (mesh, degree, distortion): 5 % and two contact faces of the
/// coarser mesh.
fn discretisation_tolerance(row: &Row, reference: Option<&Answer>) -> Tolerance {
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

/// Runs every combination of `plan`, in order: base, γ₀, θ, δ, ν, mesh size, distortion,
/// units, friction, material contrast.
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
            let (angle, area) = quality(&problem.mesh);
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

    // 8. Friction: the frictional dam over a decade of F, then cohesion at the smallest F
    let friction_build = |m: &mut Meshes| frictional_dam(m, p, size);
    let smallest = plan.friction.iter().copied().fold(f64::INFINITY, f64::min);
    let laws = plan
        .friction
        .iter()
        .map(|&friction| JointLaw::Coulomb { friction })
        .chain(plan.cohesion.iter().map(|&cohesion| JointLaw::MohrCoulomb { friction: smallest, cohesion }));
    for law in laws {
        let knobs = Knobs { law, start: Some(0.1), max_iter: 100, ..Knobs::default() };
        let case = format!("frictional dam P{p} size {size}, {law:?}, δ from 1e-1·S to 1e-4·S");
        rows.extend(contact_rows(&mut meshes, "friction", &case, p, knobs, 1.0, &PROBES_A, &friction_build));
    }

    // 9. Material contrast: Scene B (bonded interface) with a softer rock, Cholesky vs LU
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

/// The markdown table with a short preamble.
pub fn markdown(plan: &Plan, rows: &[Row]) -> String {
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
    out.push_str(&markdown_rows(rows));
    out.push_str(&format!("\n{}\n", summary(rows)));
    out
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
