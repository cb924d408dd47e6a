//! Errors of the gmsh interface: each one prints as one sentence naming the file.

use crate::geometry::{Point, Point3};
use std::path::PathBuf;

/// Everything that can go wrong while opening, meshing, reading or writing through gmsh.
#[derive(Debug, thiserror::Error)]
pub enum GmshError {
    /// The file to open does not exist.
    #[error("cannot open {}: file not found", .path.display())]
    NotFound { path: PathBuf },
    /// The path given as a file is a directory.
    #[error("cannot open {}: it is a directory, not a file", .path.display())]
    Directory { path: PathBuf },
    /// The path given as a file is something else than a regular file (a FIFO, a device, a
    /// loop of symbolic links); `reason` says what.
    #[error("cannot open {}: {reason}", .path.display())]
    NotAFile { path: PathBuf, reason: String },
    /// The model breaks one of the limits checked before meshing (see `limits`), e.g. it is
    /// 3-D or its mesh would have too many cells.
    #[error("cannot use {}: {reason}", .path.display())]
    Limit { path: PathBuf, reason: String },
    /// A file to check for shell commands exists but cannot be read.
    #[error("cannot read {}: {source}", .path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// `path` (the opened file or one it includes) could make gmsh run a shell command;
    /// `reason` completes the sentence, e.g. "uses SystemCall, which runs shell commands".
    #[error("refusing to open {}: line {line} {reason} (--allow-system-calls opens it anyway)", .path.display())]
    SystemCall { path: PathBuf, line: usize, reason: String },
    /// `path` reads `target`, which is being read already: gmsh would recurse without end.
    #[error("refusing to open {}: line {line} reads \"{target}\", which is already being read (Include recursion)", .path.display())]
    Recursion { path: PathBuf, line: usize, target: String },
    /// A file opened as a mesh does not start like a gmsh `.msh` file.
    #[error("cannot open {}: not a gmsh .msh file (it does not start with $MeshFormat)", .path.display())]
    NotMsh { path: PathBuf },
    /// gmsh reported an error while reading the file, e.g. a `.geo` syntax error with its line.
    #[error("cannot open {}: {message}", .path.display())]
    Open { path: PathBuf, message: String },
    /// gmsh reported an error while meshing the model read from `path`.
    #[error("cannot mesh {}: {message}", .path.display())]
    Meshing { path: PathBuf, message: String },
    /// gmsh reported an error while writing the mesh.
    #[error("cannot write {}: {message}", .path.display())]
    Write { path: PathBuf, message: String },
    /// The mesh has no 3-node or 6-node triangle.
    #[error("the mesh of {} has no triangles (does it define a surface?)", .path.display())]
    NoTriangles { path: PathBuf },
    /// The mesh of a model with volumes has no 4-node or 10-node tetrahedron.
    #[error("the mesh of {} has no tetrahedra (do its volumes have a mesh?)", .path.display())]
    NoTetrahedra { path: PathBuf },
    /// A tetrahedron has zero volume.
    #[error("the mesh of {} has a flat tetrahedron at ({}, {}, {}); are some mesh sizes too small?", .path.display(), .x[0], .x[1], .x[2])]
    FlatTetrahedron { path: PathBuf, x: Point3 },
    /// The mesh mixes elements of order 1 and 2.
    #[error("the mesh of {} mixes first- and second-order elements", .path.display())]
    MixedOrder { path: PathBuf },
    /// The mesh has elements other than triangles and segments of order 1 or 2 (e.g. quadrangles).
    #[error("the mesh of {} has {element} elements, but only simplices (tetrahedra, triangles, segments) of order 1 or 2 are supported", .path.display())]
    Unsupported { path: PathBuf, element: String },
    /// A triangle has zero area (gmsh can produce them when sizes approach its tolerance).
    #[error("the mesh of {} has a degenerate triangle at ({x}, {y}); are some mesh sizes too small?", .path.display())]
    Degenerate { path: PathBuf, x: f64, y: f64 },
    /// Triangles overlap: two lie on the same side of their common edge, or an edge belongs to
    /// more than two.
    #[error("the mesh of {} is folded: triangles overlap at the edge from ({}, {}) to ({}, {})", .path.display(), .edge[0][0], .edge[0][1], .edge[1][0], .edge[1][1])]
    Folded { path: PathBuf, edge: [Point; 2] },
    /// gmsh skipped nodes or elements whose tag was already used.
    #[error("cannot open {}: {message}; every node and element needs its own tag", .path.display())]
    DuplicateTag { path: PathBuf, message: String },
    /// The `$PhysicalNames` of a `.msh` file give one physical group two names.
    #[error("cannot open {}: physical tag {tag} of dimension {dim} has two names, \"{first}\" and \"{second}\", of which gmsh would keep one; give each physical group one name", .path.display())]
    TwoNames { path: PathBuf, dim: i32, tag: i32, first: String, second: String },
    /// A physical curve (surface in 3D) has nodes that no cell uses.
    #[error("physical {what} \"{group}\" of {} does not lie on the cells of the mesh", .path.display())]
    DetachedCurve { path: PathBuf, group: String, what: &'static str },
    /// A [`MeshOptions`](super::MeshOptions) field is out of range.
    #[error("invalid mesh option {name} = {value}: expected {expected}")]
    BadOption { name: &'static str, value: String, expected: &'static str },
    /// A [`SizeField`](super::SizeField) or the cell sizes it is built from is invalid, e.g.
    /// "cell 12 has size NaN, expected a positive finite number".
    #[error("invalid mesh size field: {reason}")]
    BadSizeField { reason: String },
    /// A gmsh C API call failed; `message` is gmsh's last error.
    #[error("gmsh call {call} failed: {message}")]
    Call { call: &'static str, message: String },
}
