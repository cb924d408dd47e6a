//! Scene files: the geometry, mesh options, materials, boundary roles and loads of a run.
//!
//! A scene is a TOML file beside its `.geo` file. Materials are keyed by physical-surface
//! name, boundary conditions by physical-curve name. Every key is documented in docs/reference.md.
//! Without a scene file, [`Scene::for_geometry`] gives roles by curve name (`Gamma_D`,
//! `Gamma_N`, `Gamma_C`, or `dirichlet`, `neumann`, `contact`, any case) and the default
//! material [`Scene::DEFAULT_MATERIAL`] to every region.

use crate::adapt::geo::GeoMesher;
use crate::adapt::{AdaptError, AdaptSettings, Model, Refinement};
use crate::contact::nitsche::{Gap, NitscheParameters};
use crate::contact::uplift::{CrackRule, Drains, Uplift};
use crate::contact::LoadPath;
use crate::contact::{ContactJoint, Continuation, CurveUplift, JointLaw, JointLine};
use crate::elasticity::material::MAX_DENSITY;
use crate::elasticity::{BodyForce, Dirichlet, Material, Neumann, Problem, Traction};
use crate::io::gmsh::MeshOptions;
use crate::mesh::{distance, Mesh, Topology};
use crate::safety::criteria::CriteriaSection;
use crate::solve::NewtonOptions;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

mod checks;
mod joints;

pub use joints::JointSection;
mod nested;

/// The largest distance of an uplift table's `heel` from the end of its joint, as a fraction of
/// the joint's length: the heel is an end of the joint, given to the precision of its
/// coordinates.
const HEEL_TOLERANCE: f64 = 1e-3;

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

/// Options handed to the mesher.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MeshSection {
    /// Element degree, 1 or 2.
    pub order: usize,
    /// Global factor on gmsh's mesh sizes.
    pub size_factor: f64,
    pub size_min: Option<f64>,
    pub size_max: Option<f64>,
    /// gmsh 2D algorithm (Mesh.Algorithm): 1 MeshAdapt, 5 Delaunay, 6 Frontal-Delaunay, 8 quads-ready.
    pub algorithm: i32,
}

impl Default for MeshSection {
    fn default() -> Self {
        MeshSection { order: 2, size_factor: 1.0, size_min: None, size_max: None, algorithm: 6 }
    }
}

/// Role of a physical curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    Dirichlet,
    Neumann,
    Contact,
    Free,
}

/// Which displacement components a Dirichlet condition fixes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Fix {
    #[default]
    Both,
    X,
    Y,
}

/// Water pressure ρ_w g (H_w − y)₊ along −n; g is the scene's gravity.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hydrostatic {
    /// Water density ρ_w [kg/m³], default 1000.
    #[serde(default = "water_density")]
    pub density: f64,
    /// Water level H_w \[m\] (the y coordinate of the free surface).
    pub level: f64,
}

fn water_density() -> f64 {
    1000.0
}

/// One `[boundary.<curve>]` table.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySection {
    pub role: Role,
    /// Dirichlet: fixed components (default both).
    #[serde(default)]
    pub fix: Fix,
    /// Dirichlet: prescribed displacement \[m\] (default 0).
    #[serde(default)]
    pub value: [f64; 2],
    /// Neumann: constant traction \[Pa\].
    pub traction: Option<[f64; 2]>,
    /// Neumann: hydrostatic water pressure.
    pub hydrostatic: Option<Hydrostatic>,
    /// Neumann: silt against the face, beside the water.
    pub silt: Option<SiltSection>,
    /// Neumann: the thrust of an ice sheet, beside the water.
    pub ice: Option<IceSection>,
}

/// `silt = { level, density, coefficient }`: silt against the face up to `level` \[m\] (a y
/// coordinate), of submerged density ρ' \[kg/m³\], with the earth-pressure coefficient K
/// (default 1: ρ' is then an equivalent fluid's): p = K ρ' g (level − y)₊, horizontal.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SiltSection {
    pub level: f64,
    pub density: f64,
    #[serde(default = "unit_coefficient")]
    pub coefficient: f64,
}

fn unit_coefficient() -> f64 {
    1.0
}

/// `ice = { force, level, thickness }`: an ice sheet's thrust F \[N/m\] at the reservoir
/// surface `level` \[m\], spread as a horizontal pressure F / t over its `thickness` t \[m\]
/// below it (a line load would make the stresses singular).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IceSection {
    pub force: f64,
    pub level: f64,
    pub thickness: f64,
}

impl BoundarySection {
    /// g_N of a Neumann curve under gravity `g`: its traction or water, with its silt and ice.
    fn traction(&self, g: f64) -> Traction {
        let main = match (self.traction, self.hydrostatic) {
            (_, Some(h)) => Some(Traction::Hydrostatic { density: h.density, gravity: g, level: h.level }),
            (Some(t), None) => Some(Traction::Constant(t)),
            (None, None) => None,
        };
        let silt = self.silt.map(|s| Traction::Silt { gradient: s.coefficient * s.density * g, level: s.level });
        let ice = self.ice.map(|i| Traction::Ice {
            pressure: i.force / i.thickness,
            bottom: i.level - i.thickness,
            top: i.level,
        });
        let mut parts: Vec<Traction> = main.into_iter().chain(silt).chain(ice).collect();
        match parts.len() {
            0 => Traction::Constant([0.0; 2]),
            1 => parts.remove(0),
            _ => Traction::Sum(parts),
        }
    }
}

