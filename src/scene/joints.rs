//! `[joints.<curve>]`: joints between two meshed bodies (docs/method.md §1.10). The curve is
//! shared by two physical surfaces; its nodes are split between them
//! ([`crate::mesh::interface`]), and the two sides meet by two-body Nitsche contact.

use super::{Role, Scene, SceneError, UpliftSection};
use crate::contact::nitsche::NitscheParameters;
use crate::contact::{ContactJoint, CurveLaw, JointLaw};
use crate::elasticity::Problem;
use crate::geometry::{tangent, Point, Vector};
use crate::mesh::interface::{self, Interface};
use crate::mesh::{Mesh, Topology};
use serde::Deserialize;

/// One `[joints.<curve>]` table.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct JointSection {
    /// γ₀ in γ = γ₀ E / h_F, E and h_F of the slave side.
    pub gamma0: f64,
    /// θ: 1 symmetric, 0 incomplete, −1 skew-symmetric.
    pub theta: f64,
    /// Coulomb friction coefficient F = tan φ (0: frictionless).
    pub friction: f64,
    /// Cohesion c \[Pa\] of a Mohr–Coulomb joint, on its closed part.
    pub cohesion: f64,
    /// Tresca threshold s \[Pa\] (exclusive with `friction` and `cohesion`).
    pub threshold: Option<f64>,
    /// Tensile strength σ_t \[Pa\] of a cohesive joint (with `fracture_energy`).
    pub tensile_strength: Option<f64>,
    /// Fracture energy G_f \[N/m\] of a cohesive joint (with `tensile_strength`).
    pub fracture_energy: Option<f64>,
    /// The physical surface on the slave side (its faces carry the quadrature); default: the
    /// side of smaller physical tag.
    pub slave: Option<String>,
    /// The pore pressure in this joint, along its own straight curve (docs/method.md §1.8).
    pub uplift: Option<UpliftSection>,
}

impl Default for JointSection {
    fn default() -> Self {
        JointSection {
            gamma0: NitscheParameters::GAMMA0,
            theta: 0.0,
            friction: 0.0,
            cohesion: 0.0,
            threshold: None,
            tensile_strength: None,
            fracture_energy: None,
            slave: None,
            uplift: None,
        }
    }
}

impl JointSection {
    /// The joint law of the friction keys.
    pub fn law(&self) -> JointLaw {
        super::sections::law_of(self.threshold, self.friction, self.cohesion)
    }

    /// The law and Nitsche parameters of the joint.
    pub fn curve_law(&self) -> CurveLaw {
        let parameters = NitscheParameters { gamma0: self.gamma0, theta: self.theta, ..Default::default() };
        let bond = super::sections::bond_of(self.tensile_strength, self.fracture_energy);
        CurveLaw { law: self.law(), bond, parameters }
    }

    /// The first key out of range, as "joints.<name>.key = value must …".
    fn check(&self, name: &str) -> Result<(), String> {
        if !(self.gamma0 > 0.0 && self.gamma0.is_finite()) {
            return Err(format!("joints.{name}.gamma0 = {} must be positive and finite", self.gamma0));
        }
        if ![1.0, 0.0, -1.0].contains(&self.theta) {
            return Err(format!("joints.{name}.theta = {} must be 1, 0 or -1", self.theta));
        }
        let table = format!("joints.{name}");
        super::validate::check_law(&table, self.threshold, self.friction, self.cohesion)?;
        super::validate::check_bond(&table, self.tensile_strength, self.fracture_energy)
    }
}

impl Scene {
    /// The `[joints]` checks that need no mesh: each table's values (each joint has its own law,
    /// Nitsche parameters and uplift); no joint curve with a `[boundary]` role; `[uplift]`,
    /// which lays one diagram along all the joints, not beside a joint's own; no rigid contact
    /// beside joints (not supported yet).
    pub(super) fn check_joints(&self) -> Result<(), SceneError> {
        for (name, joint) in &self.joints {
            joint.check(name).map_err(|message| self.invalid(message))?;
            if let Some(up) = &joint.uplift {
                self.check_uplift(&format!("joints.{name}.uplift"), up)?;
                if self.uplift.is_some() {
                    return Err(self.invalid(format!(
                        "curve '{name}' has two uplift diagrams: [uplift] lays one along every joint curve, and \
                         [joints.{name}.uplift] gives the curve its own; move [uplift] into [joints.<curve>.uplift] \
                         tables, or remove [joints.{name}.uplift]"
                    )));
                }
            }
            let rigid = self.boundary.get(name).is_some_and(|b| b.role == Role::Contact);
            let only_uplift = *joint == JointSection { uplift: joint.uplift.clone(), ..Default::default() };
            if rigid && joint.uplift.is_some() && only_uplift {
                return Err(self.invalid(format!(
                    "[joints.{name}.uplift] is for a joint between two meshed bodies, and '{name}' has role contact \
                     (a rigid foundation), whose uplift is [uplift]: move the table there"
                )));
            }
            if self.boundary.contains_key(name) {
                return Err(self.invalid(format!(
                    "curve '{name}' is both a joint ([joints.{name}]) and a boundary curve ([boundary.{name}]); \
                     remove one of the two tables"
                )));
            }
        }
        let Some(first) = self.joints.keys().next() else { return Ok(()) };
        if let Some((name, _)) = self.boundary.iter().find(|(_, b)| b.role == Role::Contact) {
            return Err(self.invalid(format!(
                "boundary '{name}' has role contact beside [joints]: a rigid foundation and joints between meshed \
                 bodies in one scene are not supported yet"
            )));
        }
        let (c, d) = (&self.contact, super::ContactSection::default());
        let rigid_keys = [
            ("gamma0", c.gamma0 != d.gamma0),
            ("theta", c.theta != d.theta),
            ("friction", c.friction != d.friction),
            ("cohesion", c.cohesion != d.cohesion),
            ("threshold", c.threshold.is_some()),
            ("tensile_strength", c.tensile_strength.is_some()),
            ("fracture_energy", c.fracture_energy.is_some()),
            ("gap", c.gap != d.gap),
            ("gap_gradient", c.gap_gradient != d.gap_gradient),
            ("direction", c.direction.is_some()),
        ];
        if let Some((key, _)) = rigid_keys.iter().find(|(_, set)| *set) {
            return Err(self.invalid(format!(
                "contact.{key} is set, but it applies to curves of role contact only; a joint takes its law and \
                 Nitsche parameters from [joints.{first}]"
            )));
        }
        Ok(())
    }

