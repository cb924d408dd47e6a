//! Newton steps for a Jacobian J(x) = K + E C(x) Eᵀ: a constant symmetric positive definite
//! bulk K and a nonlinear part C(x) on a thin layer of m ≪ n dofs (E: the n × m selection of
//! the layer), such as the Nitsche terms of the cells along Γ_C, whose nonzero rows lie in a
//! subset R of the layer (for θ = 0, the dofs of the nodes on Γ_C: docs/solver.md §1).
//!
//! K is factorised once by sparse Cholesky with the layer L eliminated after the interior I,
//! and within the layer its part L₁ = L \ R before R: P K Pᵀ = L Lᵀ, whose trailing m × m
//! block L_LL = [L_11 0; L_21 L_22] (rows and columns L₁, R) gives the Schur complement of the
//! interior S₀ = K_LL − K_LI K_II⁻¹ K_IL = L_LL L_LLᵀ. The rows of J outside R are those of
//! K, so eliminating everything but R by K's factor leaves the Schur complement of J on R,
//!
//!   S_R = L_22 L_22ᵀ + C_RR − C_R1 X,   X = L_11⁻ᵀ L_21ᵀ (m₁ × |R|, once per mesh),
//!
//! with C_R1 the few nonzeros of C in rows R and columns L₁. Each step factors S_R, dense
//! |R| × |R|, by LU with partial pivoting (C is not symmetric for θ ≠ 1, nor with friction),
//! and solves J x = b by w = L⁻¹ P b, then on R
//!
//!   w_R ← L_22ᵀ S_R⁻¹ (L_22 w_R − C_R1 L_11⁻ᵀ w_1),
//!
//! with w_1 (on L₁) kept, and x = Pᵀ L⁻ᵀ w: one sparse forward and back substitution and dense
//! products of size m, the block elimination of J with the interior and L₁ eliminated first.
//! With R = L (θ ≠ 0) this is S = S₀ + C_LL on the whole layer. A step costs 2|R|³/3 flops for
//! the LU and 2|R| nnz(C_R1) for S_R; once per mesh X costs m₁²|R| flops. The dense matrices
//! take 8m² bytes: above [`MAX_LAYER`] layer dofs the caller keeps the sparse LU of the whole
//! Jacobian.

use super::cholesky::Cholesky;
use super::{workspace, SolveError, PARALLELISM};
use crate::fem::sparse::SparsePattern;
use faer::dyn_stack::MemStack;
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::solve_upper_triangular_in_place;
use faer::perm::PermRef;
use faer::{Accum, Conj, Mat, MatRef};

/// The largest layer factorised dense: each dense matrix of the layer takes up to 8m² bytes
/// (288 MB at 6 000 dofs), and with R = L one step's LU costs 2m³/3 = 1.4·10¹¹ flops.
pub const MAX_LAYER: usize = 6000;

/// K is taken as definite if every pivot keeps L_ii² ≥ 10⁻¹⁰ K_ii, which holds when κ₂(K) ≤
/// 10¹⁰. A body held only by its contact has a singular K, whose floating-point Cholesky may
/// still succeed with pivots at round-off: the sparse LU of J takes those.
const MIN_PIVOT_RATIO: f64 = 1e-10;

/// Outside the rows R, J − K may differ from 0 by round-off only (a basis function that
/// vanishes on a face, evaluated there): at most this fraction of max |C| on the rows R.
const ROUND_OFF: f64 = 1e-12;

/// An entry of the pattern inside the layer: layer row, layer column, position, value of K.
#[derive(Clone, Copy)]
struct Entry {
    row: usize,
    col: usize,
    position: usize,
    stiffness: f64,
}

/// K factorised once with the dense blocks of its trailing factor L_LL on the layer.
pub struct LayerSchur {
    cholesky: Cholesky,
    factor: Vec<f64>,
    /// The layer's dofs in the order of the dense matrices: L₁, then R.
    layer: Vec<usize>,
    /// m₁ = |L₁|.
    first_rows: usize,
    /// L_LL and Xᵀ = L_21 L_11⁻¹ (|R| × m₁: column c is row c of X).
    l_ll: Mat<f64>,
    x_transposed: Mat<f64>,
    /// L_22 L_22ᵀ − K_RR, to which a step adds J_RR.
    s0_minus_k: Mat<f64>,
    /// The entries in R × R, in R × L₁ (layer rows counted from the first row of R), and in
    /// the rows L₁, where C must vanish.
    block: Vec<Entry>,
    coupling: Vec<Entry>,
    outside: Vec<Entry>,
}

