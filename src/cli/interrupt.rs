//! SIGINT and SIGTERM: the files being written are removed, the history of the run in
//! progress records "interrupted", the output directory's lock is released, the output
//! directories created for nothing are removed, and the process exits with 128 + the signal
//! number. SIGALRM, gmsh's time limit, is cleaned up
//! the same way, records the error instead, and exits with 1.

use super::common::remove_created_dirs;
use super::lock;
use crate::io::atomic::stop_writing;
use crate::io::gmsh;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

/// The `history.json` of the run in progress, if it has one.
static HISTORY: Mutex<Option<PathBuf>> = Mutex::new(None);

/// Makes `path` the history that an interrupt marks.
pub fn record_in(path: &Path) {
    *HISTORY.lock().unwrap_or_else(PoisonError::into_inner) = Some(path.to_path_buf());
}

/// Blocks SIGINT, SIGTERM and SIGALRM in this thread and every thread it starts later, and waits for
/// them on a thread of their own. Call it first in `main`.
pub fn install() {
    // SAFETY: the signal set is initialised by sigemptyset before use; the calls only change
    // this thread's signal mask.
    let set = unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        libc::sigaddset(&mut set, libc::SIGINT);
        libc::sigaddset(&mut set, libc::SIGTERM);
        libc::sigaddset(&mut set, libc::SIGALRM);
        libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut());
        set
    };
    std::thread::spawn(move || {
        let mut signal = 0;
        // SAFETY: `set` is an initialised signal set and `signal` a valid location.
        if unsafe { libc::sigwait(&set, &mut signal) } == 0 {
            interrupted(signal);
        }
    });
}

/// Cleans up after `signal` and ends the process.
fn interrupted(signal: i32) -> ! {
    let _writes = stop_writing();
    let (error, code) = match signal {
        libc::SIGALRM => {
            (gmsh::time_limit_exceeded().unwrap_or_else(|| "gmsh ran out of time (--mesh-time-limit)".into()), 1)
        }
        libc::SIGINT => ("interrupted by SIGINT".into(), 128 + signal),
        _ => ("interrupted by SIGTERM".into(), 128 + signal),
    };
    let history = HISTORY.lock().unwrap_or_else(PoisonError::into_inner).clone();
    let recorded = if signal == libc::SIGALRM { error.as_str() } else { "interrupted" };
    let marked = history.filter(|p| p.exists() && mark(p, recorded));
    lock::release();
    remove_created_dirs();
    match marked {
        Some(path) => eprintln!("error: {error}; the completed steps are in {}", path.display()),
        None => eprintln!("error: {error}"),
    }
    // _exit, not exit: the C++ destructors of gmsh must not run while another thread uses it
    // SAFETY: _exit ends the process at once; nothing after it runs.
    unsafe { libc::_exit(code) }
}

/// Sets `"error": error` in the history at `path` (written whole, then renamed); false if
/// the history could not be read or written.
fn mark(path: &Path, error: &str) -> bool {
    let Ok(Ok(mut history)) = std::fs::read(path).map(|b| serde_json::from_slice::<serde_json::Value>(&b)) else {
        return false;
    };
    let Some(fields) = history.as_object_mut() else { return false };
    fields.insert("error".into(), error.into());
    let tmp = path.with_extension("json.interrupted");
    let written = serde_json::to_vec_pretty(&history).map_err(std::io::Error::other);
    let written = written.and_then(|text| std::fs::write(&tmp, text)).and_then(|()| std::fs::rename(&tmp, path));
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written.is_ok()
}
