//! Atomic output files and the error type shared by the output writers.
//!
//! A file is first written to a hidden temporary file next to its target
//! (`.<file>.<pid>.<n>.tmp`), flushed and synced, then renamed over the target. A reader such as
//! ParaView therefore sees either the previous file or the complete new one, never a half-written
//! file, and a failed write leaves nothing behind. The files of one result are [`Provisional`]
//! until all of them are written: a failure or an interrupt before removes those written.

use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// Failure to write an output file; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The operating system refused to create, write or rename the file.
    #[error("cannot write {}: {error}", path.display())]
    Io { path: PathBuf, error: io::Error },
    /// A NaN or infinite value was about to be written.
    #[error("cannot write {}: non-finite value {value} in {location}", path.display())]
    NonFinite { path: PathBuf, location: String, value: f64 },
    /// The data do not fit the file (wrong field length, duplicate name, unusable path…).
    #[error("cannot write {}: {reason}", path.display())]
    Invalid { path: PathBuf, reason: String },
    /// The VTK library failed to encode the data set.
    #[error("cannot write {}: VTK encoding failed: {message}", path.display())]
    Encode { path: PathBuf, message: String },
    /// The font needed to lay out text is missing or unreadable.
    #[error("cannot write {}: cannot use font file {}: {reason}", path.display(), font.display())]
    Font { path: PathBuf, font: PathBuf, reason: String },
    /// Drawing or image encoding failed.
    #[error("cannot write {}: rendering failed: {message}", path.display())]
    Render { path: PathBuf, message: String },
}

/// Writes `bytes` to `path` atomically.
pub fn write_output(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    write_atomic(path, |w| w.write_all(bytes)).map_err(|error| OutputError::Io { path: path.to_path_buf(), error })
}

/// Writes `path` through `write` into a temporary file, then renames it over `path`.
///
/// On any error the temporary file is removed and `path` is left untouched.
pub fn write_atomic(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    let tmp = temp_path(path)?;
    let file = {
        let mut in_flight = in_flight();
        let file = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        in_flight.push(tmp.clone());
        file
    };
    let result = fill(file, write).and_then(|()| fs::rename(&tmp, path));
    if result.is_err() {
        // The write already failed; a failure to clean up adds nothing useful to report.
        let _ = fs::remove_file(&tmp);
    }
    in_flight().retain(|p| *p != tmp);
    result
}

/// Files written that are removed unless [`Provisional::keep`] is called: when dropped, or by
/// [`stop_writing`] on an interrupt.
#[derive(Debug, Default)]
pub struct Provisional(Vec<PathBuf>);

impl Provisional {
    /// Adds `path`, just written.
    pub fn add(&mut self, path: &Path) {
        in_flight().push(path.to_path_buf());
        self.0.push(path.to_path_buf());
    }

    /// Keeps the files.
    pub fn keep(mut self) {
        let kept = std::mem::take(&mut self.0);
        in_flight().retain(|p| !kept.contains(p));
    }
}

impl Drop for Provisional {
    fn drop(&mut self) {
        let mut in_flight = in_flight();
        for path in &self.0 {
            // the command fails already; a file that cannot be removed is left as it is
            let _ = fs::remove_file(path);
        }
        in_flight.retain(|p| !self.0.contains(p));
    }
}

/// Temporary files being written, and [`Provisional`] files.
static IN_FLIGHT: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn in_flight() -> MutexGuard<'static, Vec<PathBuf>> {
    IN_FLIGHT.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Removes the temporary files being written and the [`Provisional`] files (on an interrupt);
/// no other write can start or finish while the returned guard lives.
pub fn stop_writing() -> MutexGuard<'static, Vec<PathBuf>> {
    let mut in_flight = in_flight();
    for tmp in in_flight.drain(..) {
        // the process is ending; a file that cannot be removed is left as it is
        let _ = fs::remove_file(tmp);
    }
    in_flight
}

/// Writes, flushes and syncs `file`.
fn fill(file: File, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    let mut buffered = BufWriter::new(file);
    write(&mut buffered)?;
    let file = buffered.into_inner().map_err(|e| e.into_error())?;
    file.sync_all()
}

/// `.<file>.<pid>.<n>.tmp` next to `path`, unique within this process.
fn temp_path(path: &Path) -> io::Result<PathBuf> {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let name =
        path.file_name().ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path has no file name"))?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let mut tmp = OsString::from(".");
    tmp.push(name);
    tmp.push(format!(".{}.{n}.tmp", std::process::id()));
    Ok(path.with_file_name(tmp))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh empty directory under the system temporary directory.
    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("damfem-atomic-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn entries(dir: &Path) -> Vec<OsString> {
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name()).collect()
    }

    #[test]
    fn success_writes_the_target_only() {
        let dir = scratch("success");
        let target = dir.join("out.txt");
        write_atomic(&target, |w| w.write_all(b"first")).unwrap();
        write_atomic(&target, |w| w.write_all(b"second")).unwrap();
        assert_eq!(fs::read(&target).unwrap(), b"second");
        assert_eq!(entries(&dir), [OsString::from("out.txt")]);
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn failing_closure_leaves_no_file() {
        let dir = scratch("failure");
        let target = dir.join("out.txt");
        let result = write_atomic(&target, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("boom"))
        });
        assert_eq!(result.unwrap_err().to_string(), "boom");
        assert!(entries(&dir).is_empty());
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn failing_closure_keeps_the_previous_file() {
        let dir = scratch("keep");
        let target = dir.join("out.txt");
        write_atomic(&target, |w| w.write_all(b"old")).unwrap();
        let result = write_atomic(&target, |_| Err(io::Error::other("boom")));
        assert!(result.is_err());
        assert_eq!(fs::read(&target).unwrap(), b"old");
        assert_eq!(entries(&dir), [OsString::from("out.txt")]);
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn provisional_files_stay_only_when_kept() {
        let dir = scratch("provisional");
        let (dropped, kept) = (dir.join("dropped.txt"), dir.join("kept.txt"));
        for (target, keep) in [(&dropped, false), (&kept, true)] {
            let mut files = Provisional::default();
            write_output(target, b"data").unwrap();
            files.add(target);
            if keep {
                files.keep();
            }
        }
        assert_eq!(entries(&dir), [OsString::from("kept.txt")]);
        assert!(!in_flight().iter().any(|p| p.starts_with(&dir)));
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn io_error_names_the_path() {
        let dir = scratch("error");
        let blocker = dir.join("file");
        fs::write(&blocker, b"").unwrap();
        let target = blocker.join("out.txt");
        let message = write_output(&target, b"data").unwrap_err().to_string();
        assert!(message.starts_with(&format!("cannot write {}: ", target.display())));
        assert_eq!(entries(&dir), [OsString::from("file")]);
        fs::remove_dir_all(dir).unwrap();
    }
}
