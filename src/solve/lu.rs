//! Sparse LU factorisation of a non-symmetric matrix, symbolic part computed once.
//!
//! The Newton Jacobian of Nitsche contact is not symmetric (docs/method.md §1.5). Its
//! pattern is fixed per mesh, so the column ordering and symbolic structure are computed
//! once and every Newton step only refactors numerically.

use super::{workspace, SolveError, PARALLELISM};
use crate::fem::sparse::SparsePattern;
use faer::dyn_stack::MemStack;
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::linalg::LuError;
use faer::{Conj, Mat};

/// Symbolic LU factorisation of a [`SparsePattern`].
pub struct SparseLu {
    symbolic: SymbolicLu<usize>,
}

/// Numeric LU factors of a matrix with the analysed pattern.
pub struct LuFactors<'a> {
    symbolic: &'a SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
}

impl SparseLu {
    /// Symbolic analysis of `pattern`.
    pub fn analyse(pattern: &SparsePattern) -> Result<Self, SolveError> {
        let symbolic = factorize_symbolic_lu(pattern.symbolic(), Default::default())
            .map_err(|e| SolveError::Factorisation(format!("{e:?}")))?;
        Ok(SparseLu { symbolic })
    }

    /// Numeric factorisation of the matrix with the analysed pattern and these values.
    pub fn factor(&self, pattern: &SparsePattern, values: &[f64]) -> Result<LuFactors<'_>, SolveError> {
        let mut numeric = NumericLu::new();
        let mut buffer = workspace(self.symbolic.factorize_numeric_lu_scratch::<f64>(PARALLELISM, Default::default()))?;
        self.symbolic
            .factorize_numeric_lu(
                &mut numeric,
                pattern.matrix(values),
                PARALLELISM,
                MemStack::new(&mut buffer),
                Default::default(),
            )
            .map_err(|e| match e {
                LuError::SymbolicSingular { .. } => SolveError::Singular,
                other => SolveError::Factorisation(format!("{other:?}")),
            })?;
        Ok(LuFactors { symbolic: &self.symbolic, numeric })
    }
}

impl LuFactors<'_> {
    /// Solves A x = b.
    pub fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        self.substitute(rhs, false)
    }

    /// Solves Aᵀ x = b.
    pub fn solve_transpose(&self, rhs: &[f64]) -> Vec<f64> {
        self.substitute(rhs, true)
    }

    /// Forward and back substitution with the factors of A, or of Aᵀ if `transpose`.
    fn substitute(&self, rhs: &[f64], transpose: bool) -> Vec<f64> {
        let mut x = Mat::from_fn(rhs.len(), 1, |i, _| rhs[i]);
        let (n, par) = (1, PARALLELISM);
        let request = if transpose {
            self.symbolic.solve_transpose_in_place_scratch::<f64>(n, par)
        } else {
            self.symbolic.solve_in_place_scratch::<f64>(n, par)
        };
        let mut buffer = faer::dyn_stack::MemBuffer::new(request);
        let stack = MemStack::new(&mut buffer);
        // the numeric part was computed on this symbolic part by `SparseLu::factor`
        let lu = LuRef::new_unchecked(self.symbolic, &self.numeric);
        if transpose {
            lu.solve_transpose_in_place_with_conj(Conj::No, x.as_mut(), par, stack);
        } else {
            lu.solve_in_place_with_conj(Conj::No, x.as_mut(), par, stack);
        }
        (0..rhs.len()).map(|i| x[(i, 0)]).collect()
    }
}
