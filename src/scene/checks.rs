//! Checks of a scene that catch inputs which would otherwise give a wrong answer without a
//! word: non-finite numbers, vectors of the wrong length, inconsistent mesh sizes, contact on
//! an interface between two meshed bodies, one curve with two roles, a combination name that
//! is not plain, an uplift headwater below the joint under a reservoir above it; and the
//! warnings of `damfem check` (defaults assumed, parameters outside their known range, an
//! uplift headwater that differs from the reservoir).

use super::validate::too_dense;
use super::{BoundarySection, ContactSection, Fix, ProjectionKind, Role, Scene, SceneError, UpliftSection};
use crate::contact::ContactJoint;
use crate::elasticity::material::MAX_DENSITY;
use crate::geometry::Point;
use crate::mesh::topology::NONE;
use crate::mesh::{Mesh, Topology};
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

/// Scene keys that hold a plane vector [x, y].
const VECTOR_KEYS: [&str; 6] = ["traction", "value", "gap_gradient", "direction", "acceleration", "heel"];

/// The vector keys a solid's scene gives with three components.
const SOLID_VECTOR_KEYS: [&str; 2] = ["traction", "value"];

/// The tensile strengths \[Pa\] of a bond below and above which the scene is warned of its
/// unit: 10 kPa to 10 MPa.
const TENSILE_STRENGTHS: [f64; 2] = [1e4, 1e7];

/// The fracture energies \[N/m\] of a bond below and above which the scene is warned of its
/// unit: 1 to 1 000 N/m.
const FRACTURE_ENERGIES: [f64; 2] = [1.0, 1e3];

/// Smallest γ₀ at which the θ = 1 and θ = 0 variants are known to converge on Scene A
/// (docs/results.md, "Numerical stability": θ = 1 with γ₀ = 1 loses coercivity); θ = −1 is stable
/// for every γ₀ > 0.
const GAMMA0_STABLE: f64 = 10.0;

/// Newton's relative tolerance above which `damfem check` and `solve` warn: the joint forces and
/// displacements then carry an error of about that relative size (the default is 10⁻¹⁰).
const LOOSE_RTOL: f64 = 1e-6;

/// Poisson's ratio above which P1 triangles lock (docs/results.md, "Numerical stability").
const P1_LOCKING_POISSON: f64 = 0.45;

/// Refuses non-finite numbers and vectors that do not have two components, naming the key.
pub(super) fn check_values(path: &Path, value: &toml::Value) -> Result<(), SceneError> {
    check_value(value, "").map_err(|message| SceneError::Invalid { path: path.into(), message })
}

fn check_value(value: &toml::Value, key: &str) -> Result<(), String> {
    match value {
        toml::Value::Float(x) if !x.is_finite() => Err(format!("{key} = {x} must be a finite number")),
        toml::Value::Table(table) => table.iter().try_for_each(|(k, v)| {
            let key = if key.is_empty() { k.clone() } else { format!("{key}.{k}") };
            check_vector(v, k, &key)?;
            check_value(v, &key)
        }),
        toml::Value::Array(items) => items.iter().try_for_each(|v| check_value(v, key)),
        _ => Ok(()),
    }
}

/// A vector key `name` (full key `key`) must hold two numbers, or three where a solid has the
/// key (`traction`, `value`: their count is checked against the geometry later).
fn check_vector(value: &toml::Value, name: &str, key: &str) -> Result<(), String> {
    match value {
        toml::Value::Array(items) if SOLID_VECTOR_KEYS.contains(&name) && !(2..=3).contains(&items.len()) => Err(
            format!("{key} has {} components; a vector has two, [x, y], or three in a solid, [x, y, z]", items.len()),
        ),
        toml::Value::Array(items)
            if VECTOR_KEYS.contains(&name) && !SOLID_VECTOR_KEYS.contains(&name) && items.len() != 2 =>
        {
            Err(format!("{key} has {} components; a plane vector has two, [x, y]", items.len()))
        }
        _ => Ok(()),
    }
}

