//! Sparse Cholesky factorisation K = L Lᵀ of a symmetric positive definite matrix.
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree) depends only on the
//! pattern; it is done once and reused by every numeric factorisation on that pattern.

use super::{workspace, SolveError, PARALLELISM};
use crate::fem::sparse::SparsePattern;
use faer::dyn_stack::MemStack;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef, SymbolicCholesky};
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

    /// Numeric factorisation of K with the analysed pattern and the given values.
    pub fn factor(&self, pattern: &SparsePattern, values: &[f64]) -> Result<CholeskyFactors<'_>, SolveError> {
        let mut factor = vec![0.0; self.symbolic.len_val()];
        let mut buffer =
            workspace(self.symbolic.factorize_numeric_llt_scratch::<f64>(PARALLELISM, Default::default()))?;
        self.symbolic
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
        Ok(CholeskyFactors { symbolic: &self.symbolic, factor })
    }

    /// Solves K x = b for K with the analysed pattern and the given values.
    pub fn solve(&self, pattern: &SparsePattern, values: &[f64], rhs: &[f64]) -> Result<Vec<f64>, SolveError> {
        let mut x = Mat::from_fn(rhs.len(), 1, |i, _| rhs[i]);
        self.factor(pattern, values)?.solve_in_place(&mut x)?;
        Ok((0..rhs.len()).map(|i| x[(i, 0)]).collect())
    }
}

/// Numeric Cholesky factors, for any number of right-hand sides.
pub struct CholeskyFactors<'a> {
    symbolic: &'a SymbolicCholesky<usize>,
    factor: Vec<f64>,
}

impl CholeskyFactors<'_> {
    /// Overwrites every column b of `rhs` by K⁻¹ b.
    pub fn solve_in_place(&self, rhs: &mut Mat<f64>) -> Result<(), SolveError> {
        let mut buffer = workspace(self.symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), PARALLELISM))?;
        LltRef::new(self.symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            rhs.as_mut(),
            PARALLELISM,
            MemStack::new(&mut buffer),
        );
        Ok(())
    }
}
