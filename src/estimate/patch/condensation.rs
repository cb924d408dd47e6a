//! Static condensation of a cell's local rows (divergence, opposite side, weak symmetry) in
//! its orthonormal basis.

use super::algebra::{column, column_mut, dot, to_orthonormal, Factors, DEPENDENT_LOCAL, MAX_BASIS, MAX_WIDTH};
use super::compatibility::CompatibleData;
use super::{face_coefficients, shaped, FaceKind, FaceRow, PatchError, PatchInput};
use nalgebra::DMatrix;

/// One cell after static condensation of its local rows (divergence, weak symmetry, σn = 0
/// on the side opposite to a).
///
/// Coefficients are taken in the L²(T)-orthonormal basis χ = C φ of
/// [`CellIntegrals::orthonormal`], component by component: σ = Cᵀs, a row b of the
/// constraints becomes C b, the target becomes f = C (τ*, φ), and the cell's part of the
/// objective is |s − f|². The divergence and opposite-side rows act on one row s_i of σ at a
/// time, with the same coefficients W₁ for both rows; only weak symmetry (columns Y) couples
/// them. Two Householder factorisations, W₁ = Q₁ R₁ and Y' = Q_S R_S with Y' the part of Y
/// in N₁ ⊕ N₁ (N₁ the last columns of the square Q₁), rotate the coefficients to
///
///   ŝ = ((Q₁ᵀ s_0)_head, (Q₁ᵀ s_1)_head, Q_Sᵀ ((Q₁ᵀ s_0)_tail, (Q₁ᵀ s_1)_tail)),
///
/// where the local rows fix the first 2 n₁ + n_lower entries, (Q₁ᵀ s_i)_head = R₁⁻ᵀ b₁ and
/// (Q_Sᵀ u)_head = R_S⁻ᵀ (b_S − Y_headᵀ (Q₁ᵀ s)_head), and leave the last ones free: they are
/// Nᵀ s for N the orthonormal basis of the cell's free coefficients. The closest point s₀ to
/// f has the free coordinates Nᵀ f, and the face rows Z through a act on the free
/// coordinates by Nᵀ Z: s = s₀ − N Nᵀ Z λ. The cell adds the rows Nᵀ Z to the stacked matrix
/// and Zᵀ s₀ to its right-hand side. Every coefficient is computed from ŝ by the reflectors,
/// so the local rows hold to ε |s| whatever the correction (no projector is applied).
#[derive(Default)]
pub(super) struct Condensed {
    /// Indices of the face rows that touch the cell, the row of σ each acts on and the
    /// side of its face the cell is on.
    pub(super) rows: Vec<usize>,
    rows_of_sigma: Vec<usize>,
    sides: Vec<usize>,
    /// W₁ = Q₁ R₁ (2 n_basis × n₁).
    w1: Factors,
    /// Y' = Q_S R_S (2 (2 n_basis − n₁) × n_lower) and the head parts of (Q₁ ⊕ Q₁)ᵀ Y
    /// (2 n₁ × n_lower).
    ys: Factors,
    y_head: DMatrix<f64>,
    /// The face rows in the orthonormal basis on their row of σ (2 n_basis × rows), and
    /// rotated as ŝ but on their row only: (Q₁ᵀ z)_head, then Q_Sᵀ of the tail
    /// ((n₁ + 2 (2 n_basis − n₁)) × rows; Nᵀ Z is its last rows).
    z: DMatrix<f64>,
    z_hat: DMatrix<f64>,
    /// Zᵀ s₀, with ŝ₀ per case (4 n_basis × cases).
    pub(super) trace: DMatrix<f64>,
    pub(super) s0: DMatrix<f64>,
}

impl Condensed {
    /// Static condensation of cell t of the patch.
    pub(super) fn condense(
        &mut self,
        input: &PatchInput,
        t: usize,
        rows: &[FaceRow],
        data: &CompatibleData,
    ) -> Result<(), PatchError> {
        self.face_block(input, t, rows);
        self.row_basis(input, t)?;
        self.symmetry_basis(input, t)?;
        self.rotate_face_rows();
        self.local_solution(input, t, data);
        let (n1, cases) = (self.w1.n(), self.s0.ncols());
        let trace = shaped(&mut self.trace, self.rows.len(), cases);
        for (a, &i) in self.rows_of_sigma.iter().enumerate() {
            let z = column(&self.z_hat, a);
            for case in 0..cases {
                let s = column(&self.s0, case);
                trace[(a, case)] = dot(&z[..n1], &s[i * n1..(i + 1) * n1]) + dot(&z[n1..], &s[2 * n1..]);
            }
        }
        Ok(())
    }