/// `[uplift]`, or `[joints.<curve>.uplift]`: the pore-water pressure in the joint
/// (docs/method.md §1.8).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UpliftSection {
    /// Reservoir level upstream \[m\] (a y coordinate).
    pub headwater: f64,
    /// Level downstream \[m\]; none: no water at the toe.
    pub tailwater: Option<f64>,
    #[serde(default = "water_density")]
    pub density: f64,
    pub drains: Option<DrainsSection>,
    /// What the water does in the crack open at the heel; default `full`, and `unchanged` in a
    /// combination with an acceleration ([`UpliftSection::crack_rule`]).
    pub crack: Option<CrackKind>,
    /// A point at the heel (the upstream end of the joint); none: the end nearest a curve with
    /// a hydrostatic load.
    pub heel: Option<[f64; 2]>,
}

/// Drains: distance from the heel \[m\] and efficiency in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DrainsSection {
    pub x: f64,
    pub efficiency: f64,
}

/// What the water does in the crack open at the heel (docs/method.md §1.8): the static rule
/// `full`, the seismic rules `unchanged` and `none` (which read as `full` without an
/// acceleration: no earthquake, no crack of its own), and `ignore`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CrackKind {
    /// The reservoir pressure fills the crack.
    Full,
    /// The diagram of the state before the earthquake, whatever opens.
    Unchanged,
    /// No pressure in the crack; beyond it, the diagram before the earthquake.
    #[serde(rename = "none")]
    Dry,
    /// The diagram without crack, whatever opens.
    Ignore,
}

impl UpliftSection {
    /// The crack's rule under the acceleration `a` \[g\]: the key's, or its default.
    pub fn crack_kind(&self, a: [f64; 2]) -> CrackKind {
        let seismic = a != [0.0; 2];
        match self.crack.unwrap_or(if seismic { CrackKind::Unchanged } else { CrackKind::Full }) {
            CrackKind::Unchanged | CrackKind::Dry if !seismic => CrackKind::Full,
            kind => kind,
        }
    }

    /// The crack's rule under the acceleration `a`, with s₀ = `prior` the crack of the state
    /// before the earthquake.
    pub fn crack_rule(&self, a: [f64; 2], prior: f64) -> CrackRule {
        match self.crack_kind(a) {
            CrackKind::Full => CrackRule::Filled,
            CrackKind::Unchanged => CrackRule::Kept { prior },
            CrackKind::Dry => CrackRule::Drained { prior },
            CrackKind::Ignore => CrackRule::Kept { prior: 0.0 },
        }
    }
}

/// `[loads]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LoadSection {
    /// Gravity g [m/s²] for self-weight (0, −ρ g) and hydrostatic pressure; 0 disables self-weight.
    pub gravity: f64,
    /// A pseudo-static acceleration (a_x, a_y) in units of g: the body force becomes
    /// ρ g (a_x, a_y − 1).
    pub acceleration: [f64; 2],
    /// Westergaard's added pressure (7/8) a_x cos²θ ρ_w g √(H z) on the reservoir's curves (the
    /// hydrostatic curves of the highest level) under a horizontal acceleration; default: on
    /// when a_x ≠ 0.
    pub westergaard: Option<bool>,
}

impl Default for LoadSection {
    fn default() -> Self {
        LoadSection { gravity: 9.81, acceleration: [0.0; 2], westergaard: None }
    }
}

impl LoadSection {
    /// The body force of the weight and the pseudo-static acceleration.
    fn body_force(&self) -> BodyForce {
        let (g, [a_x, a_y]) = (self.gravity, self.acceleration);
        if g == 0.0 {
            BodyForce::None
        } else {
            BodyForce::Acceleration([g * a_x, g * (a_y - 1.0)])
        }
    }
}

/// `[contact]`: Nitsche contact on the curves with role "contact".
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ContactSection {
    /// γ₀ in the Nitsche parameter γ = γ₀ E / h_F.
    pub gamma0: f64,
    /// θ: 1 symmetric, 0 incomplete (the estimator's variant), −1 skew-symmetric.
    pub theta: f64,
    /// Regularisation δ \[Pa\] of the projection; default 10⁻⁴ × the scene's stress scale.
    pub delta: Option<f64>,
    /// First δ of the continuation path, as a multiple of the stress scale (none: solve
    /// directly at δ).
    pub delta_start: Option<f64>,
    /// "quadratic" (C¹ smoothing with δ) or "semismooth" (δ = 0).
    pub projection: ProjectionKind,
    /// Constant normal gap g₀ \[m\] to the foundation (u^n ≤ g).
    pub gap: f64,
    /// Gradient of an affine gap g(x) = g₀ + ∇g · x.
    pub gap_gradient: [f64; 2],
    /// Normal of a flat foundation, pointing from the body into it: the direction ν of u·ν ≤ g
    /// and of the contact traction. Default: the outward normal of each contact face.
    pub direction: Option<[f64; 2]>,
    /// Coulomb friction coefficient F = tan φ (0: frictionless).
    pub friction: f64,
    /// Cohesion c \[Pa\] of a Mohr–Coulomb joint, on its closed part.
    pub cohesion: f64,
    /// Tresca threshold s \[Pa\] (exclusive with `friction`).
    pub threshold: Option<f64>,
    /// Maximum number of Newton steps per regularisation stage.
    pub max_iter: usize,
    /// Relative residual tolerance of Newton.
    pub rtol: f64,
    /// Whether a solve from rest follows the load path (docs/method.md §1.11) where it
    /// matters, on a frictional joint or with uplift; false: every load at once.
    pub load_path: bool,
}

impl ContactSection {
    /// The joint law of the friction keys.
    pub fn law(&self) -> JointLaw {
        law_of(self.threshold, self.friction, self.cohesion)
    }

    /// The first friction key out of range, as "key = value must …".
    fn check_law(&self) -> Result<(), String> {
        check_law("contact", self.threshold, self.friction, self.cohesion)
    }
}

