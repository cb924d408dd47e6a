//! Newton steps for a Jacobian J(x) = K + E C(x) Eᵀ: a constant symmetric positive definite
//! bulk K and a nonlinear part C(x) on a thin layer of m ≪ n dofs (E: the n × m selection of
//! the layer), such as the Nitsche terms of the cells along Γ_C.
//!
//! K is factorised once by sparse Cholesky with the layer L eliminated after the interior I:
//! P K Pᵀ = L Lᵀ, L = [L_II 0; L_LI L_LL]. The trailing block gives the Schur complement of the
//! interior, S₀ = K_LL − K_LI K_II⁻¹ K_IL = L_LL L_LLᵀ. Since L⁻¹ E = [0; L_LL⁻¹],
//!
//!   P J Pᵀ = L diag(I, L_LL⁻¹ S L_LL⁻ᵀ) Lᵀ,   S = S₀ + C_LL,
//!
//! with S the Schur complement of J on the layer. Each step factors S, dense m × m, by LU with
//! partial pivoting (C is not symmetric for θ ≠ −1, nor with friction), and solves J x = b by
//! w = L⁻¹ P b, w_L ← L_LLᵀ S⁻¹ L_LL w_L, x = Pᵀ L⁻ᵀ w: one sparse forward and back
//! substitution and dense products of size m, the block elimination of J with the interior
//! eliminated first. A step costs 2m³/3 flops for the LU, and each dense matrix takes 8m²
//! bytes: above [`MAX_LAYER`] layer dofs the caller keeps the sparse LU of the whole Jacobian.

use super::cholesky::Cholesky;
use super::{workspace, SolveError, PARALLELISM};
use crate::fem::sparse::SparsePattern;
use faer::dyn_stack::MemStack;
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::linalg::matmul::matmul;
use faer::perm::PermRef;
use faer::{Accum, Conj, Mat, MatRef};

/// The largest layer factorised dense: at 6 000 dofs one step's LU costs 1.4·10¹¹ flops (a
/// few seconds) and each dense matrix 288 MB.
pub const MAX_LAYER: usize = 6000;

/// K is taken as definite if every pivot keeps L_ii² ≥ 10⁻¹⁰ K_ii, which holds when κ₂(K) ≤
/// 10¹⁰. A body held only by its contact has a singular K, whose floating-point Cholesky may
/// still succeed with pivots at round-off: the sparse LU of J takes those.
const MIN_PIVOT_RATIO: f64 = 1e-10;

/// K factorised once with its Schur complement S₀ on the layer.
pub struct LayerSchur {
    cholesky: Cholesky,
    factor: Vec<f64>,
    /// The layer's dofs, in the order of the dense matrices.
    layer: Vec<usize>,
    /// L_LL and S₀ − K_LL, to which a step adds J_LL.
    l_ll: Mat<f64>,
    s0_minus_k: Mat<f64>,
    /// The pattern's entries inside the layer: layer row, layer column, position.
    entries: Vec<(usize, usize, usize)>,
}

impl LayerSchur {
    /// Factorises K (`stiffness` on `pattern`) with the dofs `layer` eliminated last. None if
    /// the layer is empty or has more than [`MAX_LAYER`] dofs, or if K is not positive definite
    /// or has a pivot below 10⁻¹⁰ K_ii (a body held only by its contact): Newton then factors J
    /// by sparse LU.
    pub fn new(pattern: &SparsePattern, stiffness: &[f64], layer: Vec<usize>) -> Option<Self> {
        let m = layer.len();
        if m == 0 || m > MAX_LAYER {
            return None;
        }
        let cholesky = Cholesky::analyse_with_last(pattern, &layer).ok()?;
        let factor = cholesky.factor_values(pattern, stiffness).ok()?;
        if cholesky.pivot_ratio(&factor, pattern, stiffness)? < MIN_PIVOT_RATIO {
            return None;
        }
        let l_ll = cholesky.trailing_block(&factor, m)?;
        let entries = layer_entries(pattern, &layer);
        let mut s0_minus_k = product(l_ll.as_ref(), l_ll.transpose());
        for &(r, c, position) in &entries {
            s0_minus_k[(r, c)] -= stiffness[position];
        }
        Some(LayerSchur { cholesky, factor, layer, l_ll, s0_minus_k, entries })
    }

