//! The stability sweep's combinations: the models it solves, the retries of a combination
//! whose Newton run ran out of steps, the references and tolerances rows are compared with,
//! and a cache of gmsh meshes. `examples/stability.rs` lists the cases; [`super::sweep`]
//! solves one row and writes the tables.

use super::meshes::{distort, quality};
use super::sweep::{answer, contact_row, linear_row, run_row, Answer, BoxError, Knobs, Row, Status, Tolerance};
use super::units::rescale;
use super::v3;
use crate::elasticity::Problem;
use crate::fem::norms::errors;
use crate::geometry::Point;
use crate::io::gmsh::{mesh_geo, MeshOptions};
use crate::mesh::structured::{unit_square, BOTTOM};
use crate::mesh::Mesh;
use crate::scene::Scene;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Probe points of the dams: upstream and downstream crest corners, heel, a point of the
/// contact base (Scene A) or the toe (Scene B), and an interior point; and of V3.
const PROBES_A: [Point; 5] = [[0.0, 50.0], [5.0, 50.0], [0.0, 0.0], [16.0, 0.0], [20.0, 20.0]];
const PROBES_B: [Point; 5] = [[0.0, 50.0], [5.0, 50.0], [0.0, 0.0], [40.0, 0.0], [20.0, -25.0]];
const PROBES_V3: [Point; 5] = [[1.0, 1.0], [0.5, 1.0], [1.0, 0.0], [0.75, 0.0], [0.25, 0.5]];

/// Seed of the mesh distortion.
const SEED: u64 = 20240611;

/// A scene of the repository's `geo/` directory.
fn scene(file: &str) -> Result<Scene, BoxError> {
    Ok(Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("geo").join(file))?)
}

/// gmsh meshes by (geometry, degree, size factor), meshed once each.
#[derive(Default)]
pub struct MeshCache {
    cache: HashMap<(PathBuf, usize, u64), Mesh>,
}

impl MeshCache {
    /// The mesh of `scene`'s geometry at degree `order` and gmsh size factor `size`.
    pub fn get(&mut self, scene: &Scene, order: usize, size: f64) -> Result<Mesh, BoxError> {
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
            .map_err(|e| format!("meshing {}: {e}", scene.geometry.display()))?;
        self.cache.insert(key, mesh.clone());
        Ok(mesh)
    }
}

/// What a case solves.
#[derive(Debug, Clone, Copy)]
pub enum Model {
    /// A dam scene of `geo/` with Nitsche contact on its joint, Poisson's ratio set to `nu`
    /// if given, and stresses divided by σ₀ and lengths by `length` if `scaled` is
    /// `Some((σ₀, length))`.
    Dam { file: &'static str, order: usize, size: f64, nu: Option<f64>, scaled: Option<(f64, f64)> },
    /// V3 on an n × n grid, interior vertices moved by up to `fraction · h`.
    V3 { n: usize, order: usize, fraction: f64 },
    /// Scene B (bonded) with the rock's Young's modulus divided by `divisor`, solved by
    /// Cholesky and checked against LU to 10⁻⁸.
    Bonded { order: usize, size: f64, divisor: f64 },
}

impl Model {
    fn order(&self) -> usize {
        match *self {
            Model::Dam { order, .. } | Model::V3 { order, .. } | Model::Bonded { order, .. } => order,
        }
    }

    /// The length unit of the solved problem, in metres.
    fn length(&self) -> f64 {
        match *self {
            Model::Dam { scaled: Some((_, length)), .. } => length,
            _ => 1.0,
        }
    }

    fn probes(&self) -> &'static [Point] {
        match self {
            Model::Dam { .. } => &PROBES_A,
            Model::V3 { .. } => &PROBES_V3,
            Model::Bonded { .. } => &PROBES_B,
        }
    }

    /// The problem and its contact tags.
    fn problem(&self, meshes: &mut MeshCache) -> Result<(Problem, Vec<i32>), BoxError> {
        match *self {
            Model::Dam { file, order, size, nu, scaled } => {
                let mut scene = scene(file)?;
                if let Some(nu) = nu {
                    scene.materials.values_mut().for_each(|m| m.poisson = nu);
                }
                let (problem, joint) = scene.problem(meshes.get(&scene, order, size)?)?;
                let problem = match scaled {
                    Some((sigma0, length)) => rescale(&problem, sigma0, length),
                    None => problem,
                };
                Ok((problem, joint.map(|j| j.tags).unwrap_or_default()))
            }
            Model::V3 { n, order, fraction } => Ok((v3_problem(n, order, fraction), vec![BOTTOM])),
            Model::Bonded { order, size, divisor } => {
                let mut scene = scene("scene_b.toml")?;
                scene.materials.get_mut("rock").ok_or("scene B has no material 'rock'")?.young /= divisor;
                Ok((scene.problem(meshes.get(&scene, order, size)?)?.0, Vec::new()))
            }
        }
    }
}

/// How a case's rows are compared.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rule {
    /// Parameter changes on the base mesh: u within 1 %, L_c within two contact faces of
    /// the reference.
    Parameter,
    /// Discretisation changes (mesh, degree, distortion): 5 % and two contact faces of the
    /// coarser mesh.
    Discretisation,
    /// The same problem in other units: 10⁻⁸ on u, 10⁻⁵ L_c on L_c. L_c counts the Gauss
    /// points with P_γ < 0; in P1 one of them sits on P_γ = 0 exactly (the middle of the
    /// piece |P_γ| < δ), so round-off may flip it.
    Units,
}

