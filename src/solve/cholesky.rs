//! Sparse Cholesky factorisation K = L Lᵀ of a symmetric positive definite matrix.
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree) depends only on the
//! pattern; it is done once and reused by every numeric factorisation on that pattern.

use super::{workspace, SolveError, PARALLELISM};
use crate::fem::sparse::SparsePattern;
use faer::dyn_stack::MemStack;
use faer::perm::PermRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::supernodal::{SupernodalLltRef, SymbolicSupernodalCholesky};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
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

    /// Symbolic analysis of `pattern` with the dofs `last` eliminated last, in this order, and
    /// the others in the approximate minimum degree order of the whole pattern; supernodal,
    /// so that [`Cholesky::trailing_block`] can read the factor.
    pub(super) fn analyse_with_last(pattern: &SparsePattern, last: &[usize]) -> Result<Self, SolveError> {
        let n = pattern.n();
        let (mut amd_order, mut amd_inverse) = (vec![0usize; n], vec![0usize; n]);
        let mut buffer = workspace(amd::order_maybe_unsorted_scratch::<usize>(n, pattern.nnz()))?;
        amd::order_maybe_unsorted(
            &mut amd_order,
            &mut amd_inverse,
            pattern.symbolic(),
            Default::default(),
            MemStack::new(&mut buffer),
        )
        .map_err(|e| SolveError::Factorisation(format!("{e:?}")))?;
        let mut is_last = vec![false; n];
        for &dof in last {
            is_last[dof] = true;
        }
        // forward permutation: new position → dof
        let forward: Vec<usize> =
            amd_order.iter().copied().filter(|&dof| !is_last[dof]).chain(last.iter().copied()).collect();
        let mut inverse = vec![0; n];
        for (position, &dof) in forward.iter().enumerate() {
            inverse[dof] = position;
        }
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let ordering = SymmetricOrdering::Custom(PermRef::new_checked(&forward, &inverse, n));
        let symbolic = factorize_symbolic_cholesky(pattern.symbolic(), Side::Lower, ordering, params)
            .map_err(|e| SolveError::Factorisation(format!("{e:?}")))?;
        Ok(Cholesky { symbolic })
    }

    /// Numeric factorisation of K with the analysed pattern and the given values.
    pub fn factor(&self, pattern: &SparsePattern, values: &[f64]) -> Result<CholeskyFactors<'_>, SolveError> {
        Ok(CholeskyFactors { cholesky: self, factor: self.factor_values(pattern, values)? })
    }

    /// The values of L for K with the analysed pattern and the given values.
    pub(super) fn factor_values(&self, pattern: &SparsePattern, values: &[f64]) -> Result<Vec<f64>, SolveError> {
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
        Ok(factor)
    }

    /// Overwrites every column b of `rhs` by K⁻¹ b, for the values `factor` of L.
    pub(super) fn solve_in_place(&self, factor: &[f64], rhs: &mut Mat<f64>) -> Result<(), SolveError> {
        let mut buffer = workspace(self.symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), PARALLELISM))?;
        LltRef::new(&self.symbolic, factor).solve_in_place_with_conj(
            Conj::No,
            rhs.as_mut(),
            PARALLELISM,
            MemStack::new(&mut buffer),
        );
        Ok(())
    }

    /// The supernodal structure of L and the fill-reducing ordering (position → dof), as
    /// [`Cholesky::analyse_with_last`] makes them.
    fn supernodal(&self) -> Option<(&SymbolicSupernodalCholesky<usize>, &[usize])> {
        match (self.symbolic.raw(), self.symbolic.perm()) {
            (SymbolicCholeskyRaw::Supernodal(symbolic), Some(order)) => Some((symbolic, order.arrays().0)),
            _ => None,
        }
    }

    /// The supernodal structure and ordering, or the error of a solve without them.
    fn supernodal_or_error(&self) -> Result<(&SymbolicSupernodalCholesky<usize>, &[usize]), SolveError> {
        self.supernodal().ok_or(SolveError::Factorisation("L is not supernodal with an ordering".into()))
    }

    /// The trailing m × m block of L (lower triangular, dense) for the values `factor`: with the
    /// last m dofs eliminated last ([`Cholesky::analyse_with_last`]), L_LL L_LLᵀ is the Schur
    /// complement K_LL − K_LI K_II⁻¹ K_IL of the others. None for a simplicial analysis.
    pub(super) fn trailing_block(&self, factor: &[f64], m: usize) -> Option<Mat<f64>> {
        let (symbolic, _) = self.supernodal()?;
        let first = symbolic.nrows() - m;
        let llt = SupernodalLltRef::new(symbolic, factor);
        let mut block = Mat::zeros(m, m);
        for s in 0..symbolic.n_supernodes() {
            let node = llt.supernode(s);
            let (start, values) = (node.start(), node.val());
            let width = values.ncols();
            // row r of the supernode: column start + r of its diagonal block, then its pattern
            let row = |r: usize| if r < width { start + r } else { node.pattern()[r - width] };
            for c in (0..width).filter(|&c| start + c >= first) {
                for r in c..values.nrows() {
                    block[(row(r) - first, start + c - first)] = values[(r, c)];
                }
            }
        }
        Some(block)
    }

    /// min_i L_ii² / (P K Pᵀ)_ii over the pivots of a supernodal L: a lower bound of
    /// λ_min(K) / λ_max(K) = 1/κ₂(K), since L_ii² ≥ λ_min(K) and K_jj ≤ λ_max(K).
    pub(super) fn pivot_ratio(&self, factor: &[f64], pattern: &SparsePattern, values: &[f64]) -> Option<f64> {
        let (symbolic, order) = self.supernodal()?;
        let llt = SupernodalLltRef::new(symbolic, factor);
        let diagonal = |dof: usize| values[pattern.position(dof, dof)];
        let ratios = (0..symbolic.n_supernodes()).flat_map(|s| {
            let node = llt.supernode(s);
            let (start, values) = (node.start(), node.val());
            (0..values.ncols()).map(move |c| (start + c, values[(c, c)]))
        });
        Some(ratios.map(|(i, l_ii)| l_ii * l_ii / diagonal(order[i])).fold(f64::INFINITY, f64::min))
    }

    /// w = L⁻¹ P b, in the eliminated order, for the values `factor` of a supernodal L.
    pub(super) fn forward_substitute(&self, factor: &[f64], b: &[f64]) -> Result<Mat<f64>, SolveError> {
        let (symbolic, order) = self.supernodal_or_error()?;
        let mut w = Mat::from_fn(b.len(), 1, |i, _| b[order[i]]);
        let mut buffer = workspace(symbolic.solve_in_place_scratch::<f64>(1, PARALLELISM))?;
        let llt = SupernodalLltRef::new(symbolic, factor);
        llt.l_solve_with_conj(Conj::No, w.as_mut(), PARALLELISM, MemStack::new(&mut buffer));
        Ok(w)
    }

    /// x = Pᵀ L⁻ᵀ v, for v in the eliminated order and the values `factor` of a supernodal L.
    pub(super) fn back_substitute(&self, factor: &[f64], mut v: Mat<f64>) -> Result<Vec<f64>, SolveError> {
        let (symbolic, order) = self.supernodal_or_error()?;
        let mut buffer = workspace(symbolic.solve_in_place_scratch::<f64>(1, PARALLELISM))?;
        let llt = SupernodalLltRef::new(symbolic, factor);
        llt.l_transpose_solve_with_conj(Conj::No, v.as_mut(), PARALLELISM, MemStack::new(&mut buffer));
        let mut x = vec![0.0; v.nrows()];
        for (position, &dof) in order.iter().enumerate() {
            x[dof] = v[(position, 0)];
        }
        Ok(x)
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
    cholesky: &'a Cholesky,
    factor: Vec<f64>,
}

impl CholeskyFactors<'_> {
    /// Overwrites every column b of `rhs` by K⁻¹ b.
    pub fn solve_in_place(&self, rhs: &mut Mat<f64>) -> Result<(), SolveError> {
        self.cholesky.solve_in_place(&self.factor, rhs)
    }
}