/// The joint law of the friction keys `threshold` (Tresca), `friction` and `cohesion`.
fn law_of(threshold: Option<f64>, friction: f64, cohesion: f64) -> JointLaw {
    match (threshold, friction, cohesion) {
        (Some(threshold), _, _) => JointLaw::Tresca { threshold },
        (None, friction, 0.0) if friction > 0.0 => JointLaw::Coulomb { friction },
        (None, 0.0, 0.0) => JointLaw::Frictionless,
        (None, friction, cohesion) => JointLaw::MohrCoulomb { friction, cohesion },
    }
}

/// "key = density exceeds …" for a water density above [`MAX_DENSITY`].
fn too_dense(key: &str, density: f64) -> String {
    format!("{key} = {density:e} kg/m^3 exceeds {MAX_DENSITY:e} kg/m^3, a hundred times water's (it is in kg/m^3)")
}

/// Largest friction coefficient accepted: tan 89.4°, beyond any joint.
const MAX_FRICTION: f64 = 100.0;
/// Largest cohesion or Tresca threshold accepted \[Pa\]: a thousand times concrete's
/// compressive strength.
const MAX_STRENGTH: f64 = 1e10;

/// The first friction key of the table `table` out of range, as "table.key = value must …".
fn check_law(table: &str, threshold: Option<f64>, friction: f64, cohesion: f64) -> Result<(), String> {
    let keys = [("friction", friction), ("cohesion", cohesion), ("threshold", threshold.unwrap_or(0.0))];
    if let Some((key, value)) = keys.iter().find(|(_, v)| !(v.is_finite() && *v >= 0.0)) {
        return Err(format!("{table}.{key} = {value} must be a non-negative number"));
    }
    if friction > MAX_FRICTION {
        return Err(format!(
            "{table}.friction = {friction:e} exceeds {MAX_FRICTION}, the coefficient of a friction angle of 89.4 \
             degrees: no joint holds that much (it is tan phi, not the angle)"
        ));
    }
    let strengths = [("cohesion", cohesion), ("threshold", threshold.unwrap_or(0.0))];
    if let Some((key, value)) = strengths.iter().find(|(_, v)| *v > MAX_STRENGTH) {
        return Err(format!(
            "{table}.{key} = {value:e} Pa exceeds {MAX_STRENGTH:e} Pa, a thousand times concrete's compressive \
             strength (it is in Pa)"
        ));
    }
    match threshold {
        Some(_) if friction > 0.0 || cohesion > 0.0 => Err(format!(
            "{table}.threshold (Tresca) and {table}.friction = {friction} or {table}.cohesion = {cohesion} are \
             exclusive: give a Tresca threshold, or a Coulomb friction coefficient with an optional cohesion"
        )),
        _ => Ok(()),
    }
}

impl Default for ContactSection {
    fn default() -> Self {
        ContactSection {
            gamma0: 100.0,
            theta: 0.0,
            delta: None,
            delta_start: None,
            projection: ProjectionKind::Quadratic,
            gap: 0.0,
            gap_gradient: [0.0; 2],
            direction: None,
            friction: 0.0,
            cohesion: 0.0,
            threshold: None,
            max_iter: 50,
            rtol: 1e-10,
            load_path: true,
        }
    }
}

/// Which projection onto R⁻ the contact condition uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ProjectionKind {
    Quadratic,
    Semismooth,
}

/// `[output]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSection {
    /// Output directory, relative to the working directory (the CLI's `-o` overrides it).
    pub directory: PathBuf,
    /// Also write the boundary facets with their physical tags.
    pub boundary: bool,
    /// With an estimate: write the η fields of every cell.
    pub estimators: bool,
    /// With an estimate: write σ_h (cell means and the discontinuous `_dg.vtu`).
    pub reconstruction: bool,
}

impl Default for OutputSection {
    fn default() -> Self {
        OutputSection { directory: PathBuf::from("out"), boundary: true, estimators: true, reconstruction: true }
    }
}

