//! Sparse direct solvers (faer) with the symbolic factorisation computed once per pattern.

pub mod cholesky;

pub use cholesky::Cholesky;

/// Failure of a sparse factorisation.
#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    #[error("the stiffness matrix is not positive definite: the Dirichlet conditions do not prevent every rigid motion, or a material is degenerate")]
    NotPositiveDefinite,
    #[error("sparse factorisation failed: {0}")]
    Factorisation(String),
}
