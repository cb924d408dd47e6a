//! Meshes of an adaptive run from a `.geo` file through gmsh (docs/method.md §5.4).
//!
//! Adaptive steps hand the target sizes to gmsh as a background field on the previous mesh
//! and mesh the same geometry again, so the physical groups are those of the file at every
//! step. The field holds sizes measured on a mesh that the size factor already scaled, so a
//! remesh uses the factor 1: the factor again would scale the mesh by it at every step.
//! Uniform steps mesh it with every size halved: `Mesh.MeshSizeFactor` × 2^−ℓ.

use super::{AdaptError, Mesher, Refinement};
use crate::io::gmsh::{mesh_geo, remesh_geo, MeshOptions, SizeField};
use crate::mesh::Mesh;
use std::path::PathBuf;

/// gmsh meshes of one `.geo` file.
pub struct GeoMesher {
    pub geometry: PathBuf,
    pub options: MeshOptions,
    pub refinement: Refinement,
    pub verbose: bool,
    pub allow_system_calls: bool,
}

impl Mesher for GeoMesher {
    fn mesh(&mut self, step: usize, previous: Option<(&Mesh, &[f64])>) -> Result<Mesh, AdaptError> {
        let (path, verbose, allow) = (&self.geometry, self.verbose, self.allow_system_calls);
        let mesh = match (self.refinement, previous) {
            (Refinement::Adaptive, Some((mesh, sizes))) => {
                let options = MeshOptions { size_factor: 1.0, ..self.options.clone() };
                SizeField::from_cells(mesh, sizes).and_then(|field| remesh_geo(path, &options, &field, verbose, allow))
            }
            _ => {
                let factor = self.options.size_factor * 0.5f64.powi(step as i32);
                mesh_geo(path, &MeshOptions { size_factor: factor, ..self.options.clone() }, verbose, allow)
            }
        };
        mesh.map_err(|e| AdaptError::Mesh(e.into()))
    }

    fn size_min(&self) -> Option<f64> {
        self.options.size_min
    }
}
