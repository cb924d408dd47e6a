//! One command at a time in an output directory: a command that writes takes an exclusive
//! lock (`flock`) on `<dir>/.damfem.lock`, created if missing, and removes the file when it
//! ends ([`release`]; on an interrupt too). A second command on the directory is refused
//! while the first holds the lock.

use anyhow::{Context, Result};
use std::fs::{File, OpenOptions, TryLockError};
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

/// The lock file's name in an output directory.
pub const LOCK_FILE: &str = ".damfem.lock";

/// The lock file held by this process and its open file, which holds the lock.
static HELD: Mutex<Option<(PathBuf, File)>> = Mutex::new(None);

/// Locks `dir` for this process (once: a second call on the same directory does nothing), or
/// refuses it, naming it, while another command holds it.
pub fn lock(dir: &Path) -> Result<()> {
    let path = dir.join(LOCK_FILE);
    let mut held = HELD.lock().unwrap_or_else(PoisonError::into_inner);
    if held.as_ref().is_some_and(|(p, _)| *p == path) {
        return Ok(());
    }
    // a lock file that its holder removed after this process opened it locks nothing: again
    for _ in 0..10 {
        let file = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .with_context(|| format!("cannot create the lock file {}", path.display()))?;
        match file.try_lock() {
            Ok(()) if same_file(&path, &file) => {
                *held = Some((path, file));
                return Ok(());
            }
            Ok(()) => continue,
            Err(TryLockError::WouldBlock) => anyhow::bail!(
                "output directory {} is in use by another damfem command (it holds {LOCK_FILE}); wait for it to end \
                 or choose another directory with -o",
                dir.display()
            ),
            Err(TryLockError::Error(e)) => return Err(e).with_context(|| format!("cannot lock {}", path.display())),
        }
    }
    anyhow::bail!("cannot lock output directory {}: its lock file keeps being removed", dir.display())
}

/// Whether `path` is still the file `file` has open.
fn same_file(path: &Path, file: &File) -> bool {
    match (std::fs::metadata(path), file.metadata()) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Removes the lock file of this process, then releases the lock.
pub fn release() {
    if let Some((path, file)) = HELD.lock().unwrap_or_else(PoisonError::into_inner).take() {
        // the process is ending; a lock file that cannot be removed is left, unlocked
        let _ = std::fs::remove_file(path);
        drop(file);
    }
}
