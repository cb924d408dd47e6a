//! [`Session`]: exclusive access to gmsh's global state.

use super::{api, guard, limits, names, read, GmshError, MeshOptions, SizeField};
use crate::io::input::{check_regular, NotAFile};
use crate::mesh::Mesh;
use std::ffi::CString;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// Options a `.geo` file may set that change the mesh; every session starts from gmsh's defaults.
const RESET_OPTIONS: [&str; 12] = [
    "Mesh.Algorithm",
    "Mesh.ElementOrder",
    "Mesh.SecondOrderLinear",
    "Mesh.MeshSizeFactor",
    "Mesh.MeshSizeMin",
    "Mesh.MeshSizeMax",
    "Mesh.MeshSizeFromPoints",
    "Mesh.MeshSizeFromCurvature",
    "Mesh.MeshSizeExtendFromBoundary",
    "Mesh.RecombineAll",
    "Mesh.SubdivisionAlgorithm",
    "Mesh.SaveAll",
];

/// Why a command of plane sections refuses a model with volumes.
pub(super) const SOLID_REFUSED: &str =
    "it is 3-D (it has volumes): this command works on plane sections so far; `damfem mesh`, `check` and `solve` \
     take 3-D models (without contact)";

/// gmsh 2D meshing algorithms (`Mesh.Algorithm`).
const ALGORITHMS: [i32; 9] = [1, 2, 3, 5, 6, 7, 8, 9, 11];

/// gmsh's values of [`RESET_OPTIONS`], read once after `gmshInitialize`.
static GMSH: Mutex<Option<Vec<f64>>> = Mutex::new(None);

/// Exclusive use of gmsh, which keeps one global model. Other threads wait in [`Session::new`]
/// until this session is dropped; a second session on the same thread would deadlock.
pub struct Session {
    _lock: MutexGuard<'static, Option<Vec<f64>>>,
    /// The file last opened, named in error messages.
    source: PathBuf,
    /// Number of logger messages already examined.
    log_seen: usize,
    /// With a size field setting the mesh sizes: its estimated number of triangles.
    field_cells: Option<f64>,
    /// Whether gmsh meshed the model in this session (rather than reading a mesh file).
    meshed: bool,
    /// The dimension of the opened model: 3 if it has volumes, else 2.
    dimension: usize,
    /// Whether gmsh's messages are copied to stderr.
    verbose: bool,
}

impl Session {
    /// Waits for gmsh, initialising it on first use, and starts from an empty model.
    /// With `verbose`, gmsh's messages are copied to stderr after each long operation (gmsh's
    /// own terminal output would go to stdout, which holds the results).
    pub fn new(verbose: bool) -> Result<Session, GmshError> {
        let mut lock = GMSH.lock().unwrap_or_else(PoisonError::into_inner);
        if lock.is_none() {
            api::initialize()?;
            let defaults = RESET_OPTIONS.iter().map(|name| api::get_number(name));
            *lock = Some(defaults.collect::<Result<_, _>>()?);
        }
        for (name, &value) in RESET_OPTIONS.iter().zip(lock.iter().flatten()) {
            api::set_number(name, value)?;
        }
        api::set_number("General.Terminal", 0.0)?;
        // errors must stay logged (verbosity ≥ 1) for the session to report them
        api::set_number("General.Verbosity", if verbose { 5.0 } else { 1.0 })?;
        api::set_number("General.AbortOnError", 2.0)?;
        // gmsh passes this to omp_set_num_threads, which acts on the calling thread only: a
        // thread other than the first would mesh with OpenMP's default team, non-reproducibly
        api::set_number("General.NumThreads", 1.0)?;
        api::clear()?;
        api::restart_logger()?;
        let source = PathBuf::from("the empty model");
        Ok(Session { _lock: lock, source, log_seen: 0, field_cells: None, meshed: false, dimension: 2, verbose })
    }

    /// Opens a `.geo` file. Unless `allow_system_calls`, first refuses it if it, or a file it
    /// includes, could run a shell command (see the `guard` module).
    pub fn open_geo(&mut self, path: &Path, allow_system_calls: bool) -> Result<(), GmshError> {
        exists(path)?;
        if !allow_system_calls {
            guard::check(path)?;
        }
        self.open(path)?;
        self.dimension = limits::check_model(path)?;
        Ok(())
    }

