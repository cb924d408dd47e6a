//! The finite-element problem of a scene on a mesh: boundary roles, materials, loads, the
//! contact joint with its uplift diagrams and Westergaard's pressure, and the sliding plane.

use super::sections::{BoundarySection, Components, Fix, Role, UpliftSection};
use super::{list, Scene, SceneError};
use crate::adapt::{AdaptError, Model};
use crate::contact::nitsche::{Gap, Nitsche, NitscheParameters};
use crate::contact::uplift::{Drains, Uplift};
use crate::contact::{ContactJoint, CurveUplift, JointLine, LoadPath};
use crate::elasticity::{Dirichlet, Material, Neumann, Problem, Traction};
use crate::geometry::{distance, dot, norm, sub, tangent, Point, Vector};
use crate::mesh::{Mesh, Topology};
use crate::solve::NewtonOptions;
use std::collections::BTreeMap;
use std::sync::Arc;

/// The largest distance of an uplift table's `heel` from the end of its joint, as a fraction of
/// the joint's length: the heel is an end of the joint, given to the precision of its
/// coordinates.
const HEEL_TOLERANCE: f64 = 1e-3;

impl Scene {
    /// Boundary roles by physical-curve tag: the scene's tables, or the naming convention
    /// when the scene has none.
    pub fn roles<const D: usize>(&self, mesh: &Mesh<D>) -> Result<Vec<(i32, String, BoundarySection)>, SceneError> {
        let facets = D as u8 - 1;
        if self.boundary.is_empty() {
            return Ok(mesh
                .groups
                .iter()
                .filter(|g| g.dim == facets)
                .filter_map(|g| {
                    conventional_role(&g.name).map(|role| {
                        let section = BoundarySection {
                            role,
                            fix: Fix::All,
                            value: Components::default(),
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
            .map(|(name, b)| Ok((self.group_tag(mesh, facets, name, "boundary")?, name.clone(), b.clone())))
            .collect()
    }

    pub(super) fn group_tag<const D: usize>(
        &self,
        mesh: &Mesh<D>,
        dim: u8,
        name: &str,
        what: &'static str,
    ) -> Result<i32, SceneError> {
        mesh.group(dim, name).map(|g| g.tag).ok_or_else(|| SceneError::UnknownGroup {
            path: self.source.clone(),
            what,
            name: name.into(),
            kind: ["point", "curve", "surface", "volume"][usize::from(dim).min(3)],
            available: list(&mesh.group_names(dim)),
        })
    }

    /// Material of every cell: by region name, the default for unnamed regions.
    pub fn cell_materials<const D: usize>(&self, mesh: &Mesh<D>) -> Result<Vec<Material>, SceneError> {
        let mut by_tag = BTreeMap::new();
        for (name, m) in &self.materials {
            by_tag.insert(self.group_tag(mesh, D as u8, name, "material")?, *m);
        }
        Ok(mesh.cell_tags.iter().map(|t| *by_tag.get(t).unwrap_or(&Self::DEFAULT_MATERIAL)).collect())
    }

    /// Nitsche parameters of the `[contact]` table (the direction made a unit vector).
    fn nitsche_parameters(&self) -> NitscheParameters {
        let c = &self.contact;
        NitscheParameters {
            gamma0: c.gamma0,
            theta: c.theta,
            gap: Gap { constant: c.gap, gradient: c.gap_gradient },
            direction: c.direction.map(|nu| {
                let norm = norm(nu);
                [nu[0] / norm, nu[1] / norm]
            }),
        }
    }

    /// Physical tags of the curves with role "contact".
    pub(super) fn contact_tags(&self, mesh: &Mesh) -> Result<Vec<i32>, SceneError> {
        Ok(self.roles(mesh)?.into_iter().filter(|(_, _, b)| b.role == Role::Contact).map(|(tag, _, _)| tag).collect())
    }

    /// The contact joint of the curves with role "contact" on `mesh`, if there are any.
    fn joint(&self, mesh: &Mesh) -> Result<Option<ContactJoint>, SceneError> {
        let tags = self.contact_tags(mesh)?;
        Ok((!tags.is_empty()).then(|| {
            ContactJoint::uniform(tags, Vec::new(), self.contact.law(), self.nitsche_parameters())
                .with_bond(self.contact.bond())
        }))
    }

    /// The elasticity problem of this scene on `mesh` and its contact joint (None without
    /// curves of role "contact" or joints). The nodes of every joint curve are split between
    /// its two sides first.
    pub fn problem(&self, mut mesh: Mesh) -> Result<(Problem, Option<ContactJoint>), SceneError> {
        self.check_dimension(2)?;
        self.check_boundaries(&mesh)?;
        let interfaces = self.split_joints(&mut mesh)?;
        let roles = self.roles(&mesh)?;
        let g = self.loads.gravity;
        let mut dirichlet = Vec::new();
        let mut neumann = Vec::new();
        for (tag, _, b) in &roles {
            match b.role {
                Role::Dirichlet => {
                    let value = b.value.vector();
                    let fix = b.fix.components().expect("check_dimension refuses fix = \"z\" in the plane");
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
            self.check_bonds(&problem, &topology, j)?;
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
    fn heel(&self) -> Option<Point> {
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
        facets: &[(usize, Vector)],
        heel: Option<Point>,
    ) -> Result<JointLine, String> {
        let mesh = &problem.mesh;
        let Some(&(_, nu)) = facets.first() else { return Err("there is no contact curve".into()) };
        if facets.iter().any(|(_, n)| distance(nu, *n) > 1e-9) {
            return Err("not on one straight line".into());
        }
        let along = tangent(nu);
        let ends: Vec<Point> =
            facets.iter().flat_map(|&(f, _)| mesh.facet(f)[..2].iter().map(|&n| mesh.points[n])).collect();
        let at = |x: &Point| dot(*x, along);
        let first = *ends.iter().min_by(|a, b| at(a).total_cmp(&at(b))).expect("a joint has faces");
        let last = *ends.iter().max_by(|a, b| at(a).total_cmp(&at(b))).expect("a joint has faces");
        // parallel joints (a lift joint above the dam's base) are not one line
        let offset = |x: &Point| dot(sub(*x, first), nu);
        if ends.iter().any(|x| offset(x).abs() > 1e-9 * distance(first, last)) {
            return Err("not on one straight line".into());
        }
        let water: Vec<Point> = problem
            .neumann
            .iter()
            .filter(|bc| {
                (bc.traction.parts().iter())
                    .any(|t| matches!(t, Traction::Hydrostatic { .. } | Traction::Westergaard { .. }))
            })
            .flat_map(|bc| mesh.facets_tagged(&[bc.tag]).flat_map(|f| mesh.facet(f).to_vec()).collect::<Vec<_>>())
            .map(|n| mesh.points[n])
            .collect();
        let near = |end: Point, to: &[Point]| to.iter().map(|&x| distance(x, end)).fold(f64::INFINITY, f64::min);
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
        facets: &[(usize, Vector)],
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
        facets: &[(usize, Vector)],
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

    /// A bond's law is a function of Nitsche's P_γ only where the face is stiffer than the
    /// softening, γ o_c > σ_t (docs/method.md §1.13): else the first face that is not names
    /// the key.
    fn check_bonds(&self, problem: &Problem, topology: &Topology, joint: &ContactJoint) -> Result<(), SceneError> {
        if joint.laws.iter().all(|c| c.bond.is_none()) {
            return Ok(());
        }
        let nitsche = Nitsche::new(&problem.mesh, topology, &problem.materials, joint);
        let Some(face) =
            nitsche.faces.iter().find(|f| joint.laws[f.curve].bond.is_some_and(|b| !b.resolved_by(f.gamma)))
        else {
            return Ok(());
        };
        let bond = joint.laws[face.curve].bond.expect("found with a bond");
        let tag = joint.tags[face.curve];
        let name = problem.mesh.groups.iter().find(|g| g.dim == 1 && g.tag == tag).map_or("?", |g| g.name.as_str());
        let table = if joint.masters.is_empty() { "contact".to_string() } else { format!("joints.{name}") };
        let x = face.map.to_physical(face.ends[0]);
        Err(self.invalid(format!(
            "{table}.fracture_energy = {} N/m is too small for the mesh of curve '{name}': the bond softens over \
             o_c = 2 G_f/σ_t = {:.3e} m, and its face at ({:.3}, {:.3}) of length {:.3} m holds the joint only to \
             γ o_c = {:.3e} Pa, below {table}.tensile_strength = {:e} Pa (γ = gamma0 E / h); raise fracture_energy \
             or gamma0, or refine the mesh along the joint",
            bond.fracture_energy,
            bond.critical_opening(),
            x[0],
            x[1],
            face.length,
            face.gamma * bond.critical_opening(),
            bond.tensile_strength,
        )))
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
        facets: &[(usize, Vector)],
    ) -> Result<(), SceneError> {
        let nu = self.nitsche_parameters().direction.unwrap_or(facets[0].1);
        if facets.iter().any(|(_, n)| distance(nu, *n) > 1e-9) {
            return Ok(());
        }
        let r = problem.load_resultant(topology);
        // the uplift without a crack: a crack only adds to it
        let uplift: f64 = joint.uplift.iter().map(|up| up.diagram.force(0.0)).sum();
        let (normal, shear) = (dot(r, nu) - uplift, r[1] * nu[0] - r[0] * nu[1]);
        // at most the largest friction's F N plus every curve's cohesion or threshold over its length
        let length = |tag: i32| problem.mesh.boundary_length(tag);
        let laws = || joint.tags.iter().zip(&joint.laws);
        let friction = laws().map(|(_, c)| c.law.capacity(normal.max(0.0), 0.0)).fold(0.0, f64::max);
        let capacity = friction + laws().map(|(&tag, c)| c.law.capacity(0.0, length(tag))).sum::<f64>();
        // a bond holds the body in tension too, up to σ_t over its curve
        let tension: f64 = laws().filter_map(|(&tag, c)| Some(c.bond?.tensile_strength * length(tag))).sum();
        if normal + tension <= 0.0 || shear.abs() > capacity {
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

/// Nodes of the contact `facets` with their contact direction ν (`direction`, or the outward
/// normal), and with friction also the tangent (−ν_y, ν_x): a closed frictional joint holds
/// both.
fn contact_supports(
    mesh: &Mesh,
    facets: &[(usize, Vector)],
    direction: Option<Vector>,
    friction: bool,
) -> Vec<(Point, Vector)> {
    facets
        .iter()
        .flat_map(|&(f, normal)| {
            let nu = direction.unwrap_or(normal);
            let directions = if friction { vec![nu, tangent(nu)] } else { vec![nu] };
            mesh.facet(f).iter().flat_map(move |&n| directions.clone().into_iter().map(move |d| (mesh.points[n], d)))
        })
        .collect()
}

/// Tag of a contact facet whose outward normal n has ν·n ≤ 0, if any.
fn facing_away(mesh: &Mesh, facets: &[(usize, Vector)], direction: Option<Vector>) -> Option<i32> {
    let nu = direction?;
    facets.iter().find(|(_, n)| dot(*n, nu) <= 0.0).map(|&(f, _)| mesh.facet_tags[f])
}

/// The facets of the contact curves (tags) with their outward normals.
fn contact_facets(mesh: &Mesh, topology: &Topology, tags: &[i32]) -> Vec<(usize, Vector)> {
    mesh.facets_tagged(tags).map(|f| (f, topology.outward_normal(mesh, f))).collect()
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
