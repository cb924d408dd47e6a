//! The team of MPI processes that solves: this process, rank 0, and the workers it starts on
//! its first iterative solve (`MPI_Comm_spawn` of this program with [`WORKER_FLAG`]), merged
//! into one communicator that stays for the life of the process.
//!
//! Each solve, rank 0 broadcasts the [`Task`] and sends each worker its rows (CSR with global
//! columns, b, coordinates) as bytes; every process then builds its part of PETSc's parallel
//! matrix and vectors and solves; the workers send their rows of x back. A worker waits for the
//! next task until this process exits, which ends it. Without workers, or when they cannot be
//! started, or once a solve on the team has failed, the team is this process alone.

use super::{ffi, solve_part, Part, Petsc, SolveError, Task};
use std::ffi::{c_int, c_void, CString};
use std::path::PathBuf;
use std::sync::OnceLock;

/// The first argument that makes `damfem` a worker of a team ([`serve`]).
pub const WORKER_FLAG: &str = "--petsc-worker";

/// The program the workers run and how many there are.
static WORKERS: OnceLock<(PathBuf, usize)> = OnceLock::new();

/// Asks for `count` workers running `program` (this program), started on the first solve;
/// the first call counts.
pub fn set_workers(program: PathBuf, count: usize) {
    let _ = WORKERS.set((program, count));
}

/// A communicator and its number of processes.
#[derive(Debug, Clone, Copy)]
pub(super) struct Team {
    pub comm: ffi::MPI_Comm,
    pub size: usize,
}

/// The team of this process: the one it has, or the one of the workers asked for, started now.
pub(super) fn join(petsc: &mut Petsc) -> Team {
    if let Some(team) = petsc.team {
        return team;
    }
    let spawned = WORKERS.get().filter(|(_, count)| *count > 0).and_then(|(p, count)| spawn(petsc, p, *count).ok());
    let team = spawned.unwrap_or(Team::alone(petsc));
    petsc.team = Some(team);
    team
}

/// Starts `count` workers running `program` and merges them with this process, rank 0.
fn spawn(petsc: &Petsc, program: &std::path::Path, count: usize) -> Result<Team, SolveError> {
    let api = &petsc.api;
    let command = CString::new(program.as_os_str().as_encoded_bytes()).map_err(|e| mpi_error(e.to_string()))?;
    let flag = CString::new(WORKER_FLAG).expect("no NUL in the flag");
    let mut argv = [flag.as_ptr().cast_mut(), std::ptr::null_mut()];
    let (mut workers, mut comm) = (std::ptr::null_mut(), std::ptr::null_mut());
    // SAFETY: command and argv are NUL-terminated and outlive the call; argv ends with NULL;
    // the error handler makes a failed spawn return instead of aborting.
    unsafe {
        mpi(api.MPI_Comm_set_errhandler(petsc.comm_self, petsc.errors_return), "MPI_Comm_set_errhandler")?;
        let errors = std::ptr::null_mut();
        let code = api.MPI_Comm_spawn(
            command.as_ptr(),
            argv.as_mut_ptr(),
            count as c_int,
            petsc.info_null,
            0,
            petsc.comm_self,
            &mut workers,
            errors,
        );
        mpi(code, "MPI_Comm_spawn")?;
        mpi(api.MPI_Intercomm_merge(workers, 0, &mut comm), "MPI_Intercomm_merge")?;
        mpi(api.MPI_Comm_set_errhandler(comm, petsc.errors_return), "MPI_Comm_set_errhandler")?;
    }
    let (_, size) = rank_and_size(petsc, comm)?;
    Ok(Team { comm, size })
}

impl Team {
    /// This process alone.
    pub(super) fn alone(petsc: &Petsc) -> Team {
        Team { comm: petsc.comm_self, size: 1 }
    }

    /// Tells the workers of `task` and sends worker r its `part(r)`.
    pub(super) fn hand_out<'a>(
        &self,
        petsc: &Petsc,
        task: Task,
        part: impl Fn(usize) -> Part<'a>,
    ) -> Result<(), SolveError> {
        if self.size == 1 {
            return Ok(());
        }
        broadcast(petsc, self.comm, &mut [task.n as u64, task.blocks as u64, task.rtol.to_bits()])?;
        for r in 1..self.size {
            let p = part(r);
            send(petsc, self.comm, r, &p.row_ptr)?;
            send(petsc, self.comm, r, &p.col_idx)?;
            send(petsc, self.comm, r, &p.values)?;
            send(petsc, self.comm, r, &p.b)?;
            send(petsc, self.comm, r, &p.coordinates)?;
        }
        Ok(())
    }

    /// Receives each worker's rows of x, `rows[r]..rows[r + 1]`.
    pub(super) fn gather(&self, petsc: &Petsc, x: &mut [f64], rows: &[usize]) -> Result<(), SolveError> {
        (1..self.size).try_for_each(|r| receive(petsc, self.comm, r, &mut x[rows[r]..rows[r + 1]]))
    }
}

/// Runs this process as a worker of the team of the process that started it, solving each
/// task it is sent until that process exits; returns an exit code only on failure.
pub fn serve() -> i32 {
    let failure = match work() {
        Ok(never) => match never {},
        Err(e) => e,
    };
    eprintln!("damfem {WORKER_FLAG}: {failure}");
    1
}

