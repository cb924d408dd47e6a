//! Scene files: the geometry, mesh options, materials, boundary roles and loads of a run.
//!
//! A scene is a TOML file beside its `.geo` file. Materials are keyed by physical-surface
//! name, boundary conditions by physical-curve name. Every key is documented in docs/reference.md.
//! Without a scene file, [`Scene::for_geometry`] gives roles by curve name (`Gamma_D`,
//! `Gamma_N`, `Gamma_C`, or `dirichlet`, `neumann`, `contact`, any case) and the default
//! material [`Scene::DEFAULT_MATERIAL`] to every region.

use crate::adapt::geo::GeoMesher;
use crate::adapt::{AdaptSettings, Refinement};
use crate::contact::{Continuation, LoadPath};
use crate::elasticity::{Material, Problem};
use crate::io::gmsh::MeshOptions;
use crate::mesh::Topology;
use crate::safety::criteria::CriteriaSection;
use crate::solve::NewtonOptions;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

mod checks;
mod joints;
mod nested;
mod problem;
mod sections;
mod solid;
mod validate;

pub use joints::JointSection;
pub use sections::{
    BoundarySection, Components, ContactSection, CrackKind, DrainsSection, Fix, Hydrostatic, IceSection, LoadSection,
    MeshSection, OutputSection, ProjectionKind, Role, SafetySection, SiltSection, UpliftSection,
};

/// A scene that cannot be read or does not fit its mesh.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("cannot read {path}: {source}")]
    Read { path: PathBuf, source: std::io::Error },
    #[error("{path}: {message}")]
    Syntax { path: PathBuf, message: String },
    #[error("{path}: {what} '{name}' is not a physical {kind} of the geometry; it has: {available}")]
    UnknownGroup { path: PathBuf, what: &'static str, name: String, kind: &'static str, available: String },
    #[error("{path}: material '{name}': {message}")]
    Material { path: PathBuf, name: String, message: String },
    #[error("{path}: {message}")]
    Invalid { path: PathBuf, message: String },
    /// The loads need more than the joint alone can carry: the dam does not hold (a verdict,
    /// not bad input).
    #[error("{path}: {message}")]
    NoEquilibrium { path: PathBuf, message: String },
}

/// A scene file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// The `.geo` (or `.msh`) file, relative to the scene file.
    pub geometry: PathBuf,
    #[serde(default)]
    pub mesh: MeshSection,
    /// Materials by physical-surface name.
    #[serde(default)]
    pub materials: BTreeMap<String, Material>,
    /// Boundary conditions by physical-curve name.
    #[serde(default)]
    pub boundary: BTreeMap<String, BoundarySection>,
    #[serde(default)]
    pub loads: LoadSection,
    #[serde(default)]
    pub contact: ContactSection,
    /// Joints between two meshed bodies by physical-curve name.
    #[serde(default)]
    pub joints: BTreeMap<String, JointSection>,
    pub uplift: Option<UpliftSection>,
    #[serde(default)]
    pub safety: SafetySection,
    /// The acceptance criteria of the load combinations by category (`damfem safety`).
    #[serde(default)]
    pub criteria: CriteriaSection,
    #[serde(default)]
    pub adapt: AdaptSettings,
    #[serde(default)]
    pub output: OutputSection,
    /// Load combinations by name: `[uplift]`, `[boundary.<curve>]` and `[loads]` keys that
    /// replace the scene's ([`Scene::combination`]).
    #[serde(default)]
    pub combinations: BTreeMap<String, toml::Table>,
    /// The file this scene was read from (the geometry itself for a default scene).
    #[serde(skip)]
    pub source: PathBuf,
    /// The scene's TOML table, without its combinations.
    #[serde(skip)]
    table: toml::Table,
    /// The load combination this scene was made for ([`Scene::combination`]); None: the scene's own loads.
    #[serde(skip)]
    pub combination_name: Option<String>,
    /// The crack s₀ \[m\] of each uplift diagram in the state before the earthquake, which the
    /// seismic rules keep ([`Scene::pre_earthquake`]); 0 until it is solved.
    #[serde(skip)]
    pub prior_cracks: Vec<f64>,
}

impl Scene {
    /// Material of regions that a scene does not name: concrete, E = 30 GPa, ν = 0.2, ρ = 2400.
    pub const DEFAULT_MATERIAL: Material = Material { young: 3.0e10, poisson: 0.2, density: 2400.0 };

