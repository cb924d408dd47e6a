//! Sparse direct solvers (faer) with the symbolic factorisation computed once per pattern,
//! and Newton's method built on them.

pub mod cholesky;
pub mod lu;
pub mod newton;

pub use cholesky::Cholesky;
pub use lu::SparseLu;
pub use newton::{newton, newton_until, Iterate, NewtonError, NewtonOptions, NewtonReport, NonlinearSystem};

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