    /// Number of free coordinates, 4 n_basis minus the local rows.
    pub(super) fn n_free(&self) -> usize {
        self.z_hat.nrows() - self.w1.n() - self.ys.n()
    }

    /// The columns of Nᵀ Z, one per face row of the cell.
    pub(super) fn free_rows(&self) -> impl Iterator<Item = &[f64]> {
        let (rows, free) = (self.z_hat.nrows(), self.n_free());
        self.z_hat.as_slice().chunks_exact(rows).map(move |z| &z[rows - free..])
    }

    /// `out` ← the orthonormal coefficients s of the rotated ŝ (`s_hat`, overwritten).
    pub(super) fn coefficients(&self, s_hat: &mut [f64], out: &mut [f64]) {
        let n1 = self.w1.n();
        let h = out.len() / 2;
        let free = h - n1;
        let (heads, tails) = s_hat.split_at_mut(2 * n1);
        self.ys.apply(tails);
        for (i, s) in out.chunks_exact_mut(h).enumerate() {
            s[..n1].copy_from_slice(&heads[i * n1..(i + 1) * n1]);
            s[n1..].copy_from_slice(&tails[i * free..(i + 1) * free]);
            self.w1.apply(s);
        }
    }

    /// W₁ = Q₁ R₁ for W₁ the divergence rows (∂_j τ_ij, ψ_m)_T and the rows ∫_F (τn)_i q_m
    /// of the opposite side, on one row i of σ.
    fn row_basis(&mut self, input: &PatchInput, t: usize) -> Result<(), PatchError> {
        let (nb, nl, q) = (input.n_basis, input.n_lower, input.order + 1);
        let h = 2 * nb;
        let cell = input.cells[t];
        let opposite = input.faces.iter().filter(|f| matches!(f.kind, FaceKind::Opposite) && f.cells[0] == t);
        let w = self.w1.matrix(h, nl + opposite.clone().count() * q);
        for m in 0..nl {
            for j in 0..2 {
                for k in 0..nb {
                    w[m * h + j * nb + k] = cell.divergence[(m * nb + k) * 2 + j];
                }
            }
        }
        for (f, face) in opposite.enumerate() {
            for m in 0..q {
                face_coefficients(nb, face, 0, m, &mut w[(nl + f * q + m) * h..][..h]);
            }
        }
        w.chunks_exact_mut(nb).for_each(|block| to_orthonormal(&cell.orthonormal, block));
        match self.w1.factor(DEPENDENT_LOCAL) {
            true => Ok(()),
            false => Err(PatchError::LocalRows),
        }
    }

    /// Y' = Q_S R_S for the weak-symmetry columns Y, (τ, ψ_m J)_T = (τ_xy − τ_yx, ψ_m)_T,
    /// rotated by Q₁ᵀ in both rows of σ: their heads go to `y_head`, their tails to Y'.
    fn symmetry_basis(&mut self, input: &PatchInput, t: usize) -> Result<(), PatchError> {
        let (nb, nl, h) = (input.n_basis, input.n_lower, 2 * input.n_basis);
        let n1 = self.w1.n();
        let free = h - n1;
        let cell = input.cells[t];
        let y_head = shaped(&mut self.y_head, 2 * n1, nl);
        let y_tail = self.ys.matrix(2 * free, nl);
        let mut skew = [0.0; MAX_BASIS];
        let skew = &mut skew[..nb];
        for m in 0..nl {
            // C ∫_T φ ψ_m in τ_xy (row 0), minus it in τ_yx (row 1)
            skew.copy_from_slice(&cell.lower_mass[m * nb..(m + 1) * nb]);
            to_orthonormal(&cell.orthonormal, skew);
            for i in 0..2 {
                let mut y = [0.0; MAX_WIDTH / 2];
                if i == 0 {
                    y[nb..h].copy_from_slice(skew);
                } else {
                    y[..nb].iter_mut().zip(skew.iter()).for_each(|(y, v)| *y = -v);
                }
                self.w1.apply_transpose(&mut y[..h]);
                column_mut(y_head, m)[i * n1..(i + 1) * n1].copy_from_slice(&y[..n1]);
                y_tail[m * 2 * free + i * free..][..free].copy_from_slice(&y[n1..h]);
            }
        }
        match self.ys.factor(DEPENDENT_LOCAL) {
            true => Ok(()),
            false => Err(PatchError::SymmetryRows),
        }
    }