    /// Reads a scene file; the geometry path becomes relative to the working directory. Every
    /// load combination is checked too.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read { path: path.into(), source })?;
        let syntax = |e: toml::de::Error| SceneError::Syntax {
            path: path.into(),
            message: e.to_string().trim_end().to_string(),
        };
        let mut table: toml::Table = toml::from_str(&text).map_err(syntax)?;
        checks::check_values(path, &toml::Value::Table(table.clone()))?;
        let mut scene: Scene = toml::from_str(&text).map_err(syntax)?;
        scene.geometry = path.parent().unwrap_or(Path::new("")).join(&scene.geometry);
        scene.source = path.into();
        table.remove("combinations");
        scene.table = table;
        scene.validate()?;
        let names: Vec<&str> = scene.combinations.keys().map(String::as_str).collect();
        scene.criteria.check(&names).map_err(|message| scene.invalid(message))?;
        for name in scene.combinations.keys() {
            scene.combination(name)?;
        }
        Ok(scene)
    }

    /// The sections a load combination may change (of `joints`, the `uplift` tables only).
    const COMBINED: [&'static str; 4] = ["uplift", "boundary", "loads", "joints"];

    /// The scene of the load combination `name`: its `[uplift]`, `[boundary.<curve>]`,
    /// `[loads]` and `[joints.<curve>.uplift]` keys replace the scene's one by one (a table
    /// merges into the scene's table), every other section is this scene's (with the
    /// command-line overrides), and the result is checked as a scene file is. Errors name
    /// `combinations.<name>`.
    pub fn combination(&self, name: &str) -> Result<Scene, SceneError> {
        let context = |message: String| self.invalid(format!("combinations.{name}: {message}"));
        let overlay = self.combinations.get(name).ok_or_else(|| {
            let names: Vec<&str> = self.combinations.keys().map(String::as_str).collect();
            context(format!(
                "no such combination; the scene has: {}",
                if names.is_empty() { "none".into() } else { names.join(", ") }
            ))
        })?;
        if let Some(key) = overlay.keys().find(|k| !Self::COMBINED.contains(&k.as_str())) {
            return Err(context(format!(
                "'{key}' cannot be combined: a combination changes [uplift], [boundary.<curve>], [loads] and \
                 [joints.<curve>.uplift] keys"
            )));
        }
        self.check_combined_joints(overlay).map_err(context)?;
        let mut table = self.table.clone();
        merge(&mut table, overlay);
        let merged: Scene =
            toml::Value::Table(table).try_into().map_err(|e: toml::de::Error| context(e.to_string()))?;
        let mut joints = self.joints.clone();
        for (name, joint) in &mut joints {
            joint.uplift = merged.joints.get(name).and_then(|j| j.uplift.clone());
        }
        let scene = Scene {
            uplift: merged.uplift,
            joints,
            boundary: merged.boundary,
            loads: merged.loads,
            combinations: BTreeMap::new(),
            combination_name: Some(name.to_string()),
            ..self.clone()
        };
        match scene.validate() {
            Err(SceneError::Invalid { message, .. }) => Err(context(message)),
            other => other.map(|_| scene),
        }
    }

    /// The state before the earthquake, where a seismic crack rule (`unchanged`, `none`) keeps
    /// its crack: this scene without its acceleration (so without Westergaard's pressure),
    /// the same water, its cracks filled; None where no rule needs it.
    pub fn pre_earthquake(&self) -> Option<Scene> {
        let a = self.loads.acceleration;
        let mut sections = self.uplift.iter().chain(self.joints.values().filter_map(|j| j.uplift.as_ref()));
        if !sections.any(|up| matches!(up.crack_kind(a), CrackKind::Unchanged | CrackKind::Dry)) {
            return None;
        }
        let loads = LoadSection { acceleration: [0.0; 2], westergaard: None, ..self.loads.clone() };
        Some(Scene { loads, prior_cracks: Vec::new(), ..self.clone() })
    }

    /// This scene with the cracks s₀ \[m\] of its state before the earthquake, one per
    /// uplift diagram in order.
    pub fn with_prior_cracks(self, prior_cracks: Vec<f64>) -> Scene {
        Scene { prior_cracks, ..self }
    }

    /// The `joints` of a combination's `overlay` name joints of the scene and change their
    /// `uplift` tables only.
    fn check_combined_joints(&self, overlay: &toml::Table) -> Result<(), String> {
        let Some(joints) = overlay.get("joints") else { return Ok(()) };
        let names: Vec<&str> = self.joints.keys().map(String::as_str).collect();
        for (curve, table) in joints.as_table().into_iter().flatten() {
            if !self.joints.contains_key(curve) {
                return Err(format!(
                    "joints.{curve} is not a joint of the scene, whose [joints] are: {}",
                    list(&names)
                ));
            }
            let keys = table.as_table().map(|t| t.keys().collect::<Vec<_>>()).unwrap_or_default();
            if let Some(key) = keys.iter().find(|k| k.as_str() != "uplift") {
                return Err(format!(
                    "'joints.{curve}.{key}' cannot be combined: of a joint, a combination changes its uplift only"
                ));
            }
        }
        Ok(())
    }

    /// The default scene of a bare geometry file: roles from the curve names, default materials.
    pub fn for_geometry(path: &Path) -> Scene {
        Scene {
            geometry: path.into(),
            mesh: MeshSection::default(),
            materials: BTreeMap::new(),
            boundary: BTreeMap::new(),
            loads: LoadSection::default(),
            contact: ContactSection::default(),
            joints: BTreeMap::new(),
            uplift: None,
            safety: SafetySection::default(),
            criteria: CriteriaSection::default(),
            adapt: AdaptSettings::default(),
            output: OutputSection::default(),
            combinations: BTreeMap::new(),
            source: path.into(),
            table: toml::Table::new(),
            combination_name: None,
            prior_cracks: Vec::new(),
        }
    }

    fn invalid(&self, message: String) -> SceneError {
        SceneError::Invalid { path: self.source.clone(), message }
    }

    /// The `[mesh]` keys of the scene file.
    fn given_mesh_keys(&self) -> Vec<&str> {
        let keys = self.table.get("mesh").and_then(toml::Value::as_table);
        keys.map_or_else(Vec::new, |t| t.keys().map(String::as_str).collect())
    }

    /// `mesh.order`, if the scene file gives it (a `.msh` keeps its own degree otherwise).
    pub fn given_order(&self) -> Option<usize> {
        self.given_mesh_keys().contains(&"order").then_some(self.mesh.order)
    }

    /// gmsh options from the `[mesh]` table.
    pub fn mesh_options(&self) -> MeshOptions {
        let m = &self.mesh;
        MeshOptions {
            order: m.order,
            size_factor: m.size_factor,
            size_min: m.size_min,
            size_max: m.size_max,
            algorithm: m.algorithm,
        }
    }

    /// The adaptive loop's mesher of this scene's geometry with its `[mesh]` options and the
    /// `refinement`, quiet and without shell commands.
    pub fn mesher(&self, refinement: Refinement) -> GeoMesher {
        GeoMesher {
            geometry: self.geometry.clone(),
            options: self.mesh_options(),
            refinement,
            verbose: false,
            allow_system_calls: false,
            joints: self.joints.keys().cloned().collect(),
        }
    }

    /// Newton options of the `[contact]` table.
    pub fn newton_options(&self) -> NewtonOptions {
        NewtonOptions { max_iter: self.contact.max_iter, rtol: self.contact.rtol, ..Default::default() }
    }

    /// How `damfem solve` reaches δ, from the `[contact]` table: δ defaults to 10⁻⁴ times the
    /// stress scale of `problem` (0 for the semismooth projection); with friction the path
    /// starts by default at 0.1 times the stress scale, which Newton needs to find the slip
    /// zone from u = 0.
    pub fn continuation(&self, problem: &Problem, topology: &Topology) -> Continuation {
        let c = &self.contact;
        let scale = problem.stress_scale(topology);
        let delta = match c.projection {
            ProjectionKind::Semismooth => 0.0,
            ProjectionKind::Quadratic => c.delta.unwrap_or(1e-4 * scale),
        };
        Continuation {
            delta,
            delta_start: delta.max(c.delta_start.unwrap_or(if self.has_friction() { 0.1 } else { 0.0 }) * scale),
            newton: self.newton_options(),
            path: self.load_path(),
        }
    }

    /// The load path of a frictional joint or one with uplift, unless `contact.load_path =
    /// false` or without self-weight: its weight (0, −g) first, then the rest.
    pub fn load_path(&self) -> Option<LoadPath> {
        let uplift = self.uplift.is_some() || self.joints.values().any(|j| j.uplift.is_some());
        let g = self.loads.gravity;
        (self.contact.load_path && g > 0.0 && (uplift || self.has_friction()))
            .then_some(LoadPath { weight: [0.0, -g], trace: None })
    }
}

/// Merges `overlay` into `table`: a table into a table key by key, any other value replacing.
fn merge(table: &mut toml::Table, overlay: &toml::Table) {
    for (key, value) in overlay {
        match (table.get_mut(key), value) {
            (Some(toml::Value::Table(inner)), toml::Value::Table(over)) => merge(inner, over),
            _ => {
                table.insert(key.clone(), value.clone());
            }
        }
    }
}

fn list(names: &[&str]) -> String {
    if names.is_empty() {
        "none".into()
    } else {
        names.join(", ")
    }
}
