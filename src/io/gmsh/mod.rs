//! Meshing and mesh files through gmsh's C API (gmsh 4.8, `libgmsh`).
//!
//! gmsh keeps one global model and global options, and its API is not thread-safe. A
//! [`Session`] is the only way in: it holds a process-wide lock (a static `Mutex`), so
//! concurrent callers, e.g. `cargo test` threads, wait for each other. The first session
//! calls `gmshInitialize`; every session clears the model (`gmshClear`), puts back gmsh's
//! defaults for the options that shape the mesh, and silences gmsh's console (stdout): its
//! messages go to its logger, which the session reads, and to stderr if `verbose`. `gmshFinalize` is never called: gmsh lives until the process ends.
//!
//! This module and `solve::petsc` hold the crate's only `unsafe` code, here in `api`: every C call goes through
//! one `check(ierr, "gmshName")` helper that turns a non-zero `ierr` into
//! [`GmshError::Call`] with gmsh's last error, and every array gmsh allocates is owned by a
//! `GmshVec` that frees it on drop.
//!
//! Facts of gmsh 4.8 that shape this module:
//! - the API sets `General.AbortOnError` to 2, so errors are thrown. An error thrown while
//!   reading a file leaves gmsh "busy": every later open silently does nothing. One thrown
//!   while meshing terminates the process. Opening, meshing and writing therefore run with
//!   the option at 0 and report the first error gmsh logged (its logger runs throughout);
//!   with the option at 0, a `.geo` syntax error does not set `ierr` at all;
//! - reading a `.geo` runs its `SystemCall`s, and so does reading any file that does not start
//!   like a mesh (gmsh parses it as a `.geo`) or the `<file>.opt` gmsh merges after each
//!   file. The `guard` module therefore checks every file gmsh would read before it reads
//!   any, and refuses shell commands, `Exit`, file writes and includes it cannot follow;
//! - `Exit;` in a `.geo` ends the calling process.
//! - gmsh's OpenMP thread count is a per-thread setting, so every session sets it (to 1) on
//!   its own thread; otherwise remeshing with a size field from another thread than the first
//!   gives a different mesh on every call.
//!
//! Options a `.geo` file sets, other than those a session resets, persist into later sessions
//! of the same process.

mod api;
mod error;
mod ffi;
mod guard;
mod limits;
mod names;
mod read;
mod session;
mod size_field;

pub use error::GmshError;
use limits::TRIANGLE_AREA;
pub use limits::{cell_limit, set_cell_limit, set_time_limit, time_limit_exceeded, DEFAULT_CELL_LIMIT};
pub use session::Session;
pub use size_field::SizeField;

use crate::mesh::Mesh;
use std::path::Path;

/// The mesh of a model, of the plane or of space as the model has no volumes or has some.
#[derive(Debug, Clone)]
pub enum AnyMesh {
    Plane(Mesh),
    Solid(Mesh<3>),
}

impl AnyMesh {
    /// "n nodes, m cells, Pp" (with "tetrahedra" in space).
    pub fn describe(&self) -> String {
        match self {
            AnyMesh::Plane(m) => format!("{} nodes, {} cells, P{}", m.n_points(), m.n_cells(), m.order),
            AnyMesh::Solid(m) => format!("3-D: {} nodes, {} tetrahedra, P{}", m.n_points(), m.n_cells(), m.order),
        }
    }
}

/// How gmsh meshes a geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshOptions {
    /// Polynomial degree of the triangles: 1 or 2. Degree-2 midpoints sit on straight edges
    /// (`Mesh.SecondOrderLinear`), also along curved boundaries: the geometry is affine.
    pub order: usize,
    /// Multiplies every mesh size (`Mesh.MeshSizeFactor`).
    pub size_factor: f64,
    /// Lower bound on mesh sizes (`Mesh.MeshSizeMin`); `None` keeps the file's.
    pub size_min: Option<f64>,
    /// Upper bound on mesh sizes (`Mesh.MeshSizeMax`); `None` keeps the file's.
    pub size_max: Option<f64>,
    /// gmsh 2D algorithm (`Mesh.Algorithm`): 6 is Frontal-Delaunay, 5 Delaunay, 1 MeshAdapt.
    pub algorithm: i32,
}

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions { order: 1, size_factor: 1.0, size_min: None, size_max: None, algorithm: 6 }
    }
}

/// Meshes the `.geo` file `path` in 2D and reads the mesh. Unless `allow_system_calls`, a
/// file that could run shell commands is refused with [`GmshError::SystemCall`].
pub fn mesh_geo(
    path: &Path,
    options: &MeshOptions,
    verbose: bool,
    allow_system_calls: bool,
) -> Result<Mesh, GmshError> {
    mesh_geo_with(path, options, None, verbose, allow_system_calls)
}

/// Meshes the `.geo` file `path` like [`mesh_geo`], but with mesh sizes taken from `field` only
/// (see [`Session::set_size_field`]); the physical groups are those of the file. `options`
/// still scale (`size_factor`) and bound (`size_min`, `size_max`) the sizes.
pub fn remesh_geo(
    path: &Path,
    options: &MeshOptions,
    field: &SizeField,
    verbose: bool,
    allow_system_calls: bool,
) -> Result<Mesh, GmshError> {
    mesh_geo_with(path, options, Some(field), verbose, allow_system_calls)
}

/// Meshes the `.geo` file `path` like [`remesh_geo`], except that the curves of the physical
/// curve groups `joints` bounding a surface of the physical group `side` take their sizes from
/// `own` (see [`Session::set_side_size_field`]): the mesh of that side of the joints, sized
/// by its own field, whatever the other side asks for.
pub fn remesh_geo_side(
    path: &Path,
    options: &MeshOptions,
    field: &SizeField,
    (joints, side, own): (&[String], i32, &SizeField),
    verbose: bool,
    allow_system_calls: bool,
) -> Result<Mesh, GmshError> {
    let size = |session: &mut Session| session.set_side_size_field(field, joints, side, own);
    generated(path, options, size, verbose, allow_system_calls, false)?.mesh()
}

