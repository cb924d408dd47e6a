//! Limits checked before gmsh meshes a surface, so that absurd sizes or coordinates give an
//! error instead of a run that ends on gmsh's `bad_alloc` or never ends.
//!
//! - Coordinates: the model's bounding box must be finite and within ±[`MAX_COORDINATE`] m;
//!   a model without volumes must be flat (z = 0: a plane-strain section).
//! - Sizes: `Mesh.MeshSizeMax` must be at least [`SIZE_FLOOR`] × the bounding box diagonal d.
//! - Cell count: the curves are meshed first, with every size raised to [`SIZE_FLOOR`] d (so
//!   that this pass has at most a few 10⁵ segments per curve); with h̄ the mean segment length
//!   times the size factor, the surface mesh is estimated at N ≈ |box| / (√3/4 h̄²) triangles
//!   and refused when N exceeds the cell limit ([`set_cell_limit`], default
//!   [`DEFAULT_CELL_LIMIT`]). The curve mesh is then cleared and the model meshed as asked.
//!   With a size field h (a remesh), N ≈ ∫ 1/(√3/4 h²) over the field's triangles instead
//!   ([`super::SizeField::cells`]). A model with volumes is estimated at
//!   N ≈ |box| / (h̄³ / (6√2)) tetrahedra, the volume of the regular one of side h̄.
//! - Time: reading and meshing one file may take [`set_time_limit`] seconds (none by
//!   default). gmsh cannot be stopped from outside its loops, so the limit is an `alarm`:
//!   SIGALRM reaches the process when the time is up, and the caller's handler reports
//!   [`time_limit_exceeded`] and ends the process (the command line's does). Past
//!   [`NOTICE_AFTER`] seconds the limit is stated once on stderr.

use super::{api, GmshError};
use crate::geometry::tetrahedron::{distance3, Point3};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

/// Largest coordinate accepted [m].
pub const MAX_COORDINATE: f64 = 1e9;
/// Smallest mesh size accepted, relative to the diagonal of the model's bounding box.
pub const SIZE_FLOOR: f64 = 1e-5;
/// Estimated cell count above which meshing is refused unless the limit is raised.
pub const DEFAULT_CELL_LIMIT: usize = 2_000_000;
/// Area of the equilateral triangle of unit side, √3/4: a mesh of size h has about
/// |Ω| / (√3/4 h²) triangles.
pub(super) const TRIANGLE_AREA: f64 = 0.4330127018922193;
/// Volume of the regular tetrahedron of unit side, 1/(6√2).
const TETRAHEDRON_VOLUME: f64 = 0.11785113019775792;

static CELL_LIMIT: AtomicUsize = AtomicUsize::new(DEFAULT_CELL_LIMIT);

/// Sets the estimated cell count above which [`super::Session::generate`] refuses to mesh.
pub fn set_cell_limit(cells: usize) {
    CELL_LIMIT.store(cells, Ordering::Relaxed);
}

/// The estimated cell count above which [`super::Session::generate`] refuses to mesh.
pub fn cell_limit() -> usize {
    CELL_LIMIT.load(Ordering::Relaxed)
}

/// Seconds gmsh may take to read and mesh one file; 0: no limit.
static TIME_LIMIT: AtomicU32 = AtomicU32::new(0);
/// The file gmsh reads or meshes under the time limit.
static TIMED_FILE: Mutex<Option<PathBuf>> = Mutex::new(None);

/// Sets how many seconds gmsh may take to read and mesh one file (`None`: no limit). When
/// they are up, the process receives SIGALRM, which the caller must handle.
pub fn set_time_limit(seconds: Option<u32>) {
    TIME_LIMIT.store(seconds.unwrap_or(0), Ordering::Relaxed);
}

/// The error to report when SIGALRM came from the time limit: the file and the limit.
pub fn time_limit_exceeded() -> Option<String> {
    let file = TIMED_FILE.lock().unwrap_or_else(PoisonError::into_inner).clone()?;
    Some(format!(
        "cannot use {}: gmsh did not finish reading and meshing it within the time limit of {} s; simplify the \
         geometry or coarsen its sizes, or raise the limit with --mesh-time-limit",
        file.display(),
        TIME_LIMIT.load(Ordering::Relaxed)
    ))
}

/// How long gmsh works on one file before the time limit is stated, in seconds.
pub const NOTICE_AFTER: u32 = 5;

/// The time limit running for one file, from [`Deadline::start`] until dropped; while it runs
/// longer than [`NOTICE_AFTER`], a thread states the limit once (a `.geo` may loop for long).
pub(super) struct Deadline {
    /// Dropped with the deadline, which ends the notice's thread.
    _running: Option<std::sync::mpsc::Sender<()>>,
}

impl Deadline {
    /// Starts the clock for gmsh's work on `path`, if a time limit is set.
    pub(super) fn start(path: &Path) -> Deadline {
        let seconds = TIME_LIMIT.load(Ordering::Relaxed);
        if seconds == 0 {
            return Deadline { _running: None };
        }
        *TIMED_FILE.lock().unwrap_or_else(PoisonError::into_inner) = Some(path.to_path_buf());
        api::alarm(seconds);
        if seconds <= NOTICE_AFTER {
            return Deadline { _running: None };
        }
        let (running, done) = std::sync::mpsc::channel::<()>();
        let file = path.display().to_string();
        std::thread::spawn(move || {
            let wait = std::time::Duration::from_secs(NOTICE_AFTER.into());
            if let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = done.recv_timeout(wait) {
                eprintln!(
                    "note: gmsh is still reading and meshing {file} after {NOTICE_AFTER} s; it is stopped at {seconds} s \
                     (--mesh-time-limit)"
                );
            }
        });
        Deadline { _running: Some(running) }
    }
}

