//! CG preconditioned by smoothed-aggregation algebraic multigrid, PETSc's GAMG, through its C
//! API (Debian's libpetsc-real-dev): the iterative solver of large solids, whose sparse
//! Cholesky factor fills like N^{4/3} (docs/results.md, "Solids").
//!
//! The system is handed over with every dof, in blocks of three per node: a Dirichlet dof is
//! a row and column of its own, d u_i = d g_i with d the mean diagonal of K, so that the
//! blocks stay whole for GAMG and the scale of the matrix is kept. GAMG's near null space is
//! the six rigid motions of the node coordinates (`MatNullSpaceCreateRigidBody`).
//!
//! The solve runs on a team of MPI processes (`team.rs`): this one alone, or with the workers
//! the command line asked for ([`set_workers`]), each owning a contiguous range of nodes.
//!
//! PETSc is loaded when first needed (its BLAS starts threads as it loads, which must inherit
//! the signal mask of the command line: see `build.rs`), initialised once per process with
//! `-no_signal_handler` (the command line's signal handling stays in place), its errors
//! returned, not printed; it is never finalised.
//! PETSc's options database may tune the solve (the environment's `PETSC_OPTIONS`, e.g.
//! `-ksp_monitor`). This module and `io::gmsh` hold the crate's only `unsafe` code.

mod ffi;
mod team;

pub use team::{serve, set_workers, WORKER_FLAG};

use super::SolveError;
use std::borrow::Cow;
use std::ffi::{c_char, c_int, CStr};
use std::ops::Range;
use std::sync::{Mutex, PoisonError};
use team::Team;

/// The CSR form of a square matrix with 32-bit indices (PETSc's `PetscInt`).
pub struct Csr {
    pub row_ptr: Vec<i32>,
    pub col_idx: Vec<i32>,
    pub values: Vec<f64>,
}

/// An iterative solution: x, the CG iterations and the processes that solved.
#[derive(Debug, Clone)]
pub struct IterativeSolution {
    pub x: Vec<f64>,
    pub iterations: usize,
    pub processes: usize,
}

/// PETSc's library, initialised, with the MPI handles the solve needs.
struct Petsc {
    api: ffi::Petsc,
    comm_self: ffi::MPI_Comm,
    comm_null: ffi::MPI_Comm,
    byte: ffi::MPI_Datatype,
    info_null: ffi::MPI_Info,
    errors_return: ffi::MPI_Errhandler,
    team: Option<Team>,
}

// SAFETY: the library handle and the MPI handles are process-wide and immutable; the calls
// through them are made by one solve at a time (`PETSC` is locked).
unsafe impl Send for Petsc {}

/// PETSc, loaded and initialised on first use.
static PETSC: Mutex<Option<Result<Petsc, String>>> = Mutex::new(None);

/// The address of the data symbol `name` of `library` (or of its dependencies).
///
/// # Safety
/// `T` must be the symbol's C type.
unsafe fn data_symbol<T, H>(library: &libloading::Library, name: &[u8]) -> Result<*mut H, libloading::Error> {
    Ok((*library.get::<*mut T>(name)?).cast())
}