impl LayerSchur {
    /// Factorises K (`stiffness` on `pattern`) with the dofs `layer` eliminated last, those
    /// in `rows` (the rows where C may be nonzero) after the others. None if the layer is
    /// empty or has more than [`MAX_LAYER`] dofs, or if K is not positive definite or has a
    /// pivot below 10⁻¹⁰ K_ii (a body held only by its contact): Newton then factors J by
    /// sparse LU.
    pub fn new(pattern: &SparsePattern, stiffness: &[f64], layer: &[usize], rows: &[usize]) -> Option<Self> {
        let m = layer.len();
        if m == 0 || m > MAX_LAYER {
            return None;
        }
        let mut in_rows = vec![false; pattern.n()];
        for &dof in rows {
            in_rows[dof] = true;
        }
        let (mut layer, r): (Vec<usize>, Vec<usize>) = layer.iter().copied().partition(|&dof| !in_rows[dof]);
        let first_rows = layer.len();
        layer.extend(r);
        let cholesky = Cholesky::analyse_with_last(pattern, &layer).ok()?;
        let factor = cholesky.factor_values(pattern, stiffness).ok()?;
        if cholesky.pivot_ratio(&factor, pattern, stiffness)? < MIN_PIVOT_RATIO {
            return None;
        }
        let l_ll = cholesky.trailing_block(&factor, m)?;
        let (l_11, l_21, l_22) = blocks(l_ll.as_ref(), first_rows);
        let mut x = l_21.transpose().to_owned();
        solve_upper_triangular_in_place(l_11.transpose(), x.as_mut(), PARALLELISM);
        let mut s0_minus_k = product(l_22, l_22.transpose());
        let (mut block, mut coupling, mut outside) = (Vec::new(), Vec::new(), Vec::new());
        for entry in layer_entries(pattern, stiffness, &layer) {
            match (entry.row.checked_sub(first_rows), entry.col.checked_sub(first_rows)) {
                (Some(row), Some(col)) => {
                    s0_minus_k[(row, col)] -= entry.stiffness;
                    block.push(Entry { row, col, ..entry });
                }
                (Some(row), None) => coupling.push(Entry { row, ..entry }),
                (None, _) => outside.push(entry),
            }
        }
        let x_transposed = x.transpose().to_owned();
        Some(LayerSchur {
            cholesky,
            factor,
            layer,
            first_rows,
            l_ll,
            x_transposed,
            s0_minus_k,
            block,
            coupling,
            outside,
        })
    }

    /// Number of layer dofs m.
    pub fn layer_size(&self) -> usize {
        self.layer.len()
    }

    /// Number of layer dofs |R| on which the nonlinear part has rows: the order of the dense
    /// LU of each step.
    pub fn rows(&self) -> usize {
        self.layer.len() - self.first_rows
    }

    /// The dense LU of S_R = L_22 L_22ᵀ + C_RR − C_R1 X for the Jacobian values `jacobian` (on
    /// the pattern of K), C = J − K. An error if C is not round-off on the rows outside R.
    pub fn factor(&self, jacobian: &[f64]) -> Result<SchurFactors<'_>, SolveError> {
        let c = |e: &Entry| jacobian[e.position] - e.stiffness;
        let kept = self.block.iter().chain(&self.coupling).map(|e| c(e).abs()).fold(0.0, f64::max);
        let dropped = self.outside.iter().map(|e| c(e).abs()).fold(0.0, f64::max);
        if dropped > ROUND_OFF * kept {
            return Err(SolveError::Factorisation(format!(
                "the Jacobian differs from the stiffness by {dropped:.3e} outside the rows of its layer (max {kept:.3e} on them)"
            )));
        }
        let coupling: Vec<(usize, usize, f64)> =
            self.coupling.iter().map(|e| (e.row, e.col, c(e))).filter(|&(_, _, v)| v != 0.0).collect();
        // C_R1 X, transposed: column r is Σ_c C_rc (row c of X)
        let n_r = self.rows();
        let mut correction = Mat::<f64>::zeros(n_r, n_r);
        for &(r, col, v) in &coupling {
            let x_c = self.x_transposed.col_as_slice(col);
            for (y, x) in correction.col_as_slice_mut(r).iter_mut().zip(x_c) {
                *y += v * x;
            }
        }
        let mut lu = self.s0_minus_k.clone();
        for e in &self.block {
            lu[(e.row, e.col)] += jacobian[e.position];
        }
        lu -= correction.transpose();
        let (mut rows, mut inverse) = (vec![0usize; n_r], vec![0usize; n_r]);
        let mut buffer =
            workspace(factor::lu_in_place_scratch::<usize, f64>(n_r, n_r, PARALLELISM, Default::default()))?;
        let stack = MemStack::new(&mut buffer);
        factor::lu_in_place(lu.as_mut(), &mut rows, &mut inverse, PARALLELISM, stack, Default::default());
        Ok(SchurFactors { schur: self, coupling, lu, rows, inverse })
    }
}

