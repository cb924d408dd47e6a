//! Sparse direct solvers (faer) with the symbolic factorisation computed once per pattern,
//! the Schur complement of a Jacobian on its nonlinear layer ([`schur`]), Newton's method
//! built on them, and CG with PETSc's algebraic multigrid for large solids ([`petsc`]).

pub mod cholesky;
pub mod condition;
pub mod lu;
pub mod newton;
pub mod petsc;
pub mod schur;

pub use cholesky::Cholesky;
pub use lu::SparseLu;
pub use newton::{
    diverged, newton, newton_until, Iterate, NewtonError, NewtonOptions, NewtonReport, NonlinearSystem, Pair,
};
pub use schur::LayerSchur;

/// faer's factorisations run on one thread. On the small supernodes of 2D meshes the task
/// overhead of a parallel factorisation outweighs its gain: Scene A, P2, 83 494 unknowns,
/// 24 Newton steps took 25.2 s on one thread and 33.3 s on two. The estimator's patch
/// problems, not the factorisation, are what runs in parallel. The dense Schur complements on
/// a contact layer are factorised on one thread too, so that a solve gives the same bits
/// whatever the number of threads.
const PARALLELISM: faer::Par = faer::Par::Seq;

/// A workspace of the size faer asks for.
fn workspace(request: faer::dyn_stack::StackReq) -> Result<faer::dyn_stack::MemBuffer, SolveError> {
    faer::dyn_stack::MemBuffer::try_new(request).map_err(|_| SolveError::Factorisation("out of memory".into()))
}

/// a + b = s + e exactly, s = fl(a + b) (Knuth's TwoSum).
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let v = s - a;
    (s, (a - (s - v)) + (b - v))
}

/// Failure of a sparse factorisation.
#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    #[error("the stiffness matrix is not positive definite: the Dirichlet conditions do not prevent every rigid motion, or a material is degenerate")]
    NotPositiveDefinite,
    #[error("the matrix is singular: the Dirichlet and contact conditions do not prevent every rigid motion")]
    Singular,
    #[error("sparse factorisation failed: {0}")]
    Factorisation(String),
}