    /// Number of layer dofs m.
    pub fn layer_size(&self) -> usize {
        self.layer.len()
    }

    /// The dense LU of S = S₀ + C_LL = S₀ − K_LL + J_LL for the Jacobian values `jacobian` (on
    /// the pattern of K).
    pub fn factor(&self, jacobian: &[f64]) -> Result<SchurFactors<'_>, SolveError> {
        let mut lu = self.s0_minus_k.clone();
        for &(r, c, position) in &self.entries {
            lu[(r, c)] += jacobian[position];
        }
        let m = self.layer.len();
        let (mut rows, mut inverse) = (vec![0usize; m], vec![0usize; m]);
        let mut buffer = workspace(factor::lu_in_place_scratch::<usize, f64>(m, m, PARALLELISM, Default::default()))?;
        let stack = MemStack::new(&mut buffer);
        factor::lu_in_place(lu.as_mut(), &mut rows, &mut inverse, PARALLELISM, stack, Default::default());
        Ok(SchurFactors { schur: self, lu, rows, inverse })
    }
}

/// The entries (r, c) of `pattern` with both dofs in `layer`, as (index of r in the layer,
/// index of c, position).
fn layer_entries(pattern: &SparsePattern, layer: &[usize]) -> Vec<(usize, usize, usize)> {
    let mut index = vec![usize::MAX; pattern.n()];
    for (k, &dof) in layer.iter().enumerate() {
        index[dof] = k;
    }
    let (col_ptr, row_idx) = (pattern.symbolic().col_ptr(), pattern.symbolic().row_idx());
    let mut entries = Vec::new();
    for (c, &dof) in layer.iter().enumerate() {
        for position in col_ptr[dof]..col_ptr[dof + 1] {
            let r = index[row_idx[position]];
            if r != usize::MAX {
                entries.push((r, c, position));
            }
        }
    }
    entries
}

/// A B, on one thread as every factorisation here (the result does not depend on the
/// number of threads).
fn product(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let mut c = Mat::zeros(a.nrows(), b.ncols());
    matmul(c.as_mut(), Accum::Replace, a, b, 1.0, PARALLELISM);
    c
}

/// The factors of one Jacobian: P S = L U, the LU of its Schur complement S on the layer (L
/// unit lower and U in one matrix), with the row permutation P and its inverse.
pub struct SchurFactors<'a> {
    schur: &'a LayerSchur,
    lu: Mat<f64>,
    rows: Vec<usize>,
    inverse: Vec<usize>,
}

impl SchurFactors<'_> {
    /// Solves J x = b: w = L⁻¹ P b, w_L ← L_LLᵀ S⁻¹ L_LL w_L, x = Pᵀ L⁻ᵀ w.
    pub fn solve(&self, b: &[f64]) -> Result<Vec<f64>, SolveError> {
        let schur = self.schur;
        let mut w = schur.cholesky.forward_substitute(&schur.factor, b)?;
        let first = b.len() - schur.layer.len();
        let m = schur.layer.len();
        let mut w_l = product(schur.l_ll.as_ref(), w.as_ref().subrows(first, m));
        let mut buffer = workspace(solve::solve_in_place_scratch::<usize, f64>(m, 1, PARALLELISM))?;
        let perm = PermRef::new_checked(&self.rows, &self.inverse, m);
        let (lu, stack) = (self.lu.as_ref(), MemStack::new(&mut buffer));
        solve::solve_in_place_with_conj(lu, lu, perm, Conj::No, w_l.as_mut(), PARALLELISM, stack);
        w.as_mut().subrows_mut(first, m).copy_from(product(schur.l_ll.transpose(), w_l.as_ref()));
        schur.cholesky.back_substitute(&schur.factor, w)
    }
}