impl Scene {
    /// Newton's keys: at least one step, a relative tolerance in [0, 1) (Newton stops at
    /// ‖F‖ ≤ rtol ‖b‖), a continuation that starts at δ ≥ 0, and no δ beside the semismooth
    /// projection, which solves at δ = 0.
    pub(super) fn check_newton(&self) -> Result<(), SceneError> {
        let c = &self.contact;
        if c.max_iter == 0 {
            return Err(self.invalid("contact.max_iter = 0 must be at least 1 (Newton steps per delta)".into()));
        }
        if !(0.0..1.0).contains(&c.rtol) {
            return Err(self.invalid(format!(
                "contact.rtol = {} must lie in [0, 1): Newton stops at a residual of rtol times the loads",
                c.rtol
            )));
        }
        if let Some(start) = c.delta_start.filter(|s| *s < 0.0) {
            return Err(self.invalid(format!("contact.delta_start = {start} must be non-negative")));
        }
        match c.delta {
            Some(delta) if c.projection == ProjectionKind::Semismooth => Err(self.invalid(format!(
                "contact.delta = {delta} has no effect with contact.projection = \"semismooth\" (--semismooth), \
                 which solves at delta = 0; remove one of the two"
            ))),
            _ => Ok(()),
        }
    }

    /// Without a contact curve or a joint the `[contact]` keys act on nothing: the first one set
    /// is refused, rather than ignored.
    pub(super) fn check_contact_unused(&self) -> Result<(), SceneError> {
        let (c, d) = (&self.contact, ContactSection::default());
        let given = |key: &str, set: bool, value: String| set.then(|| format!("{key} = {value}"));
        let keys = [
            given("gamma0", c.gamma0 != d.gamma0, c.gamma0.to_string()),
            given("theta", c.theta != d.theta, c.theta.to_string()),
            c.delta.map(|v| format!("delta = {v}")),
            c.delta_start.map(|v| format!("delta_start = {v}")),
            given("projection", c.projection != d.projection, "\"semismooth\" (--semismooth)".into()),
            given("gap", c.gap != d.gap, c.gap.to_string()),
            given("gap_gradient", c.gap_gradient != d.gap_gradient, format!("{:?}", c.gap_gradient)),
            c.direction.map(|v| format!("direction = {v:?}")),
            given("friction", c.friction != d.friction, c.friction.to_string()),
            given("cohesion", c.cohesion != d.cohesion, c.cohesion.to_string()),
            c.threshold.map(|v| format!("threshold = {v}")),
            c.tensile_strength.map(|v| format!("tensile_strength = {v}")),
            c.fracture_energy.map(|v| format!("fracture_energy = {v}")),
            given("max_iter", c.max_iter != d.max_iter, c.max_iter.to_string()),
            given("rtol", c.rtol != d.rtol, c.rtol.to_string()),
            given("load_path", c.load_path != d.load_path, c.load_path.to_string()),
        ];
        match keys.into_iter().flatten().next() {
            Some(key) => Err(self.invalid(format!(
                "contact.{key} is set, but no curve has role contact and there is no [joints] table: every \
                 interface is bonded, so it acts on nothing; give a curve role = \"contact\" or a [joints.<curve>] \
                 table, or remove the key"
            ))),
            None => Ok(()),
        }
    }

