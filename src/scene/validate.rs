//! The checks of a scene's values that need no mesh: ranges, exclusive keys, the uplift
//! tables, the `[safety]` joint and what the adaptive loop and the error estimate accept.

use super::sections::{ContactSection, ProjectionKind, Role, UpliftSection};
use super::{Scene, SceneError};
use crate::elasticity::material::MAX_DENSITY;
use crate::geometry::norm;

impl ContactSection {
    /// The first friction key out of range, as "key = value must …".
    fn check_law(&self) -> Result<(), String> {
        check_law("contact", self.threshold, self.friction, self.cohesion)?;
        check_bond("contact", self.tensile_strength, self.fracture_energy)
    }
}

/// "key = density exceeds …" for a water density above [`MAX_DENSITY`].
pub(super) fn too_dense(key: &str, density: f64) -> String {
    format!("{key} = {density:e} kg/m^3 exceeds {MAX_DENSITY:e} kg/m^3, a hundred times water's (it is in kg/m^3)")
}

/// Largest friction coefficient accepted: tan 89.4°, beyond any joint.
const MAX_FRICTION: f64 = 100.0;
/// Largest cohesion or Tresca threshold accepted \[Pa\]: a thousand times concrete's
/// compressive strength.
const MAX_STRENGTH: f64 = 1e10;

/// The first friction key of the table `table` out of range, as "table.key = value must …".
pub(super) fn check_law(table: &str, threshold: Option<f64>, friction: f64, cohesion: f64) -> Result<(), String> {
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

/// The bond keys of the table `table`: both or neither, each positive and finite, σ_t at most
/// [`MAX_STRENGTH`].
pub(super) fn check_bond(
    table: &str,
    tensile_strength: Option<f64>,
    fracture_energy: Option<f64>,
) -> Result<(), String> {
    let keys = [("tensile_strength", tensile_strength), ("fracture_energy", fracture_energy)];
    if let Some((key, Some(value))) = keys.iter().find(|(_, v)| v.is_some_and(|v| !(v.is_finite() && v > 0.0))) {
        return Err(format!("{table}.{key} = {value} must be a positive number"));
    }
    match (tensile_strength, fracture_energy) {
        (Some(t), _) if t > MAX_STRENGTH => Err(format!(
            "{table}.tensile_strength = {t:e} Pa exceeds {MAX_STRENGTH:e} Pa, a thousand times concrete's compressive \
             strength (it is in Pa)"
        )),
        (Some(_), None) | (None, Some(_)) => {
            let (given, missing) = match tensile_strength {
                Some(_) => ("tensile_strength", "fracture_energy"),
                None => ("fracture_energy", "tensile_strength"),
            };
            Err(format!(
                "{table}.{given} is set without {table}.{missing}: a cohesive joint needs both, its tensile strength \
                 in Pa and its fracture energy in N/m"
            ))
        }
        _ => Ok(()),
    }
}

impl Scene {
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
        if let Some(nu) = c.direction.filter(|nu| !(norm(*nu) > 0.0 && nu.iter().all(|x| x.is_finite()))) {
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

    /// The values that need no mesh of the uplift table `table` (`uplift` or
    /// `joints.<curve>.uplift`).
    pub(super) fn check_uplift(&self, table: &str, up: &UpliftSection) -> Result<(), SceneError> {
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
}