/// Meshes the `.geo` file `path` in its dimension (3 if it has volumes) and reads the mesh.
pub fn mesh_geo_any(
    path: &Path,
    options: &MeshOptions,
    verbose: bool,
    allow_system_calls: bool,
) -> Result<AnyMesh, GmshError> {
    generated(path, options, |_| Ok(()), verbose, allow_system_calls, true)?.any_mesh()
}

/// Meshes the `.geo` file `path` like [`mesh_geo_any`] and also saves gmsh's mesh file `msh`
/// (format from its extension), written under a hidden name and renamed, so that a failed
/// write leaves no partial file.
pub fn save_geo_mesh(
    path: &Path,
    options: &MeshOptions,
    msh: &Path,
    verbose: bool,
    allow_system_calls: bool,
) -> Result<AnyMesh, GmshError> {
    let mut session = generated(path, options, |_| Ok(()), verbose, allow_system_calls, true)?;
    let mesh = session.any_mesh()?;
    let file = msh.file_name().map_or_else(|| "mesh.msh".into(), |f| f.to_string_lossy().into_owned());
    let partial = msh.with_file_name(format!(".{}.{file}", std::process::id()));
    let written = session.write(&partial).and_then(|()| check_written(&partial, msh)).and_then(|()| {
        std::fs::rename(&partial, msh).map_err(|e| GmshError::Write { path: msh.into(), message: e.to_string() })
    });
    if written.is_err() {
        std::fs::remove_file(&partial).ok();
    }
    written.map(|()| mesh)
}

/// Checks that gmsh wrote all of `partial`, the future `msh`: gmsh does not report a full disk,
/// so the file is synced and must end with the closing line of a section (`$End…`).
fn check_written(partial: &Path, msh: &Path) -> Result<(), GmshError> {
    use std::io::{Read, Seek, SeekFrom};
    let fail = |message: String| GmshError::Write { path: msh.into(), message };
    let mut file = std::fs::File::open(partial).map_err(|e| fail(e.to_string()))?;
    file.sync_all().map_err(|e| fail(e.to_string()))?;
    let length = file.metadata().map_err(|e| fail(e.to_string()))?.len();
    let mut tail = Vec::new();
    file.seek(SeekFrom::Start(length.saturating_sub(64)))
        .and_then(|_| file.read_to_end(&mut tail))
        .map_err(|e| fail(e.to_string()))?;
    let tail = String::from_utf8_lossy(&tail);
    match tail.trim_end().lines().last() {
        Some(line) if line.starts_with("$End") => Ok(()),
        _ => Err(fail(format!("the file was cut short after {length} bytes (is the disk full?)"))),
    }
}

/// [`mesh_geo`], with mesh sizes from `field` if given.
fn mesh_geo_with(
    path: &Path,
    options: &MeshOptions,
    field: Option<&SizeField>,
    verbose: bool,
    allow_system_calls: bool,
) -> Result<Mesh, GmshError> {
    let size = |session: &mut Session| field.map_or(Ok(()), |field| session.set_size_field(field));
    generated(path, options, size, verbose, allow_system_calls, false)?.mesh()
}

/// A session holding the mesh of the `.geo` file `path` in its dimension, with the mesh
/// sizes that `size` sets once the file is open; unless `solid`, a model with volumes is
/// refused before it is meshed.
fn generated(
    path: &Path,
    options: &MeshOptions,
    size: impl FnOnce(&mut Session) -> Result<(), GmshError>,
    verbose: bool,
    allow_system_calls: bool,
    solid: bool,
) -> Result<Session, GmshError> {
    let _deadline = limits::Deadline::start(path);
    let mut session = Session::new(verbose)?;
    session.open_geo(path, allow_system_calls)?;
    if !solid && session.dimension() == 3 {
        return Err(GmshError::Limit { path: path.into(), reason: session::SOLID_REFUSED.into() });
    }
    session.set_options(options)?;
    size(&mut session)?;
    session.generate()?;
    Ok(session)
}

/// Reads the gmsh mesh file `path` (`.msh`) of a plane model.
pub fn read_msh(path: &Path, verbose: bool) -> Result<Mesh, GmshError> {
    opened_msh(path, verbose)?.mesh()
}

/// Reads the gmsh mesh file `path` (`.msh`) in its dimension.
pub fn read_msh_any(path: &Path, verbose: bool) -> Result<AnyMesh, GmshError> {
    opened_msh(path, verbose)?.any_mesh()
}

fn opened_msh(path: &Path, verbose: bool) -> Result<Session, GmshError> {
    let _deadline = limits::Deadline::start(path);
    let mut session = Session::new(verbose)?;
    session.open_msh(path)?;
    Ok(session)
}

#[cfg(test)]
mod tests {
    use super::check_written;

    #[test]
    fn a_msh_cut_short_is_refused() {
        let dir = std::env::temp_dir().join(format!("damfem-msh-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let partial = dir.join(".partial.msh");
        let whole = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n$EndNodes\n";
        std::fs::write(&partial, whole).unwrap();
        check_written(&partial, &dir.join("a.msh")).unwrap();
        std::fs::write(&partial, &whole[..whole.len() - 12]).unwrap();
        let message = check_written(&partial, &dir.join("a.msh")).unwrap_err().to_string();
        assert!(message.contains("a.msh") && message.contains("cut short"), "{message}");
        std::fs::remove_dir_all(dir).unwrap();
    }
}
