//! CG preconditioned by smoothed-aggregation algebraic multigrid, PETSc's GAMG, through its C
//! API (Debian's libpetsc-real-dev, one process): the iterative solver of large solids, whose
//! sparse Cholesky factor fills like N^{4/3} (docs/results.md, "Solids").
//!
//! The system is handed over with every dof, in blocks of three per node: a Dirichlet dof is
//! a row and column of its own, d u_i = d g_i with d the mean diagonal of K, so that the
//! blocks stay whole for GAMG and the scale of the matrix is kept. GAMG's near null space is
//! the six rigid motions of the node coordinates (`MatNullSpaceCreateRigidBody`).
//!
//! PETSc is loaded when first needed (its BLAS starts threads as it loads, which must inherit
//! the signal mask of the command line: see `build.rs`), initialised once per process with
//! `-no_signal_handler` (the command line's signal handling stays in place), its errors
//! returned, not printed; it is never finalised.
//! PETSc's options database may tune the solve (the environment's `PETSC_OPTIONS`, e.g.
//! `-ksp_monitor`). This module and `io::gmsh` hold the crate's only `unsafe` code.

mod ffi;

use super::SolveError;
use std::ffi::{c_char, c_int, CStr};
use std::sync::{Mutex, PoisonError};

/// The CSR form of a square matrix with 32-bit indices (PETSc's `PetscInt`).
pub struct Csr {
    pub row_ptr: Vec<i32>,
    pub col_idx: Vec<i32>,
    pub values: Vec<f64>,
}

/// An iterative solution: x, the CG iterations and the final ‖r‖ / ‖b‖ (preconditioned).
#[derive(Debug, Clone)]
pub struct IterativeSolution {
    pub x: Vec<f64>,
    pub iterations: usize,
}

/// PETSc's library, initialised, and PETSC_COMM_SELF.
struct Petsc {
    api: ffi::Petsc,
    comm_self: ffi::MPI_Comm,
}

// SAFETY: the library handle and the communicator's address are process-wide and immutable;
// the calls through them are made by one solve at a time (`PETSC` is locked).
unsafe impl Send for Petsc {}

/// PETSc, loaded and initialised on first use.
static PETSC: Mutex<Option<Result<Petsc, String>>> = Mutex::new(None);

