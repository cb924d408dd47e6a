//! The sections of a scene file: the serde types of its tables, with their defaults and the
//! loads and joint laws they describe.

use crate::contact::nitsche::NitscheParameters;
use crate::contact::uplift::CrackRule;
use crate::contact::{Bond, JointLaw};
use crate::elasticity::{BodyForce, Traction};
use crate::geometry::{Point, Vector};
use serde::Deserialize;
use std::path::PathBuf;

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
    /// Every component ("both" in the plane).
    #[default]
    #[serde(alias = "both")]
    All,
    X,
    Y,
    /// The vertical component of a solid.
    Z,
}

impl Fix {
    /// The fixed components of a D-dimensional displacement; None: z in the plane.
    pub fn components<const D: usize>(self) -> Option<[bool; D]> {
        let one = |k: usize| (k < D).then(|| std::array::from_fn(|a| a == k));
        match self {
            Fix::All => Some([true; D]),
            Fix::X => one(0),
            Fix::Y => one(1),
            Fix::Z => one(2),
        }
    }
}

/// A vector of a scene file: \[x, y\] in a plane scene, \[x, y, z\] in a solid one; the
/// geometry decides which ([`Scene::check_dimension`](super::Scene::check_dimension) checks
/// the count). Not given: 0.
#[derive(Debug, Clone, PartialEq, Default, Deserialize)]
#[serde(transparent)]
pub struct Components(Vec<f64>);

impl Components {
    /// The number of components given.
    pub fn count(&self) -> usize {
        self.0.len()
    }

    /// The vector of dimension N.
    pub fn vector<const N: usize>(&self) -> [f64; N] {
        std::array::from_fn(|k| self.0.get(k).copied().unwrap_or(0.0))
    }

    /// Component k (0 beyond those given).
    pub fn at(&self, k: usize) -> f64 {
        self.0.get(k).copied().unwrap_or(0.0)
    }

    pub fn is_zero(&self) -> bool {
        self.0.iter().all(|&x| x == 0.0)
    }
}

impl<const N: usize> From<[f64; N]> for Components {
    fn from(v: [f64; N]) -> Self {
        Components(v.to_vec())
    }
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
    /// Dirichlet: fixed components (default all).
    #[serde(default)]
    pub fix: Fix,
    /// Dirichlet: prescribed displacement \[m\] (default 0).
    #[serde(default)]
    pub value: Components,
    /// Neumann: constant traction \[Pa\].
    pub traction: Option<Components>,
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
    pub(super) fn traction(&self, g: f64) -> Traction {
        let main = match (&self.traction, self.hydrostatic) {
            (_, Some(h)) => Some(Traction::Hydrostatic { density: h.density, gravity: g, level: h.level }),
            (Some(t), None) => Some(Traction::Constant(t.vector())),
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
    pub heel: Option<Point>,
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
    pub fn crack_kind(&self, a: Vector) -> CrackKind {
        let seismic = a != [0.0; 2];
        match self.crack.unwrap_or(if seismic { CrackKind::Unchanged } else { CrackKind::Full }) {
            CrackKind::Unchanged | CrackKind::Dry if !seismic => CrackKind::Full,
            kind => kind,
        }
    }

    /// The crack's rule under the acceleration `a`, with s₀ = `prior` the crack of the state
    /// before the earthquake.
    pub fn crack_rule(&self, a: Vector, prior: f64) -> CrackRule {
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
    pub acceleration: Vector,
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
    pub(super) fn body_force(&self) -> BodyForce {
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
    pub gap_gradient: Vector,
    /// Normal of a flat foundation, pointing from the body into it: the direction ν of u·ν ≤ g
    /// and of the contact traction. Default: the outward normal of each contact face.
    pub direction: Option<Vector>,
    /// Coulomb friction coefficient F = tan φ (0: frictionless).
    pub friction: f64,
    /// Cohesion c \[Pa\] of a Mohr–Coulomb joint, on its closed part.
    pub cohesion: f64,
    /// Tresca threshold s \[Pa\] (exclusive with `friction`).
    pub threshold: Option<f64>,
    /// Tensile strength σ_t \[Pa\] of a cohesive joint (with `fracture_energy`).
    pub tensile_strength: Option<f64>,
    /// Fracture energy G_f \[N/m\] of a cohesive joint (with `tensile_strength`).
    pub fracture_energy: Option<f64>,
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

    /// The bond of the keys `tensile_strength` and `fracture_energy` (checked: both or neither).
    pub fn bond(&self) -> Option<Bond> {
        bond_of(self.tensile_strength, self.fracture_energy)
    }
}

/// The bond of the keys `tensile_strength` and `fracture_energy`, if both are given.
pub(super) fn bond_of(tensile_strength: Option<f64>, fracture_energy: Option<f64>) -> Option<Bond> {
    Some(Bond { tensile_strength: tensile_strength?, fracture_energy: fracture_energy? })
}

/// The joint law of the friction keys `threshold` (Tresca), `friction` and `cohesion`.
pub(super) fn law_of(threshold: Option<f64>, friction: f64, cohesion: f64) -> JointLaw {
    match (threshold, friction, cohesion) {
        (Some(threshold), _, _) => JointLaw::Tresca { threshold },
        (None, friction, 0.0) if friction > 0.0 => JointLaw::Coulomb { friction },
        (None, 0.0, 0.0) => JointLaw::Frictionless,
        (None, friction, cohesion) => JointLaw::MohrCoulomb { friction, cohesion },
    }
}

impl Default for ContactSection {
    fn default() -> Self {
        ContactSection {
            gamma0: NitscheParameters::GAMMA0,
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
            tensile_strength: None,
            fracture_energy: None,
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