    /// The face rows through a that touch cell t, on their row of σ and in orthonormal
    /// coordinates.
    fn face_block(&mut self, input: &PatchInput, t: usize, rows: &[FaceRow]) {
        self.rows.clear();
        self.rows_of_sigma.clear();
        self.sides.clear();
        for (r, row) in rows.iter().enumerate() {
            let face = &input.faces[row.face];
            if let Some(side) = face.cells.iter().position(|&cell| cell == t) {
                if side == 0 || matches!(face.kind, FaceKind::Interior) {
                    self.rows.push(r);
                    self.rows_of_sigma.push(row.i);
                    self.sides.push(side);
                }
            }
        }
        let (nb, h) = (input.n_basis, 2 * input.n_basis);
        let z = shaped(&mut self.z, h, self.rows.len()).as_mut_slice();
        for (a, &r) in self.rows.iter().enumerate() {
            let (face, m) = (rows[r].face, rows[r].m);
            if a > 0 && (rows[self.rows[a - 1]].face, rows[self.rows[a - 1]].m) == (face, m) {
                // the same moment on the other row of σ
                z.copy_within((a - 1) * h..a * h, a * h);
                continue;
            }
            let column = &mut z[a * h..(a + 1) * h];
            face_coefficients(nb, &input.faces[face], self.sides[a], m, column);
            column.chunks_exact_mut(nb).for_each(|block| to_orthonormal(&input.cells[t].orthonormal, block));
        }
    }

    /// ẑ of each face row z: (Q₁ᵀ z)_head, then Q_Sᵀ of its tail placed on its row of σ.
    /// The rows (m, x) and (m, y) of a face have the same z on their rows of σ: Q₁ᵀ z is
    /// taken once for both.
    fn rotate_face_rows(&mut self) {
        let (h, n1) = (self.z.nrows(), self.w1.n());
        let free = h - n1;
        let z_hat = shaped(&mut self.z_hat, n1 + 2 * free, self.rows.len());
        let mut w = [0.0; MAX_WIDTH / 2];
        let w = &mut w[..h];
        for (a, &i) in self.rows_of_sigma.iter().enumerate() {
            if a == 0 || column(&self.z, a) != column(&self.z, a - 1) {
                w.copy_from_slice(column(&self.z, a));
                self.w1.apply_transpose(w);
            }
            let (head, tail) = column_mut(z_hat, a).split_at_mut(n1);
            head.copy_from_slice(&w[..n1]);
            tail.fill(0.0);
            tail[i * free..(i + 1) * free].copy_from_slice(&w[n1..]);
            self.ys.apply_transpose(tail);
        }
    }

    /// ŝ₀ per case: f = C (τ*, φ) rotated, with the coordinates that the local rows fix
    /// replaced by theirs, (Q₁ᵀ s_i)_head = R₁⁻ᵀ b₁ and (Q_Sᵀ u)_head = R_S⁻ᵀ (b_S − Y_headᵀ
    /// (Q₁ᵀ s)_head).
    fn local_solution(&mut self, input: &PatchInput, t: usize, data: &CompatibleData) {
        let (nb, nl, cases) = (input.n_basis, input.n_lower, input.target.len());
        let (h, width) = (2 * nb, input.width());
        let n1 = self.w1.n();
        let free = h - n1;
        let cell = input.cells[t];
        let s0 = shaped(&mut self.s0, width, cases);
        let mut f = [0.0; MAX_WIDTH];
        let f = &mut f[..width];
        for case in 0..cases {
            f.copy_from_slice(&input.target[case][t * width..(t + 1) * width]);
            f.chunks_exact_mut(nb).for_each(|block| to_orthonormal(&cell.orthonormal, block));
            let (heads, tails) = column_mut(s0, case).split_at_mut(2 * n1);
            for (i, row) in f.chunks_exact_mut(h).enumerate() {
                self.w1.apply_transpose(row);
                let head = &mut heads[i * n1..(i + 1) * n1];
                head.fill(0.0);
                for (m, b) in head[..nl].iter_mut().enumerate() {
                    *b = data.divergence[case][(t * nl + m) * 2 + i];
                }
                self.w1.solve_transpose(head);
                tails[i * free..(i + 1) * free].copy_from_slice(&row[n1..]);
            }
            self.ys.apply_transpose(tails);
            for (m, b) in tails[..nl].iter_mut().enumerate() {
                *b = data.symmetry[case][t * nl + m] - dot(column(&self.y_head, m), heads);
            }
            self.ys.solve_transpose(&mut tails[..nl]);
        }
    }
}