    /// The loads: g ≥ 0; a water pressure ρ_w g (H_w − y)₊ needs ρ_w > 0 and g > 0; `fix` and
    /// `value` prescribe a displacement, on Dirichlet curves only, and no value on a component
    /// that `fix` leaves free.
    pub(super) fn check_loads(&self) -> Result<(), SceneError> {
        let g = self.loads.gravity;
        if g < 0.0 {
            return Err(self.invalid(format!(
                "loads.gravity = {g} must be non-negative: the weight is (0, -rho g) and the water pressure rho_w g (level - y)"
            )));
        }
        let uplift = self.uplift.is_some() || self.joints.values().any(|j| j.uplift.is_some());
        for (name, b) in &self.boundary {
            if let Some(h) = b.hydrostatic.filter(|h| h.density <= 0.0) {
                return Err(self.invalid(format!(
                    "boundary.{name}.hydrostatic.density = {} must be positive (without water, remove the load)",
                    h.density
                )));
            }
            if let Some(h) = b.hydrostatic.filter(|h| h.density > MAX_DENSITY) {
                return Err(self.invalid(too_dense(&format!("boundary.{name}.hydrostatic.density"), h.density)));
            }
            check_silt_and_ice(name, b, g).map_err(|message| self.invalid(message))?;
            if b.hydrostatic.is_some() && g == 0.0 {
                return Err(self.invalid(format!(
                    "boundary.{name}.hydrostatic needs loads.gravity > 0: its pressure rho_w g (level - y) vanishes at g = 0"
                )));
            }
            let fixed = match b.fix {
                Fix::All => None,
                Fix::X => Some(("x", 0)),
                Fix::Y => Some(("y", 1)),
                Fix::Z => Some(("z", 2)),
            };
            let free = (0..b.value.count()).find(|&k| fixed.is_some_and(|(_, f)| f != k) && b.value.at(k) != 0.0);
            if let Some(((fixed, _), k)) = fixed.zip(free) {
                return Err(self.invalid(format!(
                    "boundary '{name}': fix = \"{fixed}\" leaves the other components free, so value[{k}] = {} has no \
                     effect; set it to 0 or fix all",
                    b.value.at(k)
                )));
            }
            if b.role != Role::Dirichlet && (b.fix != Fix::All || !b.value.is_zero()) {
                return Err(self.invalid(format!(
                    "boundary '{name}': fix and value prescribe a displacement and need role = \"dirichlet\", not {}",
                    role_name(b.role)
                )));
            }
        }
        if uplift && g == 0.0 {
            return Err(self.invalid(
                "the uplift pressure rho_w g (headwater - y) needs loads.gravity > 0: it vanishes at g = 0".into(),
            ));
        }
        Ok(())
    }

    /// A combination's name is that of its directory under the output directory of `damfem
    /// safety`: it must be plain, ASCII letters, digits, `_` and `-`, and not empty.
    pub(super) fn check_combination_names(&self) -> Result<(), SceneError> {
        let plain =
            |name: &str| !name.is_empty() && name.bytes().all(|b| b.is_ascii_alphanumeric() || b"_-".contains(&b));
        match self.combinations.keys().find(|name| !plain(name)) {
            Some(name) => Err(self.invalid(format!(
                "[combinations.{name:?}] is not a plain name: the name of a combination is that of its output \
                 directory, so it must be made of ASCII letters, digits, '_' and '-', at least one"
            ))),
            None => Ok(()),
        }
    }