/// The worker's loop (see [`serve`]).
fn work() -> Result<std::convert::Infallible, String> {
    let petsc = Petsc::load()?;
    let api = &petsc.api;
    let (mut parent, mut comm) = (std::ptr::null_mut(), std::ptr::null_mut());
    // SAFETY: MPI is initialised (by PETSc); both handles are written by MPI.
    unsafe {
        mpi(api.MPI_Comm_get_parent(&mut parent), "MPI_Comm_get_parent").map_err(|e| e.to_string())?;
        if parent == petsc.comm_null {
            return Err("a worker is started by damfem's iterative solve, not from the command line".into());
        }
        mpi(api.MPI_Intercomm_merge(parent, 1, &mut comm), "MPI_Intercomm_merge").map_err(|e| e.to_string())?;
    }
    let (rank, size) = rank_and_size(&petsc, comm).map_err(|e| e.to_string())?;
    loop {
        let solved = (|| {
            let mut header = [0u64; 3];
            broadcast(&petsc, comm, &mut header)?;
            let task = Task { n: header[0] as usize, blocks: header[1] as usize, rtol: f64::from_bits(header[2]) };
            let rows = task.first_rows(size);
            let m = rows[rank + 1] - rows[rank];
            let row_ptr = received(&petsc, comm, m + 1)?;
            let nonzeros = row_ptr[m] as usize;
            let col_idx = received(&petsc, comm, nonzeros)?;
            let values = received(&petsc, comm, nonzeros)?;
            let b = received(&petsc, comm, m)?;
            let coordinates = received(&petsc, comm, m)?;
            let part = Part {
                row_ptr: row_ptr.into(),
                col_idx: col_idx.into(),
                values: values.into(),
                b: b.into(),
                coordinates: coordinates.into(),
            };
            let (x, _, _) = solve_part(&petsc, comm, task, &part)?;
            send(&petsc, comm, 0, &x)
        })();
        solved.map_err(|e| e.to_string())?;
    }
}

/// This process's rank in `comm` and its size.
pub(super) fn rank_and_size(petsc: &Petsc, comm: ffi::MPI_Comm) -> Result<(usize, usize), SolveError> {
    let (mut rank, mut size) = (0, 0);
    // SAFETY: `comm` is a valid communicator; MPI writes the two integers.
    unsafe {
        mpi(petsc.api.MPI_Comm_rank(comm, &mut rank), "MPI_Comm_rank")?;
        mpi(petsc.api.MPI_Comm_size(comm, &mut size), "MPI_Comm_size")?;
    }
    Ok((rank as usize, size as usize))
}

/// The largest message, in bytes (MPI counts in `int`).
const CHUNK: usize = 1 << 30;

/// Broadcasts `words` from rank 0 to every process of `comm`.
fn broadcast(petsc: &Petsc, comm: ffi::MPI_Comm, words: &mut [u64; 3]) -> Result<(), SolveError> {
    let bytes = std::mem::size_of_val(words) as c_int;
    // SAFETY: `words` is a buffer of `bytes` bytes on every process.
    mpi(unsafe { petsc.api.MPI_Bcast(words.as_mut_ptr().cast(), bytes, petsc.byte, 0, comm) }, "MPI_Bcast")
}

/// Sends `data` to process `to` of `comm`, in chunks of at most [`CHUNK`] bytes.
fn send<T: Copy>(petsc: &Petsc, comm: ffi::MPI_Comm, to: usize, data: &[T]) -> Result<(), SolveError> {
    let (base, bytes) = (data.as_ptr().cast::<u8>(), std::mem::size_of_val(data));
    (0..bytes).step_by(CHUNK).try_for_each(|start| {
        let len = CHUNK.min(bytes - start) as c_int;
        // SAFETY: the chunk lies inside `data`, which MPI only reads.
        let code =
            unsafe { petsc.api.MPI_Send(base.add(start).cast::<c_void>(), len, petsc.byte, to as c_int, 0, comm) };
        mpi(code, "MPI_Send")
    })
}

/// Receives into `data` from process `from` of `comm` what [`send`] sent.
fn receive<T: Copy>(petsc: &Petsc, comm: ffi::MPI_Comm, from: usize, data: &mut [T]) -> Result<(), SolveError> {
    let (base, bytes) = (data.as_mut_ptr().cast::<u8>(), std::mem::size_of_val(data));
    (0..bytes).step_by(CHUNK).try_for_each(|start| {
        let len = CHUNK.min(bytes - start) as c_int;
        let status = std::ptr::null_mut();
        // SAFETY: the chunk lies inside `data`, which MPI writes; the status is ignored.
        let code = unsafe {
            petsc.api.MPI_Recv(base.add(start).cast::<c_void>(), len, petsc.byte, from as c_int, 0, comm, status)
        };
        mpi(code, "MPI_Recv")
    })
}

/// `len` values received from rank 0 of `comm`.
fn received<T: Copy + Default>(petsc: &Petsc, comm: ffi::MPI_Comm, len: usize) -> Result<Vec<T>, SolveError> {
    let mut data = vec![T::default(); len];
    receive(petsc, comm, 0, &mut data)?;
    Ok(data)
}

/// MPI's error `code` of the call `call` as a [`SolveError`].
fn mpi(code: c_int, call: &str) -> Result<(), SolveError> {
    if code == 0 {
        return Ok(());
    }
    Err(mpi_error(format!("{call} failed (MPI error {code})")))
}

/// An MPI failure as a [`SolveError`].
fn mpi_error(message: String) -> SolveError {
    SolveError::Factorisation(format!("MPI: {message}"))
}