/// `[safety]`: what `damfem safety` analyses (docs/method.md §1.9).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SafetySection {
    /// The curve of the sliding plane, a `[joints]` curve or a curve of role contact; None:
    /// every joint curve, which must then lie on one line.
    pub joint: Option<String>,
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

    /// The values that need no mesh of the uplift table `table` (`uplift` or
    /// `joints.<curve>.uplift`).
    fn check_uplift(&self, table: &str, up: &UpliftSection) -> Result<(), SceneError> {
        let numbers = [("headwater", Some(up.headwater)), ("tailwater", up.tailwater), ("density", Some(up.density))];
        if let Some((key, value)) = numbers.iter().find_map(|(k, v)| v.filter(|x| !x.is_finite()).map(|x| (k, x))) {
            return Err(self.invalid(format!("{table}.{key} = {value} must be a finite number")));
        }
        if up.density <= 0.0 {
            return Err(self.invalid(format!("{table}.density = {} must be positive", up.density)));
        }
        if up.density > MAX_DENSITY {
            return Err(self.invalid(too_dense(&format!("{table}.density"), up.density)));
        }
        if let Some(t) = up.tailwater.filter(|&t| t > up.headwater) {
            return Err(self.invalid(format!(
                "{table}.tailwater = {t} lies above {table}.headwater = {}: the reservoir is upstream",
                up.headwater
            )));
        }
        match up.drains {
            Some(d) if !(d.x.is_finite() && (0.0..=1.0).contains(&d.efficiency)) => Err(self.invalid(format!(
                "{table}.drains = {{ x = {}, efficiency = {} }}: x must be finite and the efficiency within [0, 1]",
                d.x, d.efficiency
            ))),
            _ => Ok(()),
        }
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

    /// Checks the values that need no mesh (done by [`Scene::load`]; again after changes).
    pub fn validate(&self) -> Result<(), SceneError> {
        if let Some(key) = self.given_mesh_keys().into_iter().find(|&k| k != "order" && self.is_msh()) {
            return Err(self.invalid(format!(
                "mesh.{key} applies to a .geo geometry, which gmsh meshes; {} is a mesh file with its own sizes",
                self.geometry.display()
            )));
        }
        if !(self.mesh.order == 1 || self.mesh.order == 2) {
            return Err(self.invalid(format!("mesh.order = {} must be 1 or 2", self.mesh.order)));
        }
        if !(self.mesh.size_factor > 0.0 && self.mesh.size_factor.is_finite()) {
            return Err(
                self.invalid(format!("mesh.size_factor = {} must be positive and finite", self.mesh.size_factor))
            );
        }
        let c = &self.contact;
        if !(c.gamma0 > 0.0 && c.gamma0.is_finite()) {
            return Err(self.invalid(format!("contact.gamma0 = {} must be positive and finite", c.gamma0)));
        }
        if ![1.0, 0.0, -1.0].contains(&c.theta) {
            return Err(self.invalid(format!("contact.theta = {} must be 1, 0 or -1", c.theta)));
        }
        if let Some(nu) = c.direction.filter(|nu| !(nu[0].hypot(nu[1]) > 0.0 && nu.iter().all(|x| x.is_finite()))) {
            return Err(self.invalid(format!("contact.direction = {nu:?} must be a non-zero vector")));
        }
        c.check_law().map_err(|message| self.invalid(message))?;
        let a = self.loads.acceleration;
        if a != [0.0; 2] && self.loads.gravity <= 0.0 {
            return Err(self.invalid(format!(
                "loads.acceleration = {a:?} is in g, so it needs loads.gravity > 0 (now {})",
                self.loads.gravity
            )));
        }
        let water = self.boundary.values().any(|b| b.hydrostatic.is_some());
        if self.loads.westergaard == Some(true) && (a[0] == 0.0 || !water) {
            return Err(self.invalid(format!(
                "loads.westergaard = true needs a horizontal loads.acceleration (now {}) and a reservoir: a \
                 boundary curve with a hydrostatic load",
                a[0]
            )));
        }
        if let Some(up) = &self.uplift {
            self.check_uplift("uplift", up)?;
        }
        if c.delta.is_some_and(|d| !(d >= 0.0 && d.is_finite())) {
            return Err(
                self.invalid(format!("contact.delta = {} must be non-negative and finite", c.delta.unwrap_or(0.0)))
            );
        }
        self.check_newton()?;
        self.check_loads()?;
        self.check_sizes()?;
        self.check_joints()?;
        self.check_safety()?;
        self.check_combination_names()?;
        self.adapt.validate().map_err(|message| self.invalid(message))?;
        for (name, m) in &self.materials {
            m.validate().map_err(|message| SceneError::Material {
                path: self.source.clone(),
                name: name.clone(),
                message,
            })?;
        }
        for (name, b) in &self.boundary {
            let has_load = b.traction.is_some() || b.hydrostatic.is_some() || b.silt.is_some() || b.ice.is_some();
            if b.role != Role::Neumann && has_load {
                return Err(self.invalid(format!("boundary '{name}': a traction needs role = \"neumann\"")));
            }
            if b.traction.is_some() && b.hydrostatic.is_some() {
                return Err(self.invalid(format!("boundary '{name}': give either traction or hydrostatic, not both")));
            }
        }
        Ok(())
    }

    /// Boundary roles by physical-curve tag: the scene's tables, or the naming convention
    /// when the scene has none.
    pub fn roles(&self, mesh: &Mesh) -> Result<Vec<(i32, String, BoundarySection)>, SceneError> {
        if self.boundary.is_empty() {
            return Ok(mesh
                .groups
                .iter()
                .filter(|g| g.dim == 1)
                .filter_map(|g| {
                    conventional_role(&g.name).map(|role| {
                        let section = BoundarySection {
                            role,
                            fix: Fix::Both,
                            value: [0.0; 2],
                            traction: None,
                            hydrostatic: None,
                            silt: None,
                            ice: None,
                        };
                        (g.tag, g.name.clone(), section)
                    })
                })
                .collect());
        }
        self.boundary
            .iter()
            .map(|(name, b)| Ok((self.group_tag(mesh, 1, name, "boundary")?, name.clone(), b.clone())))
            .collect()
    }

    fn group_tag(&self, mesh: &Mesh, dim: u8, name: &str, what: &'static str) -> Result<i32, SceneError> {
        mesh.group(dim, name).map(|g| g.tag).ok_or_else(|| SceneError::UnknownGroup {
            path: self.source.clone(),
            what,
            name: name.into(),
            kind: if dim == 1 { "curve" } else { "surface" },
            available: list(&mesh.group_names(dim)),
        })
    }

    /// Material of every cell: by region name, the default for unnamed regions.
    pub fn cell_materials(&self, mesh: &Mesh) -> Result<Vec<Material>, SceneError> {
        let mut by_tag = BTreeMap::new();
        for (name, m) in &self.materials {
            by_tag.insert(self.group_tag(mesh, 2, name, "material")?, *m);
        }
        Ok(mesh.cell_tags.iter().map(|t| *by_tag.get(t).unwrap_or(&Self::DEFAULT_MATERIAL)).collect())
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

    /// Nitsche parameters of the `[contact]` table (the direction made a unit vector).
    fn nitsche_parameters(&self) -> NitscheParameters {
        let c = &self.contact;
        NitscheParameters {
            gamma0: c.gamma0,
            theta: c.theta,
            gap: Gap { constant: c.gap, gradient: c.gap_gradient },
            direction: c.direction.map(|nu| {
                let norm = nu[0].hypot(nu[1]);
                [nu[0] / norm, nu[1] / norm]
            }),
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

    /// The `[contact]` keys that only `damfem solve` reads: the adaptive loop chooses δ itself
    /// (`[adapt] delta0`), so it refuses them rather than ignore them.
    pub fn check_adaptive(&self) -> Result<(), SceneError> {
        let c = &self.contact;
        let set = [
            ("contact.delta", c.delta.is_some()),
            ("contact.delta_start", c.delta_start.is_some()),
            ("contact.projection = \"semismooth\"", c.projection == ProjectionKind::Semismooth),
        ];
        match set.iter().find(|(_, given)| *given) {
            Some((key, _)) => Err(self.invalid(format!(
                "{key} is read by `damfem solve` only; `damfem adapt` chooses the regularisation from \
                 adapt.delta0 and reduces it by adapt.rho_delta, so remove the key or use `damfem solve`"
            ))),
            None => self.check_estimable("the error estimate of every mesh of `damfem adapt` and `damfem safety`"),
        }
    }

    /// θ = 0 on every joint, as an error estimate needs (the bound of docs/method.md §5.2 rests
    /// on ψ_a z being a test function of the discrete problem, §4.2); `estimate` names the
    /// estimate asked for. `[contact] theta` counts where curves may have role contact.
    pub fn check_estimable(&self, estimate: &str) -> Result<(), SceneError> {
        let contact = self.boundary.is_empty() || self.boundary.values().any(|b| b.role == Role::Contact);
        let rigid = contact.then(|| ("contact.theta".to_string(), self.contact.theta));
        let joints = self.joints.iter().map(|(name, j)| (format!("joints.{name}.theta"), j.theta));
        match rigid.into_iter().chain(joints).find(|(_, theta)| *theta != 0.0) {
            Some((key, theta)) => Err(self.invalid(format!(
                "{key} = {theta}: {estimate} covers the Nitsche variant theta = 0 only (docs/method.md §5.2); \
                 set theta = 0"
            ))),
            None => Ok(()),
        }
    }

    /// Physical tags of the curves with role "contact".
    fn contact_tags(&self, mesh: &Mesh) -> Result<Vec<i32>, SceneError> {
        Ok(self.roles(mesh)?.into_iter().filter(|(_, _, b)| b.role == Role::Contact).map(|(tag, _, _)| tag).collect())
    }

    /// The contact joint of the curves with role "contact" on `mesh`, if there are any.
    fn joint(&self, mesh: &Mesh) -> Result<Option<ContactJoint>, SceneError> {
        let tags = self.contact_tags(mesh)?;
        Ok((!tags.is_empty())
            .then(|| ContactJoint::uniform(tags, Vec::new(), self.contact.law(), self.nitsche_parameters())))
    }

    /// The elasticity problem of this scene on `mesh` and its contact joint (None without
    /// curves of role "contact" or joints). The nodes of every joint curve are split between
    /// its two sides first.
    pub fn problem(&self, mut mesh: Mesh) -> Result<(Problem, Option<ContactJoint>), SceneError> {
        self.check_boundaries(&mesh)?;
        let interfaces = self.split_joints(&mut mesh)?;
        let roles = self.roles(&mesh)?;
        let g = self.loads.gravity;
        let mut dirichlet = Vec::new();
        let mut neumann = Vec::new();
        for (tag, _, b) in &roles {
            match b.role {
                Role::Dirichlet => {
                    let value = b.value;
                    let fix = match b.fix {
                        Fix::Both => [true, true],
                        Fix::X => [true, false],
                        Fix::Y => [false, true],
                    };
                    dirichlet.push(Dirichlet { tag: *tag, fix, value: Arc::new(move |_| value) });
                }
                Role::Neumann => neumann.push(Neumann { tag: *tag, traction: b.traction(g) }),
                Role::Contact | Role::Free => {}
            }
        }
        self.add_westergaard(&mesh, &mut neumann)?;
        let how = if self.boundary.is_empty() {
            "name a physical curve Gamma_D (or dirichlet) in the geometry"
        } else {
            "give a physical curve role = \"dirichlet\""
        };
        let materials = self.cell_materials(&mesh)?;
        let body_force = self.loads.body_force();
        let problem = Problem { mesh, materials, dirichlet, neumann, body_force };
        let mut joint = match self.two_body_joint(&interfaces) {
            Some(joint) => Some(joint),
            None => self.joint(&problem.mesh)?,
        };
        if self.uplift.is_some() && joint.is_none() {
            return Err(self.invalid(
                "[uplift] needs a joint: give a boundary curve role = \"contact\" (a rigid foundation) or a \
                 [joints.<curve>] table (a meshed rock block) for the pressure to act on"
                    .into(),
            ));
        }
        if joint.is_none() {
            self.check_contact_unused()?;
        }
        let friction = joint.as_ref().is_some_and(ContactJoint::has_friction);
        if problem.dirichlet.is_empty() && !friction {
            return Err(self.invalid(format!(
                "no Dirichlet boundary and no frictional joint: the body could move as a rigid body; {how} (curves: {})",
                list(&problem.mesh.group_names(1))
            )));
        }
        let topology = Topology::new(&problem.mesh);
        let facets = joint.as_ref().map_or_else(Vec::new, |j| contact_facets(&problem.mesh, &topology, &j.tags));
        let direction = if interfaces.is_empty() { self.nitsche_parameters().direction } else { None };
        if let Some(tag) = facing_away(&problem.mesh, &facets, direction) {
            let name = problem.mesh.groups.iter().find(|g| g.dim == 1 && g.tag == tag).map_or("?", |g| &g.name);
            return Err(self.invalid(format!(
                "contact.direction = {:?} points into the body on the contact curve '{name}' (ν·n ≤ 0 on one of its faces)",
                self.contact.direction.unwrap_or_default()
            )));
        }
        if let Some(j) = joint.as_mut() {
            j.uplift = self.uplift_diagrams(&problem, &topology, j, &facets)?;
        }
        // a joint between two bodies supports neither against a rigid motion of both
        let rigid_facets = if interfaces.is_empty() { &facets[..] } else { &[] };
        let supports = contact_supports(&problem.mesh, rigid_facets, direction, friction);
        if let Some(motion) = problem.free_rigid_motion(&supports) {
            return Err(self.invalid(format!(
                "the Dirichlet and contact conditions leave a rigid motion free ({motion}); {how} that blocks it"
            )));
        }
        if let Some(j) = joint.as_ref().filter(|_| !interfaces.is_empty()) {
            self.check_bodies_held(&problem, j)?;
        }
        if let Some(j) = joint.as_ref().filter(|_| problem.dirichlet.is_empty()) {
            self.check_sliding(&problem, &topology, j, &facets)?;
        }
        Ok((problem, joint))
    }
}

impl Model for Scene {
    fn problem(&self, mesh: Mesh) -> Result<(Problem, Option<ContactJoint>), AdaptError> {
        Scene::problem(self, mesh).map_err(|e| AdaptError::Problem(e.into()))
    }

    fn newton(&self) -> NewtonOptions {
        self.newton_options()
    }

    fn joint_line(&self, problem: &Problem) -> Option<JointLine> {
        Scene::joint_line(self, problem)
    }

    fn load_path(&self) -> Option<LoadPath> {
        Scene::load_path(self)
    }
}

impl Scene {
    /// `[safety] joint` names a joint curve or a curve of role contact.
    fn check_safety(&self) -> Result<(), SceneError> {
        let Some(name) = &self.safety.joint else { return Ok(()) };
        let contact = self.boundary.get(name).is_some_and(|b| b.role == Role::Contact);
        if self.joints.contains_key(name) || contact {
            return Ok(());
        }
        let joints: Vec<&str> = (self.joints.keys().map(String::as_str))
            .chain(self.boundary.iter().filter(|(_, b)| b.role == Role::Contact).map(|(n, _)| n.as_str()))
            .collect();
        Err(self.invalid(format!(
            "safety.joint = '{name}' is not a joint: name a [joints.<curve>] table or a curve of role contact ({})",
            if joints.is_empty() { "the scene has none".into() } else { joints.join(", ") }
        )))
    }

    /// The straight joint of the sliding plane on `problem`'s mesh from its heel to its toe
    /// (docs/method.md §1.9): every contact curve (or every `[joints]` curve, on its slave
    /// side), or with `[safety] joint` those on the line of that curve (the parts of a base
    /// with different laws slide together); None without them, on a joint that is not
    /// straight, or when nothing shows its upstream end (no `[uplift] heel`, no hydrostatic
    /// curve).
    pub fn joint_line(&self, problem: &Problem) -> Option<JointLine> {
        let mesh = &problem.mesh;
        let topology = Topology::new(mesh);
        let tags = match self.joints.is_empty() {
            true => self.contact_tags(mesh).ok()?,
            false => self.joint_tags(mesh).ok()?,
        };
        let mut facets = contact_facets(mesh, &topology, &tags);
        if let Some(name) = &self.safety.joint {
            let named = contact_facets(mesh, &topology, &[self.group_tag(mesh, 1, name, "joint").ok()?]);
            let plane = self.straight_joint(problem, &named, self.heel()).ok()?;
            facets.retain(|&(f, _)| mesh.facet(f)[..2].iter().all(|&n| plane.holds(mesh.points[n])));
        }
        self.straight_joint(problem, &facets, self.heel()).ok()
    }

    /// The heel that the scene gives the sliding plane: `[uplift] heel`, else that of the
    /// uplift table of the `[safety] joint` curve, else of the first joint that gives one.
    fn heel(&self) -> Option<[f64; 2]> {
        let own = |name: &String| self.joints.get(name).and_then(|j| j.uplift.as_ref()).and_then(|up| up.heel);
        let joints = || self.joints.values().filter_map(|j| j.uplift.as_ref().and_then(|up| up.heel));
        (self.uplift.as_ref().and_then(|up| up.heel)).or_else(|| match &self.safety.joint {
            Some(name) => own(name),
            None => joints().next(),
        })
    }

    /// The joint of `facets` from its heel to its toe: the heel is the end nearest `heel`, or
    /// the end nearest a curve with a hydrostatic load. Err: why there is none.
    fn straight_joint(
        &self,
        problem: &Problem,
        facets: &[(usize, [f64; 2])],
        heel: Option<[f64; 2]>,
    ) -> Result<JointLine, String> {
        let mesh = &problem.mesh;
        let Some(&(_, nu)) = facets.first() else { return Err("there is no contact curve".into()) };
        if facets.iter().any(|(_, n)| (n[0] - nu[0]).hypot(n[1] - nu[1]) > 1e-9) {
            return Err("not on one straight line".into());
        }
        let along = [-nu[1], nu[0]];
        let ends: Vec<[f64; 2]> =
            facets.iter().flat_map(|&(f, _)| mesh.facet(f)[..2].iter().map(|&n| mesh.points[n])).collect();
        let at = |x: &[f64; 2]| x[0] * along[0] + x[1] * along[1];
        let first = *ends.iter().min_by(|a, b| at(a).total_cmp(&at(b))).expect("a joint has faces");
        let last = *ends.iter().max_by(|a, b| at(a).total_cmp(&at(b))).expect("a joint has faces");
        // parallel joints (a lift joint above the dam's base) are not one line
        let offset = |x: &[f64; 2]| (x[0] - first[0]) * nu[0] + (x[1] - first[1]) * nu[1];
        if ends.iter().any(|x| offset(x).abs() > 1e-9 * distance(first, last)) {
            return Err("not on one straight line".into());
        }
        let water: Vec<[f64; 2]> = problem
            .neumann
            .iter()
            .filter(|bc| {
                (bc.traction.parts().iter())
                    .any(|t| matches!(t, Traction::Hydrostatic { .. } | Traction::Westergaard { .. }))
            })
            .flat_map(|bc| mesh.facets_tagged(&[bc.tag]).flat_map(|f| mesh.facet(f).to_vec()).collect::<Vec<_>>())
            .map(|n| mesh.points[n])
            .collect();
        let near = |end: [f64; 2], to: &[[f64; 2]]| to.iter().map(|&x| distance(x, end)).fold(f64::INFINITY, f64::min);
        let heel_first = match heel {
            Some(h) => distance(first, h) <= distance(last, h),
            None if water.is_empty() => {
                return Err("no curve has a hydrostatic load to show the upstream end of the joint".into())
            }
            None => near(first, &water) <= near(last, &water),
        };
        Ok(if heel_first { JointLine::new(first, last) } else { JointLine::new(last, first) })
    }

    /// The uplift diagrams of the scene on `joint`, whose curves have the contact `facets`:
    /// `[uplift]` along all of them, or each `[joints.<curve>.uplift]` along its own curve.
    fn uplift_diagrams(
        &self,
        problem: &Problem,
        topology: &Topology,
        joint: &ContactJoint,
        facets: &[(usize, [f64; 2])],
    ) -> Result<Vec<CurveUplift>, SceneError> {
        if let Some(up) = &self.uplift {
            let curves = if self.joints.is_empty() { "the contact curves are" } else { "the joint curves are" };
            let diagram = self.uplift_diagram(problem, facets, up, ("uplift", 0), curves)?;
            return Ok(vec![CurveUplift { curves: (0..joint.tags.len()).collect(), diagram }]);
        }
        // the curves of a two-body joint are those of [joints], in order
        (self.joints.iter().zip(&joint.tags).enumerate())
            .filter_map(|(curve, ((name, j), &tag))| j.uplift.as_ref().map(|up| (curve, name, tag, up)))
            .enumerate()
            .map(|(d, (curve, name, tag, up))| {
                let facets = contact_facets(&problem.mesh, topology, &[tag]);
                let (table, curves) = (format!("joints.{name}.uplift"), format!("curve '{name}' is"));
                let diagram = self.uplift_diagram(problem, &facets, up, (&table, d), &curves)?;
                Ok(CurveUplift { curves: vec![curve], diagram })
            })
            .collect()
    }

    /// The uplift diagram `d` of the table `table` (`up`) on the straight joint of `facets`,
    /// whose curves are named in the errors by `curves` ("curve 'lift' is").
    fn uplift_diagram(
        &self,
        problem: &Problem,
        facets: &[(usize, [f64; 2])],
        up: &UpliftSection,
        (table, d): (&str, usize),
        curves: &str,
    ) -> Result<Uplift, SceneError> {
        let line = self.straight_joint(problem, facets, up.heel).map_err(|why| {
            self.invalid(match why.contains("hydrostatic") {
                true => format!("{table}.heel is needed: {why}"),
                false if table == "uplift" && self.joints.len() > 1 => format!(
                    "[uplift] lays one diagram along all the joint curves, which are {why}; move it into \
                     [joints.<curve>.uplift] tables, one diagram per joint"
                ),
                false => format!("{table} needs a straight joint, and {curves} {why}"),
            })
        })?;
        let (heel, toe, length) = (line.heel, line.point(line.length), line.length);
        if let Some(given) = up.heel.filter(|&h| distance(h, heel) > HEEL_TOLERANCE * length) {
            return Err(self.invalid(format!(
                "{table}.heel = {given:?} is not an end of the joint, which runs from ({}, {}) to ({}, {}); give \
                 its upstream end",
                heel[0], heel[1], toe[0], toe[1]
            )));
        }
        self.check_headwater(&problem.mesh, table, up, heel)?;
        let g = self.loads.gravity;
        let head = |level: f64, y: f64| up.density * g * (level - y).max(0.0);
        let drains = up.drains.map(|d| Drains { distance: d.x, efficiency: d.efficiency });
        if let Some(d) = drains.filter(|d| !(d.distance > 0.0 && d.distance < length)) {
            return Err(self.invalid(format!(
                "{table}.drains.x = {} lies outside the joint: give the drains' distance from the heel, between 0 and {length:.3} m",
                d.distance
            )));
        }
        Ok(Uplift {
            line,
            upstream: head(up.headwater, heel[1]),
            downstream: up.tailwater.map_or(0.0, |t| head(t, toe[1])),
            drains,
            rule: up.crack_rule(self.loads.acceleration, self.prior_cracks.get(d).copied().unwrap_or(0.0)),
            crack: 0.0,
        })
    }

    /// Westergaard's added pressure on the reservoir: the hydrostatic curves of `neumann` at the
    /// highest level H_w, with H = H_w − the lowest point of their nodes, when `[loads]
    /// westergaard` (default: a_x ≠ 0) asks for it.
    fn add_westergaard(&self, mesh: &Mesh, neumann: &mut [Neumann]) -> Result<(), SceneError> {
        let a_x = self.loads.acceleration[0];
        if !self.loads.westergaard.unwrap_or(a_x != 0.0) {
            return Ok(());
        }
        let level_of = |t: &Traction| {
            t.parts().iter().find_map(|t| match t {
                Traction::Hydrostatic { level, .. } => Some(*level),
                _ => None,
            })
        };
        let top = neumann.iter().filter_map(|bc| level_of(&bc.traction)).fold(f64::NEG_INFINITY, f64::max);
        if self.loads.westergaard.is_none() && !top.is_finite() {
            return Ok(());
        }
        if a_x == 0.0 || !top.is_finite() {
            return Err(self.invalid(format!(
                "loads.westergaard = true needs a horizontal loads.acceleration (now {a_x}) and a reservoir: a \
                 boundary curve with a hydrostatic load"
            )));
        }
        let reservoir: Vec<usize> =
            (0..neumann.len()).filter(|&k| level_of(&neumann[k].traction) == Some(top)).collect();
        let tags: Vec<i32> = reservoir.iter().map(|&k| neumann[k].tag).collect();
        let bottom = mesh.facets_tagged(&tags).flat_map(|f| mesh.facet(f).to_vec()).map(|n| mesh.points[n][1]);
        let depth = (top - bottom.fold(f64::INFINITY, f64::min)).max(0.0);
        let added = |t: &Traction| match *t {
            Traction::Hydrostatic { density, gravity, level } => {
                Traction::Westergaard { density, gravity, level, depth, acceleration: a_x }
            }
            ref other => other.clone(),
        };
        for k in reservoir {
            neumann[k].traction = match &neumann[k].traction {
                Traction::Sum(parts) => Traction::Sum(parts.iter().map(added).collect()),
                one => added(one),
            };
        }
        Ok(())
    }

    /// Without a Dirichlet condition the joint alone holds the body. On a straight joint of
    /// normal ν and tangent τ, equilibrium needs the load resultant R to press on it against
    /// the uplift force U, N = R·ν − U ≥ 0, and the joint to carry its shear, |R·τ| ≤ the
    /// law's capacity at N.
    fn check_sliding(
        &self,
        problem: &Problem,
        topology: &Topology,
        joint: &ContactJoint,
        facets: &[(usize, [f64; 2])],
    ) -> Result<(), SceneError> {
        let nu = self.nitsche_parameters().direction.unwrap_or(facets[0].1);
        if facets.iter().any(|(_, n)| (n[0] - nu[0]).hypot(n[1] - nu[1]) > 1e-9) {
            return Ok(());
        }
        let r = problem.load_resultant(topology);
        // the uplift without a crack: a crack only adds to it
        let uplift: f64 = joint.uplift.iter().map(|up| up.diagram.force(0.0)).sum();
        let (normal, shear) = (r[0] * nu[0] + r[1] * nu[1] - uplift, r[1] * nu[0] - r[0] * nu[1]);
        // at most the largest friction's F N plus every curve's cohesion or threshold over its length
        let length = |tag: i32| problem.mesh.boundary_length(tag);
        let laws = || joint.tags.iter().zip(&joint.laws);
        let friction = laws().map(|(_, c)| c.law.capacity(normal.max(0.0), 0.0)).fold(0.0, f64::max);
        let capacity = friction + laws().map(|(&tag, c)| c.law.capacity(0.0, length(tag))).sum::<f64>();
        if normal <= 0.0 || shear.abs() > capacity {
            return Err(SceneError::NoEquilibrium {
                path: self.source.clone(),
                message: format!(
                    "no equilibrium: nothing but the joint holds the body, and the loads push along it with \
                 |T| = {:.4e} N/m against a normal force N = {normal:.4e} N/m, more than the joint law {} \
                 can carry ({capacity:.4e} N/m); raise contact.friction, contact.cohesion or \
                 contact.threshold, or support the body with a Dirichlet curve",
                    shear.abs(),
                    joint.laws.iter().map(|c| format!("{:?}", c.law)).collect::<Vec<_>>().join(", ")
                ),
            });
        }
        Ok(())
    }
}

/// Nodes of the contact `facets` with their contact direction ν (`direction`, or the outward
/// normal), and with friction also the tangent (−ν_y, ν_x): a closed frictional joint holds
/// both.
fn contact_supports(
    mesh: &Mesh,
    facets: &[(usize, [f64; 2])],
    direction: Option<[f64; 2]>,
    friction: bool,
) -> Vec<([f64; 2], [f64; 2])> {
    facets
        .iter()
        .flat_map(|&(f, normal)| {
            let nu = direction.unwrap_or(normal);
            let directions = if friction { vec![nu, [-nu[1], nu[0]]] } else { vec![nu] };
            mesh.facet(f).iter().flat_map(move |&n| directions.clone().into_iter().map(move |d| (mesh.points[n], d)))
        })
        .collect()
}

/// Tag of a contact facet whose outward normal n has ν·n ≤ 0, if any.
fn facing_away(mesh: &Mesh, facets: &[(usize, [f64; 2])], direction: Option<[f64; 2]>) -> Option<i32> {
    let nu = direction?;
    facets.iter().find(|(_, n)| n[0] * nu[0] + n[1] * nu[1] <= 0.0).map(|&(f, _)| mesh.facet_tags[f])
}

/// The facets of the contact curves (tags) with their outward normals.
fn contact_facets(mesh: &Mesh, topology: &Topology, tags: &[i32]) -> Vec<(usize, [f64; 2])> {
    mesh.facets_tagged(tags).map(|f| (f, topology.outward_normal(mesh, f))).collect()
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

/// Role given by the naming convention of bare geometry files.
fn conventional_role(name: &str) -> Option<Role> {
    match name.to_ascii_lowercase().as_str() {
        "gamma_d" | "dirichlet" => Some(Role::Dirichlet),
        "gamma_n" | "neumann" => Some(Role::Neumann),
        "gamma_c" | "contact" => Some(Role::Contact),
        _ => None,
    }
}

fn list(names: &[&str]) -> String {
    if names.is_empty() {
        "none".into()
    } else {
        names.join(", ")
    }
}