    /// Opens a gmsh `.msh` file (refusing anything else: gmsh would parse it as a `.geo`).
    pub fn open_msh(&mut self, path: &Path) -> Result<(), GmshError> {
        exists(path)?;
        let mut header = [0; 11];
        let read = std::fs::File::open(path).and_then(|mut f| f.read_exact(&mut header));
        if read.is_err() || &header != b"$MeshFormat" {
            return Err(GmshError::NotMsh { path: path.into() });
        }
        guard::check_options(path)?;
        names::check_physical_names(path)?;
        let logged = self.log_seen;
        // gmsh reports skipped duplicate tags as warnings, logged from verbosity 2
        let verbosity = api::get_number("General.Verbosity")?;
        api::set_number("General.Verbosity", verbosity.max(2.0))?;
        let opened = self.open(path);
        api::set_number("General.Verbosity", verbosity)?;
        opened?;
        let log = api::logged()?;
        if let Some(line) = log.get(logged..).unwrap_or_default().iter().find(|l| l.contains("uplicate")) {
            let message = line.strip_prefix("Warning: ").unwrap_or(line);
            return Err(GmshError::DuplicateTag { path: path.into(), message: format!("gmsh: {message}") });
        }
        self.dimension = limits::check_model(path)?;
        Ok(())
    }

    /// The dimension of the opened model: 3 if it has volumes, else 2.
    pub fn dimension(&self) -> usize {
        self.dimension
    }

    fn open(&mut self, path: &Path) -> Result<(), GmshError> {
        self.source = path.into();
        let c_path = c_path(path).ok_or_else(|| GmshError::NotFound { path: path.into() })?;
        // gmsh names the top file in its messages: "'dam.geo', line 3: syntax error (;)"
        let prefix = format!("'{}', ", path.display());
        self.step(
            || api::open(&c_path),
            |message| GmshError::Open {
                path: path.into(),
                message: message.strip_prefix(&prefix).unwrap_or(&message).into(),
            },
        )
    }

    /// Sets the meshing options (overriding those of the opened file).
    pub fn set_options(&mut self, options: &MeshOptions) -> Result<(), GmshError> {
        validate(options)?;
        api::set_number("Mesh.ElementOrder", options.order as f64)?;
        api::set_number("Mesh.SecondOrderLinear", 1.0)?;
        api::set_number("Mesh.MeshSizeFactor", options.size_factor)?;
        if let Some(size) = options.size_min {
            api::set_number("Mesh.MeshSizeMin", size)?;
        }
        if let Some(size) = options.size_max {
            api::set_number("Mesh.MeshSizeMax", size)?;
        }
        api::set_number("Mesh.Algorithm", f64::from(options.algorithm))
    }

    /// Makes `field` the only source of mesh sizes, replacing any background field of the opened
    /// file: a "PostView" field on a list-based view of its triangles, with no sizes from points,
    /// curvature or the boundary. gmsh 4.8 gives points outside the view's triangles (on curved
    /// boundaries, where the old mesh is coarse) its maximum size, so `Mesh.MeshSizeMax` is
    /// lowered to max(maxᵢ h(xᵢ), `Mesh.MeshSizeMin`). Call it after opening the file, to which
    /// the field belongs; the view lives until the next session clears the model.
    pub fn set_size_field(&mut self, field: &SizeField) -> Result<(), GmshError> {
        let tag = post_view(field)?;
        self.set_background(tag, field.max_size(), field)
    }