impl Drop for Deadline {
    fn drop(&mut self) {
        if TIME_LIMIT.load(Ordering::Relaxed) > 0 {
            api::alarm(0);
            *TIMED_FILE.lock().unwrap_or_else(PoisonError::into_inner) = None;
        }
    }
}

/// Checks the opened model and gives its dimension: 3 with volumes, else 2. It must not be
/// empty, its coordinates must be finite and within ±[`MAX_COORDINATE`], and a plane model
/// must have z = 0 everywhere (no tilted plane).
pub(super) fn check_model(path: &Path) -> Result<usize, GmshError> {
    let fail = |reason: String| Err(GmshError::Limit { path: path.into(), reason });
    if (0..=3).map(api::entities).collect::<Result<Vec<_>, _>>()?.iter().all(Vec::is_empty) {
        return fail("it is empty: it defines no point, curve or surface".into());
    }
    let b = api::bounding_box()?;
    if let Some(x) = b.iter().find(|x| x.is_nan() || x.abs() > MAX_COORDINATE) {
        return fail(format!("coordinate {x:e} is beyond the limit of ±{MAX_COORDINATE:e} m"));
    }
    if !api::entities(3)?.is_empty() {
        return Ok(3);
    }
    if b[2] != 0.0 || b[5] != 0.0 {
        return fail(format!(
            "it is not plane: z ranges over [{}, {}], but a section needs z = 0 (a solid needs volumes)",
            b[2], b[5]
        ));
    }
    Ok(2)
}

/// Meshes the curves with sizes of at least [`SIZE_FLOOR`] d, estimates the number of
/// cells of the model of dimension `dimension` and refuses it above the cell limit; clears
/// the curve mesh.
pub(super) fn check_cell_count(path: &Path, dimension: usize) -> Result<(), GmshError> {
    let [x0, y0, z0, x1, y1, z1] = api::bounding_box()?;
    let (width, height, depth) = (x1 - x0, y1 - y0, z1 - z0);
    let floor = SIZE_FLOOR * width.hypot(height).hypot(depth);
    let fail = |reason: String| Err(GmshError::Limit { path: path.into(), reason });
    let (size_min, size_max, factor) = (
        api::get_number("Mesh.MeshSizeMin")?,
        api::get_number("Mesh.MeshSizeMax")?,
        api::get_number("Mesh.MeshSizeFactor")?,
    );
    if size_max < floor {
        return fail(format!(
            "mesh size_max = {size_max:e} m is below {SIZE_FLOOR:e} of the model's extent ({floor:e} m)"
        ));
    }
    api::set_number("Mesh.MeshSizeFactor", 1.0)?;
    api::set_number("Mesh.MeshSizeMin", size_min.max(floor / factor))?;
    let mean = api::generate(1).and_then(|()| mean_segment_length());
    api::set_number("Mesh.MeshSizeFactor", factor)?;
    api::set_number("Mesh.MeshSizeMin", size_min)?;
    api::clear_mesh()?;
    let Some(mean) = mean? else { return Ok(()) };
    let h = factor * mean;
    let estimate = match dimension {
        3 => width * height * depth / (TETRAHEDRON_VOLUME * h * h * h),
        _ => width * height / (TRIANGLE_AREA * h * h),
    };
    let cells = if dimension == 3 { "tetrahedra" } else { "triangles" };
    check_estimate(path, estimate, cells, &format!("mean size {h:.3e} m on the curves"))
}

/// Refuses `estimate` cells (`cells` names them), estimated from `sizes` (what they were),
/// above the cell limit.
pub(super) fn check_estimate(path: &Path, estimate: f64, cells: &str, sizes: &str) -> Result<(), GmshError> {
    let limit = cell_limit();
    if estimate.is_nan() || estimate > limit as f64 {
        return Err(GmshError::Limit {
            path: path.into(),
            reason: format!(
                "its mesh would have about {estimate:.1e} {cells} ({sizes}), above the limit of {limit}; \
                 coarsen the sizes or raise the limit with --max-cells"
            ),
        });
    }
    Ok(())
}

/// Mean length of the curve segments of the current mesh, `None` if there is none.
fn mean_segment_length() -> Result<Option<f64>, GmshError> {
    let (tags, coords) = api::nodes()?;
    let xyz: std::collections::HashMap<usize, Point3> =
        tags.as_slice().iter().zip(coords.as_slice().chunks_exact(3)).map(|(&t, c)| (t, [c[0], c[1], c[2]])).collect();
    let (mut total, mut count) = (0.0, 0usize);
    for (_, curve) in api::entities(1)? {
        for &element_type in api::element_types(1, curve)?.as_slice() {
            let stride = if element_type == 8 { 3 } else { 2 };
            for segment in api::element_nodes(element_type, curve)?.as_slice().chunks_exact(stride) {
                let (Some(a), Some(b)) = (xyz.get(&segment[0]), xyz.get(&segment[1])) else { continue };
                total += distance3(*a, *b);
                count += 1;
            }
        }
    }
    Ok((count > 0).then(|| total / count as f64))
}
