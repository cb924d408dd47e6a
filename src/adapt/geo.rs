//! Meshes of an adaptive run from a `.geo` file through gmsh (docs/method.md §5.4).
//!
//! Adaptive steps hand the target sizes to gmsh as a background field on the previous mesh
//! and mesh the same geometry again, so the physical groups are those of the file at every
//! step. The field holds sizes measured on a mesh that the size factor already scaled, so a
//! remesh uses the factor 1: the factor again would scale the mesh by it at every step.
//! Uniform steps mesh it with every size halved: `Mesh.MeshSizeFactor` × 2^−ℓ.
//!
//! With joints between meshed bodies, each side of the joints is remeshed on its own: gmsh
//! meshes the geometry once per side, the joint curves bounding that side sized by that side's
//! cells only, and the side's cells of each mesh are put together
//! ([`merge_sides`]), so the two sides of a joint no
//! longer match.

use super::{AdaptError, CellLimit, Mesher, Refinement};
use crate::io::gmsh::{cell_limit, mesh_geo, remesh_geo, remesh_geo_side, GmshError, MeshOptions, SizeField};
use crate::mesh::interface::merge_sides;
use crate::mesh::{Mesh, Topology};
use std::collections::BTreeSet;
use std::path::PathBuf;

/// gmsh meshes of one `.geo` file.
pub struct GeoMesher {
    pub geometry: PathBuf,
    pub options: MeshOptions,
    pub refinement: Refinement,
    pub verbose: bool,
    pub allow_system_calls: bool,
    /// The physical curves that are joints between meshed bodies, each side remeshed on its own.
    pub joints: Vec<String>,
}

impl Mesher for GeoMesher {
    fn mesh(&mut self, step: usize, previous: Option<(&Mesh, &[f64])>) -> Result<Mesh, AdaptError> {
        let (path, verbose, allow) = (&self.geometry, self.verbose, self.allow_system_calls);
        match (self.refinement, previous) {
            (Refinement::Adaptive, Some((mesh, sizes))) => {
                let options = self.remesh_options();
                let field = SizeField::from_cells(mesh, sizes).map_err(|e| AdaptError::Mesh(e.into()))?;
                let sides = joint_sides(mesh, &self.joints);
                if sides.is_empty() {
                    return remesh_geo(path, &options, &field, verbose, allow).map_err(|e| AdaptError::Mesh(e.into()));
                }
                let mut parts = Vec::new();
                for &side in &sides {
                    let own = field.of_cells(|c| mesh.cell_tags[c] == side);
                    let part = remesh_geo_side(path, &options, &field, (&self.joints, side, &own), verbose, allow)
                        .map_err(|e| AdaptError::Mesh(e.into()))?;
                    let mut kept = vec![side];
                    if parts.is_empty() {
                        // the surfaces off the joints, from the first part
                        kept.extend(part.cell_tags.iter().filter(|t| !sides.contains(t)).collect::<BTreeSet<_>>());
                    }
                    parts.push((part, kept));
                }
                let joints: Vec<i32> =
                    self.joints.iter().filter_map(|name| parts[0].0.group(1, name)).map(|g| g.tag).collect();
                merge_sides(&parts, &joints)
                    .map_err(|message| AdaptError::Mesh(GmshError::Meshing { path: path.clone(), message }.into()))
            }
            _ => {
                let factor = self.options.size_factor * 0.5f64.powi(step as i32);
                mesh_geo(path, &MeshOptions { size_factor: factor, ..self.options.clone() }, verbose, allow)
                    .map_err(|e| AdaptError::Mesh(e.into()))
            }
        }
    }

    fn size_min(&self) -> Option<f64> {
        self.options.size_min
    }

    /// The cell count of the size field of an adaptive step (gmsh estimates a uniform step's
    /// from the curves before meshing, and refuses it above the limit).
    fn over_cell_limit(&self, previous: &Mesh, sizes: &[f64]) -> Option<CellLimit> {
        if self.refinement == Refinement::Uniform {
            return None;
        }
        let cells = SizeField::from_cells(previous, sizes).ok()?.cells(&self.remesh_options());
        let limit = cell_limit();
        (cells > limit as f64).then_some(CellLimit { cells, limit })
    }
}

impl GeoMesher {
    /// The options of an adaptive remesh: the scene's size bounds, the size factor 1 (see above).
    fn remesh_options(&self) -> MeshOptions {
        MeshOptions { size_factor: 1.0, ..self.options.clone() }
    }
}

/// The physical surfaces on either side of the curves `joints` of `mesh` (split: the slave
/// side keeps the curve's name, the master side's is `<curve>:<surface>`).
fn joint_sides(mesh: &Mesh, joints: &[String]) -> Vec<i32> {
    let is_joint = |name: &str| {
        joints.iter().any(|j| name == j || name.strip_prefix(j.as_str()).is_some_and(|r| r.starts_with(':')))
    };
    let tags: Vec<i32> = mesh.groups.iter().filter(|g| g.dim == 1 && is_joint(&g.name)).map(|g| g.tag).collect();
    let topology = Topology::new(mesh);
    let sides: BTreeSet<i32> = mesh.facets_tagged(&tags).map(|f| mesh.cell_tags[topology.tagged_cell(f)]).collect();
    sides.into_iter().collect()
}