    /// Like [`Session::set_size_field`], except on the curves of the physical curve groups
    /// `joints` that bound a surface of the physical group `side`: these are meshed with the
    /// sizes of `own` instead (docs/method.md §5.4, two bodies). The background field is
    /// Min(Restrict(`field`; every point, surface and other curve), Restrict(`own`; those
    /// curves)), gmsh's Restrict giving its largest size off its entities.
    pub fn set_side_size_field(
        &mut self,
        field: &SizeField,
        joints: &[String],
        side: i32,
        own: &SizeField,
    ) -> Result<(), GmshError> {
        let mut curves = Vec::new();
        for (_, group) in api::physical_groups(1)? {
            if joints.contains(&api::physical_name(1, group)?) {
                for &curve in api::group_entities(1, group)?.as_slice() {
                    let bounds_side = api::upward(1, curve)?
                        .into_iter()
                        .map(|surface| api::entity_groups(2, surface).map(|g| g.as_slice().first() == Some(&side)))
                        .collect::<Result<Vec<bool>, _>>()?;
                    if bounds_side.contains(&true) {
                        curves.push(curve);
                    }
                }
            }
        }
        let tags = |dim| -> Result<Vec<f64>, GmshError> {
            Ok(api::entities(dim)?
                .into_iter()
                .filter(|&(_, t)| dim != 1 || !curves.contains(&t))
                .map(|(_, t)| f64::from(t))
                .collect())
        };
        let rest = restrict(
            post_view(field)?,
            &[("PointsList", tags(0)?), ("CurvesList", tags(1)?), ("SurfacesList", tags(2)?)],
        )?;
        let joint = restrict(post_view(own)?, &[("CurvesList", curves.iter().map(|&c| f64::from(c)).collect())])?;
        let min = api::field_add("Min")?;
        api::field_set_numbers(min, "FieldsList", &[f64::from(rest), f64::from(joint)])?;
        self.set_background(min, field.max_size().max(own.max_size()), field)
    }

    /// Makes the field `tag` the background field and the only source of mesh sizes, the
    /// largest at most max(`max_size`, `Mesh.MeshSizeMin`); the cell count is estimated from
    /// `field`, which covers the model.
    fn set_background(&mut self, tag: i32, max_size: f64, field: &SizeField) -> Result<(), GmshError> {
        api::field_set_background(tag)?;
        for name in ["Mesh.MeshSizeFromPoints", "Mesh.MeshSizeFromCurvature", "Mesh.MeshSizeExtendFromBoundary"] {
            api::set_number(name, 0.0)?;
        }
        let size_min = api::get_number("Mesh.MeshSizeMin")?;
        let size_max = api::get_number("Mesh.MeshSizeMax")?.min(max_size.max(size_min));
        let factor = api::get_number("Mesh.MeshSizeFactor")?;
        self.field_cells = Some(field.cells_within(size_min, size_max, factor));
        api::set_number("Mesh.MeshSizeMax", size_max)
    }

    /// Meshes the model in its dimension; with `Mesh.ElementOrder` 2, gmsh then raises the
    /// mesh to order 2.
    /// The cell count is first estimated, from the curves or from the size field, and refused
    /// above the limit (see the `limits` module).
    pub fn generate(&mut self) -> Result<(), GmshError> {
        let path = self.source.clone();
        let (field_cells, dimension) = (self.field_cells, self.dimension);
        self.meshed = true;
        self.step(
            || {
                match field_cells {
                    None => limits::check_cell_count(&path, dimension)?,
                    Some(cells) => {
                        limits::check_estimate(&path, cells, "triangles", "from the target sizes of the previous mesh")?
                    }
                }
                api::generate(dimension as i32)
            },
            |message| GmshError::Meshing { path: path.clone(), message },
        )
    }

    /// Reads the current mesh. Cells are the 3-node or 6-node triangles of every surface,
    /// tagged with the surface's first physical group (0 if none); facets are the 2-node or
    /// 3-node segments of the curves of each physical curve group (a segment in two groups
    /// appears twice). Node order is gmsh's, which is the [`Mesh`] convention; nodes are
    /// numbered from 0 in order of first use by a cell, and cells are counter-clockwise.
    pub fn mesh(&self) -> Result<Mesh, GmshError> {
        if self.dimension == 3 {
            return Err(GmshError::Limit { path: self.source.clone(), reason: SOLID_REFUSED.into() });
        }
        read::mesh(&self.source, self.meshed)
    }

    /// Reads the current mesh in the model's dimension.
    pub fn any_mesh(&self) -> Result<super::AnyMesh, GmshError> {
        Ok(match self.dimension {
            3 => super::AnyMesh::Solid(self.solid_mesh()?),
            _ => super::AnyMesh::Plane(self.mesh()?),
        })
    }

    /// Reads the current mesh of a model with volumes: 4-node or 10-node tetrahedra of every
    /// volume, tagged with its first physical group, and the 3-node or 6-node triangles of the
    /// surfaces of each physical surface group; cells positively oriented.
    pub fn solid_mesh(&self) -> Result<Mesh<3>, GmshError> {
        read::solid(&self.source)
    }

