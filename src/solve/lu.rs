//! Sparse LU factorisation of a non-symmetric matrix, symbolic part computed once.
//!
//! The Newton Jacobian of Nitsche contact is not symmetric (docs/method.md §1.5). Its
//! pattern is fixed per mesh, so the column ordering and symbolic structure are computed
//! once and every Newton step only refactors numerically.

use super::SolveError;
use crate::fem::sparse::SparsePattern;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::Mat;

/// Symbolic LU factorisation of a [`SparsePattern`].
pub struct SparseLu {
    symbolic: SymbolicLu<usize>,
}

impl SparseLu {
    /// Symbolic analysis of `pattern`.
    pub fn analyse(pattern: &SparsePattern) -> Result<Self, SolveError> {
        let symbolic =
            SymbolicLu::try_new(pattern.symbolic()).map_err(|e| SolveError::Factorisation(format!("{e:?}")))?;
        Ok(SparseLu { symbolic })
    }

    /// Numeric factorisation of the matrix with the analysed pattern and these values.
    pub fn factor(&self, pattern: &SparsePattern, values: &[f64]) -> Result<Lu<usize, f64>, SolveError> {
        Lu::try_new_with_symbolic(self.symbolic.clone(), pattern.matrix(values)).map_err(|e| match e {
            faer::sparse::linalg::LuError::SymbolicSingular { .. } => SolveError::Singular,
            other => SolveError::Factorisation(format!("{other:?}")),
        })
    }
}

/// Solves A x = b with a numeric factorisation.
pub fn solve_with(lu: &Lu<usize, f64>, rhs: &[f64]) -> Vec<f64> {
    let mut x = Mat::from_fn(rhs.len(), 1, |i, _| rhs[i]);
    lu.solve_in_place(x.as_mut());
    (0..rhs.len()).map(|i| x[(i, 0)]).collect()
}