/// L_11, L_21 and L_22 of L_LL split after its first m₁ rows and columns.
fn blocks(l_ll: MatRef<'_, f64>, m1: usize) -> (MatRef<'_, f64>, MatRef<'_, f64>, MatRef<'_, f64>) {
    let (l_11, _, l_21, l_22) = l_ll.split_at(m1, m1);
    (l_11, l_21, l_22)
}

/// The entries (r, c) of `pattern` with both dofs in `layer`, with r and c their indices in
/// the layer and the value of K there.
fn layer_entries(pattern: &SparsePattern, stiffness: &[f64], layer: &[usize]) -> Vec<Entry> {
    let mut index = vec![usize::MAX; pattern.n()];
    for (k, &dof) in layer.iter().enumerate() {
        index[dof] = k;
    }
    let (col_ptr, row_idx) = (pattern.symbolic().col_ptr(), pattern.symbolic().row_idx());
    let mut entries = Vec::new();
    for (col, &dof) in layer.iter().enumerate() {
        for position in col_ptr[dof]..col_ptr[dof + 1] {
            let row = index[row_idx[position]];
            if row != usize::MAX {
                entries.push(Entry { row, col, position, stiffness: stiffness[position] });
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

/// The factors of one Jacobian: P S_R = L U, the LU of its Schur complement on the rows R (L
/// unit lower and U in one matrix), with the row permutation P and its inverse, and the
/// nonzeros of C_R1 (row in R, column in L₁, value).
pub struct SchurFactors<'a> {
    schur: &'a LayerSchur,
    coupling: Vec<(usize, usize, f64)>,
    lu: Mat<f64>,
    rows: Vec<usize>,
    inverse: Vec<usize>,
}

impl SchurFactors<'_> {
    /// Solves J x = b: w = L⁻¹ P b, w_R ← L_22ᵀ S_R⁻¹ (L_22 w_R − C_R1 L_11⁻ᵀ w_1), x = Pᵀ L⁻ᵀ w.
    pub fn solve(&self, b: &[f64]) -> Result<Vec<f64>, SolveError> {
        let schur = self.schur;
        let mut w = schur.cholesky.forward_substitute(&schur.factor, b)?;
        let (m1, n_r) = (schur.first_rows, schur.rows());
        let first = b.len() - schur.layer.len();
        let (l_11, _, l_22) = blocks(schur.l_ll.as_ref(), m1);
        let mut y = w.as_ref().subrows(first, m1).to_owned();
        solve_upper_triangular_in_place(l_11.transpose(), y.as_mut(), PARALLELISM);
        let mut z = product(l_22, w.as_ref().subrows(first + m1, n_r));
        for &(r, c, v) in &self.coupling {
            z[(r, 0)] -= v * y[(c, 0)];
        }
        let mut buffer = workspace(solve::solve_in_place_scratch::<usize, f64>(n_r, 1, PARALLELISM))?;
        let perm = PermRef::new_checked(&self.rows, &self.inverse, n_r);
        let (lu, stack) = (self.lu.as_ref(), MemStack::new(&mut buffer));
        solve::solve_in_place_with_conj(lu, lu, perm, Conj::No, z.as_mut(), PARALLELISM, stack);
        w.as_mut().subrows_mut(first + m1, n_r).copy_from(product(l_22.transpose(), z.as_ref()));
        schur.cholesky.back_substitute(&schur.factor, w)
    }
}