impl Petsc {
    /// Loads the library of `PETSC_LIBRARY` and initialises PETSc.
    fn load() -> Result<Petsc, String> {
        let path = env!("PETSC_LIBRARY");
        let fail =
            |e: libloading::Error| format!("cannot load PETSc from {path} (install Debian's libpetsc-real-dev): {e}");
        // SAFETY: loading PETSc runs its and MPI's initialisers, which have no preconditions;
        // the data symbols are Open MPI's predefined objects, whose addresses the MPI handles are.
        let petsc = unsafe {
            let library = libloading::Library::new(path).map_err(fail)?;
            let petsc = Petsc {
                api: ffi::Petsc::new(path).map_err(fail)?,
                comm_self: data_symbol::<ffi::ompi_predefined_communicator_t, _>(&library, b"ompi_mpi_comm_self\0")
                    .map_err(fail)?,
                comm_null: data_symbol::<ffi::ompi_predefined_communicator_t, _>(&library, b"ompi_mpi_comm_null\0")
                    .map_err(fail)?,
                byte: data_symbol::<ffi::ompi_predefined_datatype_t, _>(&library, b"ompi_mpi_byte\0").map_err(fail)?,
                info_null: data_symbol::<ffi::ompi_predefined_info_t, _>(&library, b"ompi_mpi_info_null\0")
                    .map_err(fail)?,
                errors_return: data_symbol::<ffi::ompi_predefined_errhandler_t, _>(
                    &library,
                    b"ompi_mpi_errors_return\0",
                )
                .map_err(fail)?,
                team: None,
            };
            // the addresses stay valid as long as the library is loaded: for the process
            std::mem::forget(library);
            petsc
        };
        let mut words: Vec<Vec<u8>> =
            ["damfem", "-no_signal_handler"].iter().map(|w| format!("{w}\0").into_bytes()).collect();
        let mut argv: Vec<*mut c_char> = words.iter_mut().map(|w| w.as_mut_ptr().cast()).collect();
        let mut argc = argv.len() as c_int;
        argv.push(std::ptr::null_mut());
        let mut argv_ptr = argv.as_mut_ptr();
        // SAFETY: argc/argv describe NUL-terminated strings, argv[argc] = NULL as MPI_Init
        // expects; both are leaked, since PETSc and MPI may keep pointers to them.
        let code = unsafe { petsc.api.PetscInitialize(&mut argc, &mut argv_ptr, std::ptr::null(), std::ptr::null()) };
        std::mem::forget(words);
        std::mem::forget(argv);
        petsc.check(code, "PetscInitialize").map_err(|e| e.to_string())?;
        // SAFETY: PetscReturnErrorHandler is PETSc's handler that returns the error code silently.
        let code =
            unsafe { petsc.api.PetscPushErrorHandler(Some(petsc.api.PetscReturnErrorHandler), std::ptr::null_mut()) };
        petsc.check(code, "PetscPushErrorHandler").map_err(|e| e.to_string())?;
        Ok(petsc)
    }

    /// PETSc's error `code` of the call `call` as a [`SolveError`].
    fn check(&self, code: c_int, call: &str) -> Result<(), SolveError> {
        if code == 0 {
            return Ok(());
        }
        let mut text: *const c_char = std::ptr::null();
        // SAFETY: PetscErrorMessage writes a pointer to a static string for a PETSc error code.
        let message = unsafe {
            self.api.PetscErrorMessage(code, &mut text, std::ptr::null_mut());
            if text.is_null() {
                String::new()
            } else {
                CStr::from_ptr(text).to_string_lossy().into_owned()
            }
        };
        Err(SolveError::Factorisation(format!("PETSc {call} failed (error {code}: {message})")))
    }
}

/// The rows of A x = b one process owns: its CSR rows (local row pointers, global column
/// indices), b and the node coordinates on them.
struct Part<'a> {
    row_ptr: Cow<'a, [i32]>,
    col_idx: Cow<'a, [i32]>,
    values: Cow<'a, [f64]>,
    b: Cow<'a, [f64]>,
    coordinates: Cow<'a, [f64]>,
}

impl<'a> Part<'a> {
    /// The `rows` of the whole system; borrowed when they start at row 0.
    fn of(a: &'a Csr, b: &'a [f64], coordinates: &'a [f64], rows: Range<usize>) -> Part<'a> {
        let (first, last) = (a.row_ptr[rows.start] as usize, a.row_ptr[rows.end] as usize);
        let row_ptr = &a.row_ptr[rows.start..=rows.end];
        Part {
            row_ptr: if first == 0 { row_ptr.into() } else { row_ptr.iter().map(|p| p - first as i32).collect() },
            col_idx: a.col_idx[first..last].into(),
            values: a.values[first..last].into(),
            b: b[rows.clone()].into(),
            coordinates: coordinates[rows].into(),
        }
    }
}

/// What every process of a team is told of a solve: the global size, the block size (dofs
/// per node) and the relative residual.
#[derive(Debug, Clone, Copy)]
struct Task {
    n: usize,
    blocks: usize,
    rtol: f64,
}

impl Task {
    /// The first row of each of `processes` processes, and the end: whole nodes, in order.
    fn first_rows(&self, processes: usize) -> Vec<usize> {
        let nodes = self.n / self.blocks;
        (0..=processes).map(|r| self.blocks * (nodes * r / processes)).collect()
    }
}

/// The PETSc objects of one solve, destroyed on drop in reverse order.
struct Objects<'a> {
    api: &'a ffi::Petsc,
    matrix: ffi::Mat,
    null_space: ffi::MatNullSpace,
    vectors: Vec<ffi::Vec>,
    ksp: ffi::KSP,
}