impl Rule {
    fn tolerance(self, row: &Row, reference: Option<&Answer>) -> Tolerance {
        let two_faces = |face: Option<f64>| face.map(|h| 2.0 * h);
        match self {
            Rule::Parameter => Tolerance { u: 1e-2, length: two_faces(reference.and_then(|r| r.contact_face)) },
            Rule::Discretisation => {
                let face = row.solution.as_ref().and_then(|s| s.contact_face);
                Tolerance { u: 5e-2, length: two_faces(face.or(reference.and_then(|r| r.contact_face))) }
            }
            Rule::Units => {
                let length = reference.and_then(|r| r.contact_length).map(|l| 1e-5 * l.max(1.0));
                Tolerance { u: 1e-8, length }
            }
        }
    }
}

/// A case's part in the comparisons.
#[derive(Debug, Clone, PartialEq)]
pub enum Role {
    /// Not compared.
    Alone,
    /// The reference of this name.
    Reference(String),
    /// Compared with the named reference under a rule.
    Compared(String, Rule),
}

/// One combination of the sweep.
#[derive(Debug, Clone)]
pub struct Case {
    pub group: &'static str,
    pub label: String,
    pub model: Model,
    pub knobs: Knobs,
    pub role: Role,
}

/// One contact combination and, if Newton ran out of steps, retries until one succeeds:
/// with rtol 10⁻⁸ when the residual had come below 10⁻⁸ (a round-off floor); otherwise by
/// δ-continuation from 10⁻¹ S, then directly with 200 Newton steps instead of 50. The last
/// row is the combination's answer.
fn contact_rows(meshes: &mut MeshCache, case: &Case) -> Vec<Row> {
    let model = case.model;
    let mut solve = |label: String, knobs: Knobs| {
        run_row(case.group, label, model.order(), |row| {
            let (problem, tags) = model.problem(meshes)?;
            contact_row(row, &problem, &tags, knobs, model.length(), model.probes());
            Ok(())
        })
    };
    let knobs = case.knobs;
    let first = solve(case.label.clone(), knobs);
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
        let mut row = solve(format!("{} ↳ retry: {what}", case.label), knobs);
        row.is_retry = true;
        let done = row.status != Status::Failed || row.min_rel_residual.is_none();
        rows.push(row);
        if done {
            break;
        }
    }
    rows
}

/// The Cholesky row of a bonded model, compared with its own LU solve.
fn linear_rows(meshes: &mut MeshCache, case: &Case) -> Vec<Row> {
    let mut lu = None;
    let mut row = run_row(case.group, case.label.clone(), case.model.order(), |row| {
        lu = linear_row(row, &case.model.problem(meshes)?.0, case.model.probes());
        Ok(())
    });
    row.compare(lu.as_ref(), Tolerance { u: 1e-8, length: None });
    vec![row]
}

/// V3 on an n × n grid of degree `order`, interior vertices moved by up to `fraction · h`.
fn v3_problem(n: usize, order: usize, fraction: f64) -> Problem {
    let mut mesh = unit_square(n, order);
    if fraction > 0.0 {
        distort(&mut mesh, fraction, 1.0 / n as f64, SEED);
    }
    v3::problem(mesh)
}

/// Notes the mesh quality of V3 on an n × n grid and the H¹ error of each answer.
fn note_v3(rows: &mut [Row], n: usize, order: usize, fraction: f64) {
    let problem = v3_problem(n, order, fraction);
    let (angle, area) = quality(&problem.mesh);
    for row in rows {
        let mut note = format!("min angle {angle:.1}°, min area {area:.1e}");
        if let Some(s) = &row.solution {
            note += &format!(", |u−u_exact|_H1 = {:.2e}", errors(&problem.mesh, &s.u, v3::u, v3::grad_u).1);
        }
        row.note = if row.note.is_empty() { note } else { format!("{}; {note}", row.note) };
    }
}

/// Solves every case in order, then compares each with its reference.
pub fn run(cases: &[Case]) -> Vec<Row> {
    let mut meshes = MeshCache::default();
    let mut solved: Vec<Vec<Row>> = Vec::with_capacity(cases.len());
    let mut references = HashMap::new();
    for case in cases {
        let mut rows = match case.model {
            Model::Bonded { .. } => linear_rows(&mut meshes, case),
            _ => contact_rows(&mut meshes, case),
        };
        if let Model::V3 { n, order, fraction } = case.model {
            note_v3(&mut rows, n, order, fraction);
        }
        if let Role::Reference(name) = &case.role {
            rows.iter_mut().for_each(|r| r.is_reference = true);
            references.insert(name.clone(), answer(&rows));
        }
        solved.push(rows);
    }
    for (case, rows) in cases.iter().zip(&mut solved) {
        if let Role::Compared(name, rule) = &case.role {
            let reference = references.get(name).and_then(Option::as_ref);
            for row in rows.iter_mut() {
                let tolerance = rule.tolerance(row, reference);
                row.compare(reference, tolerance);
            }
        }
    }
    solved.into_iter().flatten().collect()
}