impl Petsc {
    /// Loads the library of `PETSC_LIBRARY` and initialises PETSc.
    fn load() -> Result<Petsc, String> {
        let path = env!("PETSC_LIBRARY");
        let fail =
            |e: libloading::Error| format!("cannot load PETSc from {path} (install Debian's libpetsc-real-dev): {e}");
        // SAFETY: loading PETSc runs its and MPI's initialisers, which have no preconditions.
        let api = unsafe { ffi::Petsc::new(path) }.map_err(fail)?;
        // SAFETY: the same library again (a second reference), to find the data symbol of Open
        // MPI's predefined communicator, which PETSC_COMM_SELF is the address of.
        let comm_self = unsafe {
            let library = libloading::Library::new(path).map_err(fail)?;
            let symbol =
                library.get::<*mut ffi::ompi_predefined_communicator_t>(b"ompi_mpi_comm_self\0").map_err(fail)?;
            let address = (*symbol).cast();
            std::mem::forget(library);
            address
        };
        let petsc = Petsc { api, comm_self };
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

/// Solves A x = b (A symmetric positive definite, in `blocks` of dofs per node with node
/// coordinates `coordinates`, `blocks` per node) by CG with GAMG to ‖r‖ ≤ `rtol` ‖b‖.
pub fn cg_gamg(
    a: &Csr,
    b: &[f64],
    coordinates: &[f64],
    blocks: usize,
    rtol: f64,
) -> Result<IterativeSolution, SolveError> {
    let mut loaded = PETSC.lock().unwrap_or_else(PoisonError::into_inner);
    let petsc = match loaded.get_or_insert_with(Petsc::load) {
        Ok(petsc) => &*petsc,
        Err(message) => return Err(SolveError::Factorisation(message.clone())),
    };
    let (api, comm, bs, n) = (&petsc.api, petsc.comm_self, blocks as ffi::PetscInt, b.len());
    let (matrix, null_space, ksp) = (std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null_mut());
    let mut o = Objects { api, matrix, null_space, vectors: Vec::new(), ksp };
    let mut x = vec![0.0; n];
    let mut iterations: ffi::PetscInt = 0;
    let mut reason: ffi::KSPConvergedReason = 0;
    // SAFETY: every pointer handed over points into a buffer that outlives the PETSc object
    // using it (`a`, `b`, `coordinates`, `x` outlive `o`, dropped at the end of this scope);
    // PETSc copies the CSR arrays into its own matrix.
    unsafe {
        petsc.check(api.MatCreate(comm, &mut o.matrix), "MatCreate")?;
        petsc.check(api.MatSetSizes(o.matrix, n as _, n as _, n as _, n as _), "MatSetSizes")?;
        petsc.check(api.MatSetType(o.matrix, c"seqaij".as_ptr()), "MatSetType")?;
        petsc.check(api.MatSetBlockSize(o.matrix, bs), "MatSetBlockSize")?;
        petsc.check(
            api.MatSeqAIJSetPreallocationCSR(o.matrix, a.row_ptr.as_ptr(), a.col_idx.as_ptr(), a.values.as_ptr()),
            "MatSeqAIJSetPreallocationCSR",
        )?;
        let mut coords: ffi::Vec = std::ptr::null_mut();
        petsc.check(
            api.VecCreateSeqWithArray(comm, bs, coordinates.len() as _, coordinates.as_ptr(), &mut coords),
            "VecCreateSeqWithArray",
        )?;
        o.vectors.push(coords);
        petsc.check(api.MatNullSpaceCreateRigidBody(coords, &mut o.null_space), "MatNullSpaceCreateRigidBody")?;
        petsc.check(api.MatSetNearNullSpace(o.matrix, o.null_space), "MatSetNearNullSpace")?;
        let (mut rhs, mut solution): (ffi::Vec, ffi::Vec) = (std::ptr::null_mut(), std::ptr::null_mut());
        petsc.check(api.VecCreateSeqWithArray(comm, 1, n as _, b.as_ptr(), &mut rhs), "VecCreateSeqWithArray")?;
        o.vectors.push(rhs);
        petsc.check(
            api.VecCreateSeqWithArray(comm, 1, n as _, x.as_mut_ptr(), &mut solution),
            "VecCreateSeqWithArray",
        )?;
        o.vectors.push(solution);
        petsc.check(api.KSPCreate(comm, &mut o.ksp), "KSPCreate")?;
        petsc.check(api.KSPSetOperators(o.ksp, o.matrix, o.matrix), "KSPSetOperators")?;
        petsc.check(api.KSPSetType(o.ksp, c"cg".as_ptr()), "KSPSetType")?;
        let mut pc: ffi::PC = std::ptr::null_mut();
        petsc.check(api.KSPGetPC(o.ksp, &mut pc), "KSPGetPC")?;
        petsc.check(api.PCSetType(pc, c"gamg".as_ptr()), "PCSetType")?;
        petsc.check(api.KSPSetTolerances(o.ksp, rtol, 0.0, 1e10, 10_000), "KSPSetTolerances")?;
        petsc.check(api.KSPSetFromOptions(o.ksp), "KSPSetFromOptions")?;
        petsc.check(api.KSPSolve(o.ksp, rhs, solution), "KSPSolve")?;
        petsc.check(api.KSPGetIterationNumber(o.ksp, &mut iterations), "KSPGetIterationNumber")?;
        petsc.check(api.KSPGetConvergedReason(o.ksp, &mut reason), "KSPGetConvergedReason")?;
    }
    drop(o);
    if reason <= 0 {
        return Err(SolveError::Factorisation(format!(
            "CG with GAMG did not converge to a relative residual of {rtol:e} (PETSc reason {reason}, {iterations} iterations)"
        )));
    }
    Ok(IterativeSolution { x, iterations: iterations as usize })
}
