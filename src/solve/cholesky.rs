//! Sparse Cholesky factorisation K = L Lᵀ of a symmetric positive definite matrix.
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree) depends only on the
//! pattern; it is done once and reused by every numeric factorisation on that pattern.

use super::{workspace, SolveError, PARALLELISM};
use crate::fem::sparse::SparsePattern;
use faer::dyn_stack::MemStack;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymbolicCholesky};
use faer::{Conj, Mat, Side};

/// Symbolic Cholesky factorisation of a [`SparsePattern`] (lower triangle).
pub struct Cholesky {
    symbolic: SymbolicCholesky<usize>,
}

impl Cholesky {
    /// Symbolic analysis of `pattern`.
    pub fn analyse(pattern: &SparsePattern) -> Result<Self, SolveError> {
        let symbolic =
            factorize_symbolic_cholesky(pattern.symbolic(), Side::Lower, Default::default(), Default::default())
                .map_err(|e| SolveError::Factorisation(format!("{e:?}")))?;
        Ok(Cholesky { symbolic })
    }

    /// Solves K x = b for K with the analysed pattern and the given values.
    pub fn solve(&self, pattern: &SparsePattern, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, SolveError> {
        let mut factor = vec![0.0; self.symbolic.len_val()];
        let request = self
            .symbolic
            .factorize_numeric_llt_scratch::<f64>(PARALLELISM, Default::default())
            .or(self.symbolic.solve_in_place_scratch::<f64>(1, PARALLELISM));
        let mut buffer = workspace(request)?;
        let llt = self
            .symbolic
            .factorize_numeric_llt(
                &mut factor,
                pattern.matrix(values),
                Side::Lower,
                Default::default(),
                PARALLELISM,
                MemStack::new(&mut buffer),
                Default::default(),
            )
            .map_err(|_| SolveError::NotPositiveDefinite)?;
        let mut x = Mat::from_fn(rhs.len(), 1, |i, _| rhs[i]);
        llt.solve_in_place_with_conj(Conj::No, x.as_mut(), PARALLELISM, MemStack::new(&mut buffer));
        Ok((0..rhs.len()).map(|i| x[(i, 0)]).collect())
    }
}