    /// Writes the mesh in the format of the extension. Only elements of physical groups are
    /// saved (all of them when the model has no physical group), as gmsh does by default;
    /// saving the untagged point entities too would make the file unreadable for meshio.
    pub fn write(&mut self, path: &Path) -> Result<(), GmshError> {
        api::set_number("Mesh.SaveAll", 0.0)?;
        let fail = |message| GmshError::Write { path: path.into(), message };
        let c_path = c_path(path).ok_or_else(|| fail("invalid file name".into()))?;
        self.step(|| api::write(&c_path), fail)
    }

    /// Runs a long gmsh operation with `General.AbortOnError` = 0 and reports the first error
    /// it logged through `fail`. With gmsh's API default (2), an error thrown while parsing
    /// leaves gmsh busy (later opens silently do nothing) and one thrown by the mesher
    /// aborts the process.
    fn step(
        &mut self,
        operation: impl FnOnce() -> Result<(), GmshError>,
        fail: impl FnOnce(String) -> GmshError,
    ) -> Result<(), GmshError> {
        api::set_number("General.AbortOnError", 0.0)?;
        let result = operation();
        api::set_number("General.AbortOnError", 2.0)?;
        if let Some(message) = self.first_new_error()? {
            return Err(fail(message));
        }
        result.map_err(|e| match e {
            GmshError::Call { message, .. } => fail(message),
            e => e,
        })
    }

    /// The first error gmsh logged since the last look; with `verbose`, every message logged
    /// since then goes to stderr.
    fn first_new_error(&mut self) -> Result<Option<String>, GmshError> {
        let log = api::logged()?;
        let new = log.get(self.log_seen..).unwrap_or_default();
        self.log_seen = log.len();
        if self.verbose {
            new.iter().for_each(|line| eprintln!("gmsh: {line}"));
        }
        Ok(new.iter().find_map(|line| line.strip_prefix("Error: ")).map(str::to_owned))
    }
}

/// A "PostView" field on a list-based view of the triangles of `field`; its tag.
fn post_view(field: &SizeField) -> Result<i32, GmshError> {
    field.validate()?;
    let view = api::view_add("target mesh sizes")?;
    api::view_add_list_data(view, "ST", field.triangles.len(), &field.list_data())?;
    let tag = api::field_add("PostView")?;
    api::field_set_number(tag, "ViewTag", f64::from(view))?;
    Ok(tag)
}

/// A "Restrict" field of the field `inner` to the entity lists `lists` (option, tags); its tag.
fn restrict(inner: i32, lists: &[(&str, Vec<f64>)]) -> Result<i32, GmshError> {
    let tag = api::field_add("Restrict")?;
    api::field_set_number(tag, "InField", f64::from(inner))?;
    for (option, tags) in lists {
        api::field_set_numbers(tag, option, tags)?;
    }
    Ok(tag)
}

/// Checks that `path` is a regular file, without opening it.
fn exists(path: &Path) -> Result<(), GmshError> {
    let path = path.to_path_buf();
    check_regular(&path).map_err(|e| match e {
        NotAFile::Missing => GmshError::NotFound { path },
        NotAFile::Directory => GmshError::Directory { path },
        NotAFile::Other(reason) => GmshError::NotAFile { path, reason },
    })
}

/// `path` for gmsh, `None` if it holds a NUL byte.
fn c_path(path: &Path) -> Option<CString> {
    CString::new(path.as_os_str().as_encoded_bytes()).ok()
}

fn validate(options: &MeshOptions) -> Result<(), GmshError> {
    let bad = |name, value: String, expected| Err(GmshError::BadOption { name, value, expected });
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !matches!(options.order, 1 | 2) {
        return bad("order", options.order.to_string(), "1 or 2");
    }
    if !positive(options.size_factor) {
        return bad("size_factor", options.size_factor.to_string(), "a positive number");
    }
    for (name, size) in [("size_min", options.size_min), ("size_max", options.size_max)] {
        if let Some(size) = size.filter(|&s| !positive(s)) {
            return bad(name, size.to_string(), "a positive number");
        }
    }
    if !ALGORITHMS.contains(&options.algorithm) {
        let expected = "a gmsh 2D algorithm (1, 2, 3, 5, 6, 7, 8, 9 or 11)";
        return bad("algorithm", options.algorithm.to_string(), expected);
    }
    Ok(())
}