impl Drop for Objects<'_> {
    fn drop(&mut self) {
        // SAFETY: each handle is null or was created by PETSc and is destroyed once.
        unsafe {
            if !self.ksp.is_null() {
                self.api.KSPDestroy(&mut self.ksp);
            }
            for v in &mut self.vectors {
                self.api.VecDestroy(v);
            }
            if !self.null_space.is_null() {
                self.api.MatNullSpaceDestroy(&mut self.null_space);
            }
            if !self.matrix.is_null() {
                self.api.MatDestroy(&mut self.matrix);
            }
        }
    }
}

/// An option of PETSc's database set for one solve where the user's `PETSC_OPTIONS` left it
/// unset, and cleared on drop.
struct TeamDefault<'a> {
    api: &'a ffi::Petsc,
    name: Option<&'static CStr>,
}

impl<'a> TeamDefault<'a> {
    /// `name` = `value` unless the database has `name`.
    fn set(petsc: &'a Petsc, name: &'static CStr, value: &CStr) -> Result<TeamDefault<'a>, SolveError> {
        let (api, mut given) = (&petsc.api, ffi::PetscBool_PETSC_FALSE);
        let options = std::ptr::null_mut();
        // SAFETY: the global options database (null), a NUL-terminated name and value.
        unsafe {
            petsc.check(
                api.PetscOptionsHasName(options, std::ptr::null(), name.as_ptr(), &mut given),
                "PetscOptionsHasName",
            )?;
            if given == ffi::PetscBool_PETSC_TRUE {
                return Ok(TeamDefault { api, name: None });
            }
            petsc.check(api.PetscOptionsSetValue(options, name.as_ptr(), value.as_ptr()), "PetscOptionsSetValue")?;
        }
        Ok(TeamDefault { api, name: Some(name) })
    }
}

impl Drop for TeamDefault<'_> {
    fn drop(&mut self) {
        if let Some(name) = self.name {
            // SAFETY: clears the option this guard set in the global database.
            unsafe { self.api.PetscOptionsClearValue(std::ptr::null_mut(), name.as_ptr()) };
        }
    }
}