    /// Splits the nodes of every joint curve of `mesh` between its two sides; the interfaces.
    pub(super) fn split_joints(&self, mesh: &mut Mesh) -> Result<Vec<Interface>, SceneError> {
        let mut interfaces = Vec::new();
        // every joint curve found before the first split adds the groups of its sides
        let curves = self.joint_tags(mesh)?;
        for ((name, joint), curve) in self.joints.iter().zip(curves) {
            let sides = interface::sides(mesh, &Topology::new(mesh), curve).map_err(|m| self.invalid(m))?;
            let slave = match &joint.slave {
                None => sides[0],
                Some(surface) => {
                    let tag = self.group_tag(mesh, 2, surface, "slave")?;
                    if !sides.contains(&tag) {
                        let side =
                            |t: i32| mesh.groups.iter().find(|g| g.dim == 2 && g.tag == t).map_or("?", |g| &g.name);
                        return Err(self.invalid(format!(
                            "joints.{name}.slave = '{surface}' is not a side of the joint: the curve separates '{}' \
                             from '{}'",
                            side(sides[0]),
                            side(sides[1])
                        )));
                    }
                    tag
                }
            };
            interfaces.push(interface::split(mesh, curve, slave).map_err(|m| self.invalid(m))?);
        }
        Ok(interfaces)
    }

    /// The physical tags of the joint curves on `mesh` (their slave sides once split).
    pub(super) fn joint_tags(&self, mesh: &Mesh) -> Result<Vec<i32>, SceneError> {
        self.joints.keys().map(|name| self.group_tag(mesh, 1, name, "joint")).collect()
    }

    /// Whether a joint of the scene (or `[contact]`, without joints) has a tangential law.
    pub fn has_friction(&self) -> bool {
        match self.joints.is_empty() {
            true => self.contact.law().has_friction(),
            false => self.joints.values().any(|j| j.law().has_friction()),
        }
    }

    /// Each body (a set of cells connected through their nodes) must be held against rigid
    /// motions by its Dirichlet curves and its joint facets (their normals, and with friction
    /// their tangents too). Err names the body, by its surfaces, and the motion left free.
    pub(super) fn check_bodies_held(&self, problem: &Problem, joint: &ContactJoint) -> Result<(), SceneError> {
        let mesh = &problem.mesh;
        let topology = Topology::new(mesh);
        let body = mesh.bodies();
        // the facets of both sides of every joint, with whether its law has friction
        let facets: Vec<(usize, bool)> = (joint.tags.iter().chain(&joint.masters))
            .zip(joint.laws.iter().chain(&joint.laws))
            .flat_map(|(tag, c)| mesh.facets_tagged(std::slice::from_ref(tag)).map(move |f| (f, c.law.has_friction())))
            .collect();
        for b in 0..=body.iter().copied().max().unwrap_or(0) {
            let nodes: Vec<bool> = {
                let mut nodes = vec![false; mesh.n_points()];
                (0..mesh.n_cells())
                    .filter(|&c| body[c] == b)
                    .for_each(|c| mesh.cell(c).iter().for_each(|&n| nodes[n] = true));
                nodes
            };
            let supports: Vec<(Point, Vector)> = facets
                .iter()
                .filter(|&&(f, _)| body[topology.tagged_cell(f)] == b)
                .flat_map(|&(f, friction)| {
                    let nu = topology.outward_normal(mesh, f);
                    let directions = if friction { vec![nu, tangent(nu)] } else { vec![nu] };
                    mesh.facet(f)
                        .iter()
                        .flat_map(move |&n| directions.clone().into_iter().map(move |d| (mesh.points[n], d)))
                })
                .collect();
            if let Some(motion) = problem.free_rigid_motion_of(&nodes, &supports) {
                let names: Vec<String> = (mesh.groups.iter())
                    .filter(|g| g.dim == 2 && (0..mesh.n_cells()).any(|c| body[c] == b && mesh.cell_tags[c] == g.tag))
                    .map(|g| format!("'{}'", g.name))
                    .collect();
                return Err(self.invalid(format!(
                    "nothing holds the body of {} against {motion}: its joints and Dirichlet curves leave it free; \
                     give the joint friction, bond part of the interface, or give the body a Dirichlet curve",
                    names.join(", ")
                )));
            }
        }
        Ok(())
    }

    /// The two-body contact joint of `interfaces`, one per `[joints]` table in order, each curve
    /// with its table's law and Nitsche parameters (None without joints).
    pub(super) fn two_body_joint(&self, interfaces: &[Interface]) -> Option<ContactJoint> {
        (!interfaces.is_empty()).then(|| ContactJoint {
            tags: interfaces.iter().map(|i| i.slave_curve).collect(),
            masters: interfaces.iter().map(|i| i.master_curve).collect(),
            laws: self.joints.values().map(JointSection::curve_law).collect(),
            uplift: Vec::new(),
            slip_origin: None,
        })
    }
}