    /// The reservoir at the joint's `heel`: the highest level of the hydrostatic loads on the
    /// curves through it, with its key.
    fn reservoir_at(&self, mesh: &Mesh, heel: Point) -> Option<(String, f64)> {
        let through = |tag| mesh.facets_tagged(&[tag]).any(|f| mesh.facet(f).iter().any(|&n| mesh.points[n] == heel));
        (self.boundary.iter())
            .filter_map(|(name, b)| Some((name, b.hydrostatic?.level, mesh.group(1, name)?.tag)))
            .filter(|&(_, _, tag)| through(tag))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(name, level, _)| (format!("boundary.{name}.hydrostatic.level"), level))
    }

    /// Refuses a headwater of the uplift table `table` (`up`) at or below the joint's `heel`
    /// while the reservoir there stands above it: the joint would carry no uplift.
    pub(super) fn check_headwater(
        &self,
        mesh: &Mesh,
        table: &str,
        up: &UpliftSection,
        heel: Point,
    ) -> Result<(), SceneError> {
        match self.reservoir_at(mesh, heel) {
            Some((key, level)) if up.headwater <= heel[1] && level > heel[1] => Err(self.invalid(format!(
                "{table}.headwater = {} lies at or below the joint's heel at y = {}, while {key} = {level} puts the \
                 reservoir above it, so the joint would carry no uplift; give the reservoir's level",
                up.headwater, heel[1]
            ))),
            _ => Ok(()),
        }
    }

    /// The uplift tables with their keys, in the order of the joint's diagrams: `[uplift]`, or
    /// each `[joints.<curve>.uplift]`.
    fn uplift_tables(&self) -> Vec<(String, &UpliftSection)> {
        match &self.uplift {
            Some(up) => vec![("uplift".into(), up)],
            None => (self.joints.iter())
                .filter_map(|(name, j)| Some((format!("joints.{name}.uplift"), j.uplift.as_ref()?)))
                .collect(),
        }
    }

    /// A warning for each uplift table of `joint` (on `mesh`, its joints split) whose headwater
    /// differs from the level of the reservoir at its joint's heel.
    pub fn uplift_warnings(&self, mesh: &Mesh, joint: Option<&ContactJoint>) -> Vec<String> {
        let diagrams = joint.map_or(&[][..], |j| &j.uplift);
        (self.uplift_tables().into_iter().zip(diagrams))
            .filter_map(|((table, up), d)| {
                let heel = d.diagram.line.heel;
                let (key, level) = self.reservoir_at(mesh, heel).filter(|&(_, level)| level != up.headwater)?;
                Some(format!(
                    "{table}.headwater = {} differs from {key} = {level}, the reservoir at the joint's heel ({}, {}): \
                     the uplift in the joint is that of the headwater",
                    up.headwater, heel[0], heel[1]
                ))
            })
            .collect()
    }

    /// Mesh sizes: `size_min ≤ size_max`.
    pub(super) fn check_sizes(&self) -> Result<(), SceneError> {
        match (self.mesh.size_min, self.mesh.size_max) {
            (Some(lo), Some(hi)) if lo > hi => {
                Err(self.invalid(format!("mesh.size_min = {lo} is larger than mesh.size_max = {hi}")))
            }
            _ => Ok(()),
        }
    }

    /// Refuses contact on a curve between two meshed surfaces, and a curve segment in two
    /// physical groups with different roles.
    pub(super) fn check_boundaries(&self, mesh: &Mesh) -> Result<(), SceneError> {
        self.check_one_table_per_group(mesh)?;
        let roles = self.roles(mesh)?;
        let role_of: BTreeMap<i32, (&str, Role)> = roles.iter().map(|(t, n, b)| (*t, (n.as_str(), b.role))).collect();
        let topology = Topology::new(mesh);
        let mut seen: BTreeMap<usize, (&str, Role)> = BTreeMap::new();
        for f in 0..mesh.n_facets() {
            let Some(&(name, role)) = role_of.get(&mesh.facet_tags[f]) else { continue };
            let e = topology.tagged_facet[f];
            if role == Role::Contact && topology.facet_cells[e][1] != NONE {
                return Err(self.interior_contact(mesh, name, topology.facet_cells[e]));
            }
            match seen.insert(e, (name, role)) {
                Some((other, other_role)) if other_role != role => {
                    return Err(self.invalid(format!(
                        "physical curves '{other}' ({}) and '{name}' ({}) share a segment but have different roles; \
                         give each segment one role",
                        role_name(other_role),
                        role_name(role)
                    )))
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Names are matched to physical groups ignoring case: two groups of the geometry whose
    /// names differ only in case, or two tables (`[materials]`, or `[boundary]` and `[joints]`)
    /// that name one group, are refused.
    pub(super) fn check_one_table_per_group<const D: usize>(&self, mesh: &Mesh<D>) -> Result<(), SceneError> {
        let kind = |dim: u8| ["point", "curve", "surface", "volume"][usize::from(dim).min(3)];
        let mut seen: HashMap<(u8, String), &str> = HashMap::new();
        for g in &mesh.groups {
            let Some(first) = seen.insert((g.dim, g.name.to_ascii_lowercase()), &g.name) else { continue };
            let (geometry, kind) = (self.geometry.display(), kind(g.dim));
            return Err(self.invalid(if first == g.name {
                format!(
                    "the geometry {geometry} has two physical {kind} groups named '{first}', which scene names \
                     cannot tell apart; rename one"
                )
            } else {
                format!(
                    "the geometry {geometry} has two physical groups '{first}' and '{}' whose names differ only in \
                     case, which scene names cannot tell apart; rename one",
                    g.name
                )
            }));
        }
        let curves = (self.boundary.keys().map(|n| ("boundary", n))).chain(self.joints.keys().map(|n| ("joints", n)));
        let surfaces = self.materials.keys().map(|n| ("materials", n));
        let facets = D as u8 - 1;
        for (dim, tables) in [(facets, curves.collect::<Vec<_>>()), (facets + 1, surfaces.collect())] {
            let mut seen: BTreeMap<i32, (&str, &String)> = BTreeMap::new();
            for (table, name) in tables {
                let Some(group) = mesh.group(dim, name) else { continue };
                if let Some((other_table, other)) = seen.insert(group.tag, (table, name)) {
                    return Err(self.invalid(format!(
                        "[{other_table}.{other}] and [{table}.{name}] name the same physical {} '{}' (names are \
                         matched ignoring case); keep one table",
                        kind(dim),
                        group.name
                    )));
                }
            }
        }
        Ok(())
    }

    /// The error of contact on the interface of `cells`: role contact is a rigid foundation.
    fn interior_contact(&self, mesh: &Mesh, name: &str, cells: [usize; 2]) -> SceneError {
        let [a, b] = cells.map(|c| surface_name(mesh, mesh.cell_tags[c]));
        let bonded = if self.boundary.is_empty() { "rename the curve" } else { "remove its role" };
        self.invalid(format!(
            "curve '{name}' has role contact (a rigid foundation) but lies between {a} and {b}: give it a \
             [joints.{name}] table for a joint, or {bonded} for a bonded interface"
        ))
    }

    /// What `damfem check` warns about on the `mesh` of the problem (its joints split) with
    /// its `joint`: boundary curves without a role, surfaces without a material (with the
    /// defaults they get), an uplift headwater that differs from the reservoir, γ₀ below the
    /// known stable range for θ, a Newton tolerance above 10⁻⁶, and P1 with ν > 0.45.
    pub fn warnings(&self, mesh: &Mesh, joint: Option<&ContactJoint>) -> Result<Vec<String>, SceneError> {
        let topology = Topology::new(mesh);
        let mut warnings = self.unassigned_curves(mesh, &topology)?;
        warnings.extend(self.unassigned_materials(mesh));
        warnings.extend(self.uplift_warnings(mesh, joint));
        warnings.extend(self.bond_warnings());
        let c = &self.contact;
        if !self.contact_tags(mesh)?.is_empty() && c.theta != -1.0 && c.gamma0 < GAMMA0_STABLE {
            warnings.push(format!(
                "contact.gamma0 = {} is below {GAMMA0_STABLE}, where Nitsche's method with theta = {} is known to \
                 be stable; use gamma0 >= {GAMMA0_STABLE} or theta = -1",
                c.gamma0, c.theta
            ));
        }
        if c.rtol > LOOSE_RTOL {
            warnings.push(format!(
                "contact.rtol = {} is above {LOOSE_RTOL:e}: Newton stops at a residual of that fraction of the loads, \
                 and the results carry an error of about that relative size",
                c.rtol
            ));
        }
        warnings.extend(self.locking_warnings(mesh.order));
        Ok(warnings)
    }

    /// Materials with ν > [`P1_LOCKING_POISSON`] on a mesh of `order` 1.
    pub(super) fn locking_warnings(&self, order: usize) -> Vec<String> {
        let locking = self.materials.iter().filter(|(_, m)| order == 1 && m.poisson > P1_LOCKING_POISSON);
        locking
            .map(|(name, m)| {
                format!(
                    "material '{name}': nu = {} > {P1_LOCKING_POISSON} with P1 elements, which lock near \
                     incompressibility; use mesh.order = 2",
                    m.poisson
                )
            })
            .collect()
    }

    /// A bond's tensile strength outside [`TENSILE_STRENGTHS`] or fracture energy outside
    /// [`FRACTURE_ENERGIES`], for each table that gives one: likely in the wrong unit.
    fn bond_warnings(&self) -> Vec<String> {
        let contact = [("contact".to_string(), self.contact.tensile_strength, self.contact.fracture_energy)];
        let joints =
            self.joints.iter().map(|(name, j)| (format!("joints.{name}"), j.tensile_strength, j.fracture_energy));
        let mut warnings = Vec::new();
        for (table, strength, energy) in contact.into_iter().chain(joints) {
            let ([lo, hi], [e_lo, e_hi]) = (TENSILE_STRENGTHS, FRACTURE_ENERGIES);
            if let Some(t) = strength.filter(|t| !(lo..=hi).contains(t)) {
                warnings.push(format!(
                    "{table}.tensile_strength = {t:e} Pa is outside {lo:e}–{hi:e} Pa, beyond a concrete–rock bond's \
                     0.1–1.5 MPa and concrete's tensile strength: it is in Pa"
                ));
            }
            if let Some(g) = energy.filter(|g| !(e_lo..=e_hi).contains(g)) {
                warnings.push(format!(
                    "{table}.fracture_energy = {g:e} N/m is outside {e_lo}–{e_hi} N/m, beyond a concrete–rock bond's \
                     50–300 N/m: it is in N/m (J/m²)"
                ));
            }
        }
        warnings
    }

    /// Boundary curves without a role, and boundary segments in no physical curve: both are
    /// traction-free.
    fn unassigned_curves(&self, mesh: &Mesh, topology: &Topology) -> Result<Vec<String>, SceneError> {
        let roled: Vec<i32> = self.roles(mesh)?.iter().map(|(t, _, _)| *t).collect();
        // a joint's two sides, `<curve>` and `<curve>:<surface>` once split
        let joint = |name: &str| self.joints.keys().any(|j| name.split(':').next() == Some(j.as_str()));
        let on_boundary = |f: usize| topology.is_boundary_facet(topology.tagged_facet[f]);
        let mut warnings: Vec<String> = mesh
            .groups
            .iter()
            .filter(|g| g.dim == 1 && !roled.contains(&g.tag) && !joint(&g.name))
            .filter(|g| (0..mesh.n_facets()).any(|f| mesh.facet_tags[f] == g.tag && on_boundary(f)))
            .map(|g| format!("boundary curve '{}' has no role: it is taken as free (traction-free)", g.name))
            .collect();
        let mut tagged = vec![false; topology.n_facets()];
        for &e in &topology.tagged_facet {
            tagged[e] = true;
        }
        let untagged: f64 = (0..topology.n_facets())
            .filter(|&e| topology.is_boundary_facet(e) && !tagged[e])
            .map(|e| crate::geometry::distance(mesh.points[topology.facets[e][0]], mesh.points[topology.facets[e][1]]))
            .sum();
        if untagged > 0.0 {
            warnings.push(format!(
                "{untagged:.4} m of the boundary lies in no physical curve: it is taken as free (traction-free)"
            ));
        }
        Ok(warnings)
    }

    /// Regions (surfaces of a section, volumes of a solid) without a material, and cells in no
    /// physical region: both get the default.
    pub(super) fn unassigned_materials<const D: usize>(&self, mesh: &Mesh<D>) -> Vec<String> {
        let m = Self::DEFAULT_MATERIAL;
        let default =
            format!("the default concrete (E = {:e} Pa, nu = {}, rho = {} kg/m3)", m.young, m.poisson, m.density);
        let region = if D == 3 { "volume" } else { "surface" };
        let named = |name: &str| self.materials.keys().any(|k| k.eq_ignore_ascii_case(name));
        let mut warnings: Vec<String> = mesh
            .groups
            .iter()
            .filter(|g| usize::from(g.dim) == D && !named(&g.name))
            .map(|g| format!("{region} '{}' has no material: it is given {default}", g.name))
            .collect();
        let untagged = mesh.cell_tags.iter().filter(|&&t| t == 0).count();
        if untagged > 0 {
            warnings.push(format!("{untagged} cells lie in no physical {region}: they are given {default}"));
        }
        warnings
    }
}

/// A curve's silt: ρ' in (0, MAX_DENSITY], K in (0, 10], g > 0; its ice: F ≥ 0, t > 0.
fn check_silt_and_ice(name: &str, b: &BoundarySection, g: f64) -> Result<(), String> {
    if let Some(s) = b.silt {
        let key = format!("boundary.{name}.silt");
        if s.density <= 0.0 {
            return Err(format!(
                "{key}.density = {} must be positive: the submerged density of the silt [kg/m^3]",
                s.density
            ));
        }
        if s.density > MAX_DENSITY {
            return Err(too_dense(&format!("{key}.density"), s.density));
        }
        if s.coefficient <= 0.0 || s.coefficient > 10.0 {
            return Err(format!(
                "{key}.coefficient = {} must lie in (0, 10]: the earth-pressure coefficient K (about 0.5 at rest)",
                s.coefficient
            ));
        }
        if g == 0.0 {
            return Err(format!("{key} needs loads.gravity > 0: its pressure K rho' g (level - y) vanishes at g = 0"));
        }
    }
    if let Some(i) = b.ice {
        let key = format!("boundary.{name}.ice");
        if i.force < 0.0 {
            return Err(format!("{key}.force = {} must be non-negative: the ice sheet's thrust [N/m]", i.force));
        }
        if i.thickness <= 0.0 {
            return Err(format!("{key}.thickness = {} must be positive: the ice sheet's thickness [m]", i.thickness));
        }
    }
    Ok(())
}

fn role_name(role: Role) -> &'static str {
    match role {
        Role::Dirichlet => "dirichlet",
        Role::Neumann => "neumann",
        Role::Contact => "contact",
        Role::Free => "free",
    }
}

/// Name of the physical surface `tag`, or a description of an untagged region.
fn surface_name(mesh: &Mesh, tag: i32) -> String {
    mesh.groups
        .iter()
        .find(|g| g.dim == 2 && g.tag == tag)
        .map_or_else(|| format!("a surface with no physical group (tag {tag})"), |g| format!("'{}'", g.name))
}

#[cfg(test)]
mod tests {
    use crate::mesh::PhysicalGroup;
    use crate::scene::Scene;

    #[test]
    fn two_groups_of_one_name_are_named_identical_and_of_two_cases_differing_in_case() {
        let scene = Scene::for_geometry("dam.geo".as_ref());
        let mut mesh = crate::mesh::structured::unit_square(2, 1);
        let group = |tag, name: &str| PhysicalGroup { dim: 1, tag, name: name.into() };
        mesh.groups.extend([group(90, "twin"), group(91, "twin")]);
        let message = scene.check_boundaries(&mesh).unwrap_err().to_string();
        assert!(message.contains("two physical curve groups named 'twin'"), "{message}");
        mesh.groups.last_mut().unwrap().name = "Twin".into();
        let message = scene.check_boundaries(&mesh).unwrap_err().to_string();
        assert!(message.contains("'twin' and 'Twin' whose names differ only in case"), "{message}");
    }
}