/// One process's share of a solve on `comm` (collective): its rows of x, the iterations and
/// PETSc's converged reason (positive when converged).
///
/// On a team, GAMG's Galerkin products P^T A P take PETSc's "nonscalable" algorithm (a dense
/// accumulator per row, for parallel matrices only): 3.0 s of setup against 3.7 s with the
/// default at 1.4·10⁵ unknowns on two processes (docs/results.md, "Solids").
fn solve_part(
    petsc: &Petsc,
    comm: ffi::MPI_Comm,
    task: Task,
    part: &Part,
) -> Result<(Vec<f64>, usize, i32), SolveError> {
    let _galerkin = match team::rank_and_size(petsc, comm)?.1 {
        1 => None,
        _ => Some(TeamDefault::set(petsc, c"-matptap_via", c"nonscalable")?),
    };
    let (api, bs, n, m) = (&petsc.api, task.blocks as ffi::PetscInt, task.n as ffi::PetscInt, part.b.len());
    let (matrix, null_space, ksp) = (std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null_mut());
    let mut o = Objects { api, matrix, null_space, vectors: Vec::new(), ksp };
    let mut x = vec![0.0; m];
    let mut iterations: ffi::PetscInt = 0;
    let mut reason: ffi::KSPConvergedReason = 0;
    let vector = |o: &mut Objects, values: *const f64| -> Result<ffi::Vec, SolveError> {
        let mut v: ffi::Vec = std::ptr::null_mut();
        // SAFETY: `values` points to the m entries this process owns, which outlive `o`.
        petsc.check(
            unsafe { api.VecCreateMPIWithArray(comm, bs, m as _, n, values, &mut v) },
            "VecCreateMPIWithArray",
        )?;
        o.vectors.push(v);
        Ok(v)
    };
    let coordinates = vector(&mut o, part.coordinates.as_ptr())?;
    let rhs = vector(&mut o, part.b.as_ptr())?;
    let solution = vector(&mut o, x.as_mut_ptr())?;
    // SAFETY: every pointer handed over points into a buffer that outlives the PETSc object
    // using it (`part` and `x` outlive `o`, dropped at the end of this scope); PETSc copies
    // the CSR arrays into its own matrix ("aij" is sequential on one process, and the other
    // type's preallocation call does nothing).
    unsafe {
        petsc.check(api.MatCreate(comm, &mut o.matrix), "MatCreate")?;
        petsc.check(api.MatSetSizes(o.matrix, m as _, m as _, n, n), "MatSetSizes")?;
        petsc.check(api.MatSetType(o.matrix, c"aij".as_ptr()), "MatSetType")?;
        petsc.check(api.MatSetBlockSize(o.matrix, bs), "MatSetBlockSize")?;
        let (i, j, v) = (part.row_ptr.as_ptr(), part.col_idx.as_ptr(), part.values.as_ptr());
        petsc.check(api.MatSeqAIJSetPreallocationCSR(o.matrix, i, j, v), "MatSeqAIJSetPreallocationCSR")?;
        petsc.check(api.MatMPIAIJSetPreallocationCSR(o.matrix, i, j, v), "MatMPIAIJSetPreallocationCSR")?;
        petsc.check(api.MatNullSpaceCreateRigidBody(coordinates, &mut o.null_space), "MatNullSpaceCreateRigidBody")?;
        petsc.check(api.MatSetNearNullSpace(o.matrix, o.null_space), "MatSetNearNullSpace")?;
        petsc.check(api.KSPCreate(comm, &mut o.ksp), "KSPCreate")?;
        petsc.check(api.KSPSetOperators(o.ksp, o.matrix, o.matrix), "KSPSetOperators")?;
        petsc.check(api.KSPSetType(o.ksp, c"cg".as_ptr()), "KSPSetType")?;
        let mut pc: ffi::PC = std::ptr::null_mut();
        petsc.check(api.KSPGetPC(o.ksp, &mut pc), "KSPGetPC")?;
        petsc.check(api.PCSetType(pc, c"gamg".as_ptr()), "PCSetType")?;
        petsc.check(api.KSPSetTolerances(o.ksp, task.rtol, 0.0, 1e10, 10_000), "KSPSetTolerances")?;
        petsc.check(api.KSPSetFromOptions(o.ksp), "KSPSetFromOptions")?;
        petsc.check(api.KSPSolve(o.ksp, rhs, solution), "KSPSolve")?;
        petsc.check(api.KSPGetIterationNumber(o.ksp, &mut iterations), "KSPGetIterationNumber")?;
        petsc.check(api.KSPGetConvergedReason(o.ksp, &mut reason), "KSPGetConvergedReason")?;
    }
    drop(o);
    Ok((x, iterations as usize, reason))
}

/// Solves A x = b (A symmetric positive definite, in `blocks` of dofs per node with node
/// coordinates `coordinates`, `blocks` per node) by CG with GAMG to ‖r‖ ≤ `rtol` ‖b‖, on this
/// process and its workers.
pub fn cg_gamg(
    a: &Csr,
    b: &[f64],
    coordinates: &[f64],
    blocks: usize,
    rtol: f64,
) -> Result<IterativeSolution, SolveError> {
    let mut loaded = PETSC.lock().unwrap_or_else(PoisonError::into_inner);
    let petsc = match loaded.get_or_insert_with(Petsc::load) {
        Ok(petsc) => petsc,
        Err(message) => return Err(SolveError::Factorisation(message.clone())),
    };
    let task = Task { n: b.len(), blocks, rtol };
    let team = team::join(petsc);
    let rows = task.first_rows(team.size);
    let solved = team.hand_out(petsc, task, |r| Part::of(a, b, coordinates, rows[r]..rows[r + 1])).and_then(|()| {
        let (mut x, iterations, reason) = solve_part(petsc, team.comm, task, &Part::of(a, b, coordinates, 0..rows[1]))?;
        x.resize(task.n, 0.0);
        team.gather(petsc, &mut x, &rows)?;
        Ok((x, iterations, reason))
    });
    if solved.is_err() {
        petsc.team = Some(Team::alone(petsc));
    }
    let (x, iterations, reason) = solved?;
    if reason <= 0 {
        return Err(SolveError::Factorisation(format!(
            "CG with GAMG did not converge to a relative residual of {rtol:e} (PETSc reason {reason}, {iterations} iterations)"
        )));
    }
    Ok(IterativeSolution { x, iterations, processes: team.size })
}
