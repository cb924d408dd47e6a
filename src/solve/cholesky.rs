//! Sparse Cholesky factorisation K = L Lᵀ of a symmetric positive definite matrix.
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree) depends only on the
//! pattern; it is done once and reused by every numeric factorisation on that pattern.

use super::SolveError;
use crate::fem::sparse::SparsePattern;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::{Mat, Side};

/// Symbolic Cholesky factorisation of a [`SparsePattern`] (lower triangle).
pub struct Cholesky {
    symbolic: SymbolicLlt<usize>,
}

impl Cholesky {
    /// Symbolic analysis of `pattern`.
    pub fn analyse(pattern: &SparsePattern) -> Result<Self, SolveError> {
        let symbolic = SymbolicLlt::try_new(pattern.symbolic(), Side::Lower)
            .map_err(|e| SolveError::Factorisation(format!("{e:?}")))?;
        Ok(Cholesky { symbolic })
    }

    /// Solves K x = b for K with the analysed pattern and the given values.
    pub fn solve(&self, pattern: &SparsePattern, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, SolveError> {
        let llt = Llt::try_new_with_symbolic(self.symbolic.clone(), pattern.matrix(values), Side::Lower).map_err(
            |e| match e {
                faer::sparse::linalg::LltError::Numeric(_) => SolveError::NotPositiveDefinite,
                other => SolveError::Factorisation(format!("{other:?}")),
            },
        )?;
        let mut x = Mat::from_fn(rhs.len(), 1, |i, _| rhs[i]);
        llt.solve_in_place(x.as_mut());
        Ok((0..rhs.len()).map(|i| x[(i, 0)]).collect())
    }
}
