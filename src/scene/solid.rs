//! The problem of a scene on a solid's mesh (a geometry with volumes): materials by physical
//! volume, roles by physical surface, vectors of three components, gravity along −z. What
//! the solid does not model yet (contact, joints, uplift, seismic loads, silt and ice, load
//! combinations) is refused by its key.

use super::sections::Role;
use super::{Scene, SceneError};
use crate::elasticity::solid::{Solid, SolidBody, SolidDirichlet, SolidNeumann, SolidTraction};
use crate::mesh::Mesh;
use std::sync::Arc;

/// The tables of a scene that a solid has no use for yet.
const PLANE_ONLY: [&str; 5] = ["contact", "joints", "uplift", "combinations", "safety"];

impl Scene {
    /// Every vector the scene gives has `dimension` components, and a plane scene fixes no z.
    pub fn check_dimension(&self, dimension: usize) -> Result<(), SceneError> {
        let geometry = if dimension == 3 { "a solid (it has volumes)" } else { "a plane section" };
        for (name, b) in &self.boundary {
            let vectors = [("value", Some(&b.value)), ("traction", b.traction.as_ref())];
            for (key, v) in vectors.into_iter().filter_map(|(k, v)| v.map(|v| (k, v))) {
                if v.count() != 0 && v.count() != dimension {
                    return Err(self.invalid(format!(
                        "boundary.{name}.{key} has {} components, but {} is {geometry}: give {dimension}",
                        v.count(),
                        self.geometry.display()
                    )));
                }
            }
            if dimension == 2 && b.fix == super::Fix::Z {
                return Err(self.invalid(format!(
                    "boundary.{name}.fix = \"z\", but {} is a plane section: fix \"x\", \"y\" or \"all\"",
                    self.geometry.display()
                )));
            }
        }
        Ok(())
    }

    /// What `damfem check` and `solve` warn about on a solid's `mesh`: physical surfaces on
    /// the boundary without a role (traction-free), volumes without a material and cells in no
    /// physical volume (with the defaults they get), and P1 with ν > 0.45.
    pub fn solid_warnings(&self, mesh: &Mesh<3>) -> Result<Vec<String>, SceneError> {
        let roled: Vec<i32> = self.roles(mesh)?.iter().map(|(t, _, _)| *t).collect();
        let interior = mesh.interior_facets();
        let mut warnings: Vec<String> = mesh
            .groups
            .iter()
            .filter(|g| g.dim == 2 && !roled.contains(&g.tag))
            .filter(|g| mesh.facets_tagged(&[g.tag]).any(|f| !interior[f]))
            .map(|g| format!("boundary surface '{}' has no role: it is taken as free (traction-free)", g.name))
            .collect();
        warnings.extend(self.unassigned_materials(mesh));
        warnings.extend(self.locking_warnings(mesh.order));
        Ok(warnings)
    }

    /// The elasticity problem of this scene on the solid's `mesh`.
    pub fn solid(&self, mesh: Mesh<3>) -> Result<Solid, SceneError> {
        self.check_dimension(3)?;
        self.refuse_plane_only()?;
        self.check_one_table_per_group(&mesh)?;
        let interior = mesh.interior_facets();
        let g = self.loads.gravity;
        let (mut dirichlet, mut neumann) = (Vec::new(), Vec::new());
        for (tag, name, b) in self.roles(&mesh)? {
            match b.role {
                Role::Dirichlet => {
                    let value = b.value.vector();
                    let fix = b.fix.components().expect("every fix has a component in 3-D");
                    dirichlet.push(SolidDirichlet { tag, fix, value: Arc::new(move |_| value) });
                }
                Role::Neumann => {
                    if let Some(key) = [("silt", b.silt.is_some()), ("ice", b.ice.is_some())].iter().find(|k| k.1) {
                        return Err(self.invalid(format!(
                            "boundary.{name}.{}: silt and ice on a solid are not available yet",
                            key.0
                        )));
                    }
                    if mesh.facets_tagged(&[tag]).any(|f| interior[f]) {
                        return Err(self.invalid(format!(
                            "boundary.{name}: physical surface '{name}' lies inside the solid (between two of its \
                             volumes), where a load has no outward side; give the load to a surface on the boundary"
                        )));
                    }
                    let traction = match (&b.traction, b.hydrostatic) {
                        (_, Some(h)) => SolidTraction::Hydrostatic { density: h.density, gravity: g, level: h.level },
                        (Some(t), None) => SolidTraction::Constant(t.vector()),
                        (None, None) => SolidTraction::Constant([0.0; 3]),
                    };
                    neumann.push(SolidNeumann { tag, traction });
                }
                Role::Contact => {
                    return Err(self.invalid(format!(
                        "boundary.{name}: role = \"contact\" on a solid is not available yet; give it role \
                         \"dirichlet\", \"neumann\" or \"free\""
                    )))
                }
                Role::Free => {}
            }
        }
        let materials = self.cell_materials(&mesh)?;
        let solid = Solid { mesh, materials, dirichlet, neumann, body: SolidBody::Weight(g) };
        if let Some((body, motion)) = solid.free_rigid_motion() {
            let mesh = &solid.mesh;
            let bodies = mesh.bodies();
            let names: Vec<String> = (mesh.groups.iter())
                .filter(|g| g.dim == 3 && (0..mesh.n_cells()).any(|c| bodies[c] == body && mesh.cell_tags[c] == g.tag))
                .map(|g| format!("'{}'", g.name))
                .collect();
            return Err(self.invalid(format!(
                "nothing holds the body of {} against {motion}: its Dirichlet surfaces leave it free; fix more \
                 components (role = \"dirichlet\", fix = \"x\", \"y\", \"z\" or \"all\")",
                if names.is_empty() { "the unnamed volumes".into() } else { names.join(", ") }
            )));
        }
        Ok(solid)
    }

    /// Refuses the tables and keys a solid does not model yet, by name.
    fn refuse_plane_only(&self) -> Result<(), SceneError> {
        if let Some(table) = PLANE_ONLY
            .iter()
            .find(|t| self.table.contains_key(**t) || (**t == "combinations" && !self.combinations.is_empty()))
        {
            return Err(self.invalid(format!(
                "[{table}]: a solid (a geometry with volumes) has no contact, joints, uplift, load combinations or \
                 safety factors yet; remove the table to solve its elasticity"
            )));
        }
        let a = self.loads.acceleration;
        if a != [0.0; 2] || self.loads.westergaard.is_some() {
            return Err(self.invalid(
                "loads.acceleration and loads.westergaard: a solid has no seismic loads yet; remove them".into(),
            ));
        }
        Ok(())
    }
}
