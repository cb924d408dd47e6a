//! The vertex-patch problem of the stress reconstruction (docs/method.md §4).
//!
//! On the patch ω_a, find σ^a in broken P_p(T)^{2×2} minimising ‖σ^a − τ*‖_{ω_a} under the
//! linear constraints B σ^a = b:
//!
//! - normal-trace continuity on interior faces, ∫_F [[σ n_F]]·q = 0, q ∈ P_p(F)²;
//! - prescribed normal traces on the boundary faces through a, ∫_F σn·q = ∫_F t_F·q (none
//!   for the fixed components of Dirichlet faces);
//! - σn = 0 on the side of each cell opposite to a, where ψ_a = 0;
//! - divergence, (∇·σ, v)_T = (g, v)_T for v ∈ P_{p−1}(T)²;
//! - weak symmetry, (σ, m J)_T = (c, m J)_T for m ∈ P_{p−1}(T).
//!
//! The last three act on one cell each and are eliminated cell by cell (static
//! condensation, `Condensed`). In the L²(T)-orthonormal basis of each cell the cell's part
//! of the objective is |s − f|², so the elimination is an orthogonal projection: with N an
//! orthonormal basis of the coefficients that the local rows leave free, s₀ the point of the
//! local rows closest to f and Z the face rows through a (as columns),
//!
//!   s = s₀ − N Nᵀ Z λ,
//!
//! and only the multipliers λ of the face rows remain: (Σ_T Zᵀ N Nᵀ Z) λ = Σ_T Zᵀ s₀ − b_G.
//! The divergence and opposite-side rows act on each row of σ alone, with the same
//! coefficients in both rows, and only weak symmetry couples the rows, so N comes from two
//! Householder factorisations per cell, one for one row of σ and one for the symmetry rows;
//! s₀ and Nᵀ Z are computed in the coordinates that they rotate to. One orthogonal
//! factorisation of the stacked Nᵀ Z serves every right-hand side (total, regularisation,
//! linearisation); see [`solve`] for why not the normal equations.
//!
//! Rigid motions z that the patch leaves free make the rows dependent: Bᵀλ_z = 0 for the
//! multipliers λ_z = (z on the faces, −Π^{p−1}z for the divergence, b for the symmetry) of
//! z = a + b(−y, x). The data are first made compatible, λ_zᵀ b = 0 (condition (C)), and the
//! condensed matrix is made definite by adding s K Kᵀ (rows √s Kᵀ below the stacked Nᵀ Z),
//! K the face part of the λ_z, which leaves the solution of compatible systems unchanged.

use super::afw::{CellIntegrals, COMPONENTS};
use nalgebra::{DMatrix, DVector};

/// What a face of the patch imposes.
pub enum FaceKind {
    /// Shared by two cells of the patch: continuity of σn.
    Interior,
    /// A boundary face through a: σn·e_i = data for the components i with `active[i]`;
    /// `data[case][m · 2 + i]` holds ∫_F t_i q_m for each right-hand side.
    Trace { active: [bool; 2], data: Vec<Vec<f64>> },
    /// The side of a cell opposite to a: σn = 0.
    Opposite,
}

/// A face of a patch.
pub struct PatchFace {
    /// Local cell indices (the second only for interior faces).
    pub cells: [usize; 2],
    /// ∫_F φ_k q_m of each side per unit length, from [`super::afw::edge_moments`].
    pub moments: [&'static [f64]; 2],
    /// |F|.
    pub length: f64,
    /// Unit normal, outward of the first cell.
    pub normal: [f64; 2],
    /// Physical positions of the face nodes: ends, then midpoint (a node for p = 2 only).
    pub nodes: [[f64; 2]; 3],
    pub kind: FaceKind,
}

impl PatchFace {
    /// The components i of its rows: both, or the active ones of a trace.
    fn active(&self) -> [bool; 2] {
        match &self.kind {
            FaceKind::Trace { active, .. } => *active,
            _ => [true; 2],
        }
    }
}

/// Data of one patch problem with `cases` right-hand sides.
pub struct PatchInput<'a> {
    pub order: usize,
    pub n_basis: usize,
    pub n_lower: usize,
    pub cells: Vec<&'a CellIntegrals>,
    pub faces: Vec<PatchFace>,
    /// (τ*, φ_k E_c)_T per case, cell-major: `[case][cell · 4 n_basis + c · n_basis + k]`.
    pub target: Vec<Vec<f64>>,
    /// (g, ψ_m e_i)_T per case: `[case][(cell · n_lower + m) · 2 + i]`.
    pub divergence: Vec<Vec<f64>>,
    /// Physical positions of the P_{p−1} nodes (for Π^{p−1} z), cell by cell: n_lower per cell.
    pub lower_nodes: Vec<[f64; 2]>,
    /// Rigid motions left free by the patch's Dirichlet faces, as coefficient triples
    /// (a_x, a_y, b) of z(x) = (a_x − b y, a_y + b x), y and x relative to `origin`.
    pub rigid: Vec<[f64; 3]>,
    pub origin: [f64; 2],
    /// Total area |ω_a|.
    pub area: f64,
    /// For p = 1: correct the symmetry datum of case 0 (the total) by c = κ J so that the
    /// rotations satisfy the compatibility condition (docs/method.md §4.2).
    pub rotation_correction: bool,
}

/// Reconstructed coefficients per case and the compatibility residual of case 0.
pub struct PatchSolution {
    pub sigma: Vec<Vec<f64>>,
    /// max_z |defect of (C) for z| after the p = 1 correction, and the largest sum of the
    /// absolute values of its terms (its scale).
    pub compatibility: (f64, f64),
}

impl PatchInput<'_> {
    /// Coefficients per cell, 4 n_basis.
    fn width(&self) -> usize {
        COMPONENTS * self.n_basis
    }

    fn rigid_motion(&self, z: &[f64; 3], x: [f64; 2]) -> [f64; 2] {
        let (px, py) = (x[0] - self.origin[0], x[1] - self.origin[1]);
        [z[0] - z[2] * py, z[1] + z[2] * px]
    }
}

/// A face row ∫_F (σn)_i q_m through a, with its right-hand side per case.
struct FaceRow {
    face: usize,
    m: usize,
    i: usize,
    /// One entry per case (at most [`MAX_CASES`]).
    rhs: [f64; MAX_CASES],
}

/// Most right-hand sides of a patch problem: the total, the regularisation and the
/// linearisation.
const MAX_CASES: usize = 3;

/// Scratch matrices of one thread, reused from patch to patch: a matrix is reallocated only
/// when its shape changes, so the condensation of the many cells with the usual shapes does
/// not allocate.
pub struct Workspace {
    cells: Vec<Condensed>,
    stacked: Stacked,
    reduced: DMatrix<f64>,
}

impl Default for Workspace {
    fn default() -> Self {
        Workspace { cells: Vec::new(), stacked: Stacked::default(), reduced: empty() }
    }
}

fn empty() -> DMatrix<f64> {
    DMatrix::zeros(0, 0)
}

/// `m` with the shape rows × cols, reallocated only if its shape differs (most cells of a
/// mesh give the same shapes); its entries are then arbitrary.
fn shaped(m: &mut DMatrix<f64>, rows: usize, cols: usize) -> &mut DMatrix<f64> {
    if m.shape() != (rows, cols) {
        *m = DMatrix::zeros(rows, cols);
    }
    m
}

/// [`shaped`], zeroed.
fn zeroed(m: &mut DMatrix<f64>, rows: usize, cols: usize) -> &mut DMatrix<f64> {
    shaped(m, rows, cols).fill(0.0);
    m
}

/// Solves the patch problem for every case; fails only if the constraints are dependent
/// beyond the free rigid motions.
///
/// With A = Nᵀ Z stacked over the cells, N the orthonormal basis of each cell's free
/// coefficients (`Condensed`), and √s Kᵀ below it on patches with free rigid motions, the
/// correction x = A λ of the free coordinates is the least-norm solution of Aᵀ x = r,
/// r = Σ_T Zᵀ s₀ − b_G. It is taken from A = Q R as x = Q R⁻ᵀ r, never through λ (Q is
/// applied by its reflectors): the normal equations AᵀA λ = r square the condition of A,
/// which grows like the square of the aspect ratio of the cells, and their Cholesky
/// factorisation leaves a residual of ε κ(A) |A| |x| in the constraints (10⁻⁹ at aspect
/// 100), where the QR factorisation leaves ε |A| |x|.
pub fn solve(input: &PatchInput, work: &mut Workspace) -> Result<PatchSolution, String> {
    let cases = input.target.len();
    let rows = face_rows(input);
    let data = compatible_data(input, &rows);
    let width = input.width();
    let Workspace { cells, stacked, reduced } = work;
    cells.resize_with(cells.len().max(input.cells.len()), Condensed::default);
    let cells = &mut cells[..input.cells.len()];
    let kernel = rigid_kernel(input, &rows);
    zeroed(reduced, rows.len(), cases);
    let mut norm_squared = 0.0;
    for (t, cell) in cells.iter_mut().enumerate() {
        cell.condense(input, t, &rows, &data)?;
        norm_squared += cell.free_rows().map(|row| dot(row, row)).sum::<f64>();
        for (a, &r) in cell.rows.iter().enumerate() {
            for case in 0..cases {
                reduced[(r, case)] += cell.trace[(a, case)];
            }
        }
    }
    for (r, row) in rows.iter().enumerate() {
        for case in 0..cases {
            reduced[(r, case)] -= row.rhs[case];
        }
    }
    // A = [Nᵀ Z of every cell], with √s Kᵀ below, s = tr AᵀA / tr KᵀK
    let scale = (kernel.ncols() > 0).then(|| (norm_squared / kernel.norm_squared()).sqrt());
    stacked.stack(cells, kernel.transpose() * scale.unwrap_or(0.0), rows.len());
    stacked.factor()?;
    let mut y = vec![0.0; stacked.n_rows];
    let mut sigma = vec![vec![0.0; cells.len() * width]; cases];
    let mut s = [0.0; MAX_WIDTH];
    for (case, out) in sigma.iter_mut().enumerate() {
        y.fill(0.0);
        y[..rows.len()].copy_from_slice(column(reduced, case));
        stacked.least_norm(&mut y);
        let mut offset = 0;
        for (t, cell) in cells.iter().enumerate() {
            let s = &mut s[..width];
            s.copy_from_slice(column(&cell.s0, case));
            let free = cell.n_free();
            s[width - free..].iter_mut().zip(&y[offset..offset + free]).for_each(|(s, x)| *s -= x);
            offset += free;
            let block = &mut out[t * width..(t + 1) * width];
            cell.coefficients(s, block);
            for part in block.chunks_exact_mut(input.n_basis) {
                from_orthonormal(&input.cells[t].orthonormal, part);
            }
        }
    }
    Ok(PatchSolution { sigma, compatibility: data.defect })
}

/// The stacked blocks Nᵀ Z of the cells (each on the columns of its face rows) and the
/// rows √s Kᵀ, factored in place as Q R.
#[derive(Default)]
pub struct Stacked {
    factors: Factors,
    n_rows: usize,
}

impl Stacked {
    fn stack(&mut self, cells: &[Condensed], kernel_rows: DMatrix<f64>, n_cols: usize) {
        self.n_rows = cells.iter().map(Condensed::n_free).sum::<usize>() + kernel_rows.nrows();
        let n_rows = self.n_rows;
        let a = self.factors.matrix(n_rows, n_cols);
        let mut offset = 0;
        for cell in cells {
            for (&r, block) in cell.rows.iter().zip(cell.free_rows()) {
                a[r * n_rows + offset..][..block.len()].copy_from_slice(block);
            }
            offset += cell.n_free();
        }
        for j in 0..n_cols {
            for i in 0..kernel_rows.nrows() {
                a[j * n_rows + offset + i] = kernel_rows[(i, j)];
            }
        }
    }

    /// Q R of the stacked rows; fails if there are fewer rows than columns or R has a
    /// diagonal entry below [`DEPENDENT`] times the largest.
    fn factor(&mut self) -> Result<(), String> {
        match self.factors.factor(DEPENDENT) {
            true => Ok(()),
            false => Err("the patch constraints are not independent".into()),
        }
    }

    /// y ← Q R⁻ᵀ y (y holds r in its first n_cols entries): the least-norm x with Aᵀx = r.
    fn least_norm(&self, y: &mut [f64]) {
        self.factors.solve_transpose(&mut y[..self.factors.n()]);
        self.factors.apply(y);
    }
}

/// Below this, a diagonal entry of R relative to the largest marks dependent constraints.
const DEPENDENT: f64 = 1e-14;

/// The face rows through a (interior faces and boundary traces).
fn face_rows(input: &PatchInput) -> Vec<FaceRow> {
    let cases = input.target.len();
    let mut rows = Vec::new();
    for (f, face) in input.faces.iter().enumerate() {
        if matches!(face.kind, FaceKind::Opposite) {
            continue;
        }
        let active = face.active();
        for m in 0..=input.order {
            for i in (0..2).filter(|&i| active[i]) {
                let rhs = std::array::from_fn(|case| match &face.kind {
                    FaceKind::Trace { data, .. } if case < cases => data[case][m * 2 + i],
                    _ => 0.0,
                });
                rows.push(FaceRow { face: f, m, i, rhs });
            }
        }
    }
    rows
}

/// Writes the coefficients of the face row (m, i) of `face` on its side `side` into `out`,
/// over the 2 n_basis coefficients of row i of τ (the same for both i):
/// ± ∫_F (τ n)_i q_m = ± Σ_{k,j} τ_{ij,k} n_j ∫_F φ_k q_m (both sides use the first cell's
/// normal, the second with a minus sign).
fn face_coefficients(nb: usize, face: &PatchFace, side: usize, m: usize, out: &mut [f64]) {
    let sign = if side == 0 { 1.0 } else { -1.0 };
    for k in 0..nb {
        let moment = sign * (face.moments[side][m * nb + k] * face.length);
        for j in 0..2 {
            out[j * nb + k] = moment * face.normal[j];
        }
    }
}

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
struct Condensed {
    /// Indices of the face rows that touch the cell, the row of σ each acts on and the
    /// side of its face the cell is on.
    rows: Vec<usize>,
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
    trace: DMatrix<f64>,
    s0: DMatrix<f64>,
}

impl Condensed {
    /// Static condensation of cell t of the patch.
    fn condense(
        &mut self,
        input: &PatchInput,
        t: usize,
        rows: &[FaceRow],
        data: &CompatibleData,
    ) -> Result<(), String> {
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
    fn n_free(&self) -> usize {
        self.z_hat.nrows() - self.w1.n() - self.ys.n()
    }

    /// The columns of Nᵀ Z, one per face row of the cell.
    fn free_rows(&self) -> impl Iterator<Item = &[f64]> {
        let (rows, free) = (self.z_hat.nrows(), self.n_free());
        self.z_hat.as_slice().chunks_exact(rows).map(move |z| &z[rows - free..])
    }

    /// `out` ← the orthonormal coefficients s of the rotated ŝ (`s_hat`, overwritten).
    fn coefficients(&self, s_hat: &mut [f64], out: &mut [f64]) {
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
    fn row_basis(&mut self, input: &PatchInput, t: usize) -> Result<(), String> {
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
            false => Err("the local constraints of a cell are not independent".into()),
        }
    }

    /// Y' = Q_S R_S for the weak-symmetry columns Y, (τ, ψ_m J)_T = (τ_xy − τ_yx, ψ_m)_T,
    /// rotated by Q₁ᵀ in both rows of σ: their heads go to `y_head`, their tails to Y'.
    fn symmetry_basis(&mut self, input: &PatchInput, t: usize) -> Result<(), String> {
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
            false => Err("the weak symmetry rows of a cell are not independent".into()),
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

/// Most coefficients of a cell, 4 n_basis for p ≤ 2.
const MAX_WIDTH: usize = 24;

/// Most basis functions n_basis of a cell, for p ≤ 2.
const MAX_BASIS: usize = 6;

/// Column j of `m`.
fn column(m: &DMatrix<f64>, j: usize) -> &[f64] {
    let rows = m.nrows();
    &m.as_slice()[j * rows..(j + 1) * rows]
}

/// Column j of `m`, mutable.
fn column_mut(m: &mut DMatrix<f64>, j: usize) -> &mut [f64] {
    let rows = m.nrows();
    &mut m.as_mut_slice()[j * rows..(j + 1) * rows]
}

/// a · b with four partial sums, so that the products of short columns run in parallel.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let mut sums = [0.0; 4];
    for (x, y) in a[..n].chunks_exact(4).zip(b[..n].chunks_exact(4)) {
        for l in 0..4 {
            sums[l] += x[l] * y[l];
        }
    }
    let tail = n - n % 4;
    let rest: f64 = a[tail..n].iter().zip(&b[tail..n]).map(|(x, y)| x * y).sum();
    (sums[0] + sums[2]) + (sums[1] + sums[3]) + rest
}

/// v ← C v for C lower triangular, row-major.
fn to_orthonormal(c: &[f64], v: &mut [f64]) {
    let n = v.len();
    for k in (0..n).rev() {
        v[k] = dot(&c[k * n..k * n + k + 1], &v[..=k]);
    }
}

/// v ← Cᵀ v for C lower triangular, row-major.
fn from_orthonormal(c: &[f64], v: &mut [f64]) {
    let n = v.len();
    for k in 0..n {
        v[k] = (k..n).map(|l| c[l * n + k] * v[l]).sum();
    }
}

/// Householder factors Q R of a column-major m × n matrix (m ≥ n) from [`householder_qr`],
/// kept between cells and patches so that the usual shapes do not allocate; Q is the square
/// product of the reflectors, never formed.
#[derive(Default)]
struct Factors {
    a: Vec<f64>,
    tau: Vec<f64>,
    m: usize,
}

impl Factors {
    /// The zeroed m × n matrix to factor.
    fn matrix(&mut self, m: usize, n: usize) -> &mut [f64] {
        self.m = m;
        self.tau.resize(n, 0.0);
        self.a.clear();
        self.a.resize(m * n, 0.0);
        &mut self.a
    }

    /// Number of columns n.
    fn n(&self) -> usize {
        self.tau.len()
    }

    /// Factors the matrix in place; false if m < n or a diagonal entry of R is at most
    /// `dependent` times the largest.
    fn factor(&mut self, dependent: f64) -> bool {
        let (m, n) = (self.m, self.n());
        if m < n {
            return false;
        }
        householder_qr(&mut self.a, m, n, &mut self.tau);
        let diagonal = |j: usize| self.a[j * m + j].abs();
        let largest = (0..n).map(diagonal).fold(0.0, f64::max);
        (0..n).all(|j| diagonal(j) > dependent * largest)
    }

    /// x ← Q x (x of length m).
    fn apply(&self, x: &mut [f64]) {
        householder_apply(&self.a, self.m, &self.tau, x);
    }

    /// x ← Qᵀ x = H_{n−1} ⋯ H_0 x (x of length m).
    fn apply_transpose(&self, x: &mut [f64]) {
        let m = self.m;
        for (j, &tau) in self.tau.iter().enumerate() {
            reflect(&self.a[j * m + j + 1..(j + 1) * m], tau, &mut x[j..]);
        }
    }

    /// c ← R⁻ᵀ c (c of length n).
    fn solve_transpose(&self, c: &mut [f64]) {
        let m = self.m;
        for i in 0..self.n() {
            let sum = dot(&self.a[i * m..i * m + i], &c[..i]);
            c[i] = (c[i] - sum) / self.a[i * m + i];
        }
    }
}

/// Below this, a diagonal entry of R relative to the largest marks dependent local rows.
const DEPENDENT_LOCAL: f64 = 1e-13;

/// Householder QR of the column-major m × n matrix `a` (m ≥ n) in place: R in its upper
/// triangle, the reflectors H_j = I − τ_j v_j v_jᵀ (v_j = (0, …, 0, 1, v_j below the
/// diagonal)) under it, τ_j in `tau`. By hand because the patch matrices are small (12 × 6
/// per cell, 54 × 36 on an interior P2 patch of six cells): reflectors applied to the few vectors
/// replace nalgebra's QR with the explicit Q it needs and its allocations (docs/results.md,
/// Error estimation).
fn householder_qr(a: &mut [f64], m: usize, n: usize, tau: &mut [f64]) {
    for j in 0..n {
        let column = &mut a[j * m..(j + 1) * m];
        let (alpha, below) = (column[j], &mut column[j + 1..]);
        let sigma = dot(below, below);
        if sigma == 0.0 {
            tau[j] = 0.0;
            continue;
        }
        let norm = (alpha * alpha + sigma).sqrt();
        let beta = if alpha > 0.0 { -norm } else { norm };
        let scale = 1.0 / (alpha - beta);
        below.iter_mut().for_each(|x| *x *= scale);
        column[j] = beta;
        tau[j] = (beta - alpha) / beta;
        let (left, right) = a.split_at_mut((j + 1) * m);
        for c in right.chunks_exact_mut(m) {
            reflect(&left[j * m + j + 1..], tau[j], &mut c[j..]);
        }
    }
}

/// x ← Q x = H_0 ⋯ H_{n−1} x for the factors of [`householder_qr`] (n = `tau.len()`).
fn householder_apply(a: &[f64], m: usize, tau: &[f64], x: &mut [f64]) {
    for j in (0..tau.len()).rev() {
        reflect(&a[j * m + j + 1..(j + 1) * m], tau[j], &mut x[j..]);
    }
}

/// x ← (I − τ v vᵀ) x for v = (1, `below`).
fn reflect(below: &[f64], tau: f64, x: &mut [f64]) {
    let s = tau * (x[0] + dot(below, &x[1..]));
    x[0] -= s;
    x[1..].iter_mut().zip(below).for_each(|(x, v)| *x -= s * v);
}

/// K = the face rows' part of λ_z for the free rigid motions z (z_i at the face nodes), one
/// column per motion.
fn rigid_kernel(input: &PatchInput, rows: &[FaceRow]) -> DMatrix<f64> {
    DMatrix::from_fn(rows.len(), input.rigid.len(), |r, j| {
        input.rigid_motion(&input.rigid[j], input.faces[rows[r].face].nodes[rows[r].m])[rows[r].i]
    })
}

/// Divergence and symmetry right-hand sides per case (layouts of [`PatchInput::divergence`]
/// and `[case][cell · n_lower + m]`), and the compatibility defect of the total with its scale.
struct CompatibleData {
    divergence: Vec<Vec<f64>>,
    symmetry: Vec<Vec<f64>>,
    defect: (f64, f64),
}

/// The divergence and symmetry data of every case, made compatible, and the remaining
/// compatibility defect of the total. The total (case 0) satisfies (C) by construction up
/// to the p = 1 rotations, cancelled by c = κ J; the other cases get a rigid-motion term
/// Π^{p−1} r_i in their divergence data, r_i the rigid motion that restores (C)
/// (docs/method.md §4.3), and a κ J term along the motions with Π^{p−1} z = 0.
fn compatible_data(input: &PatchInput, rows: &[FaceRow]) -> CompatibleData {
    let cases = input.target.len();
    let mut divergence = input.divergence.clone();
    let mut symmetry = vec![vec![0.0; input.cells.len() * input.n_lower]; cases];
    if input.rigid.is_empty() {
        return CompatibleData { divergence, symmetry, defect: (0.0, 0.0) };
    }
    let coefficients = lower_coefficients(input);
    let projections = rigid_projections(input, &coefficients);
    let gram = projections.transpose() * &coefficients;
    let eigen = gram.symmetric_eigen();
    let largest = eigen.eigenvalues.amax();
    let (seen, unseen): (Vec<usize>, Vec<usize>) =
        (0..input.rigid.len()).partition(|&j| eigen.eigenvalues[j] > 1e-10 * largest);
    let unseen: Vec<Vec<f64>> =
        unseen.iter().map(|&j| eigen.eigenvectors.column(j).iter().copied().collect()).collect();
    let all: Vec<Vec<f64>> =
        (0..input.rigid.len()).map(|k| (0..input.rigid.len()).map(|j| f64::from(j == k)).collect()).collect();
    let mut total = (0.0, 0.0);
    for case in 0..cases {
        let d = defects(input, rows, case, &divergence[case], &coefficients);
        let directions = if case == 0 { &all } else { &unseen };
        let kappa = if input.rotation_correction { rotation_kappa(input, &d, directions) } else { None };
        if let Some(kappa) = kappa {
            correct_symmetry(input, kappa, &mut symmetry[case]);
        }
        let kappa = kappa.unwrap_or(0.0);
        let remaining: Vec<f64> =
            input.rigid.iter().zip(&d).map(|(z, d)| d.0 + 2.0 * z[2] * kappa * input.area).collect();
        if case == 0 {
            total = (remaining.iter().fold(0.0_f64, |m, r| m.max(r.abs())), d.iter().map(|d| d.1).fold(0.0, f64::max));
        }
        // r = Σ_j c_j z_j with (Π^{p−1} z_k, Π^{p−1} r) = remaining_k on the seen motions
        let remaining = DVector::from_vec(remaining);
        let mut c = DVector::zeros(input.rigid.len());
        for &j in &seen {
            let v = eigen.eigenvectors.column(j);
            c += v * (v.dot(&remaining) / eigen.eigenvalues[j]);
        }
        for (value, shift) in divergence[case].iter_mut().zip((&projections * c).iter()) {
            *value += shift;
        }
    }
    CompatibleData { divergence, symmetry, defect: total }
}

/// (ψ_m e_i, z)_T = Σ_l (ψ_m, ψ_l)_T z_i(x_l) for every divergence row (t, m, i) and free
/// rigid motion z, from the `values` z_i(x_l) of [`lower_coefficients`].
fn rigid_projections(input: &PatchInput, values: &DMatrix<f64>) -> DMatrix<f64> {
    let nl = input.n_lower;
    let mut out = DMatrix::zeros(values.nrows(), values.ncols());
    for (j, z) in values.column_iter().enumerate() {
        for (t, cell) in input.cells.iter().enumerate() {
            let z = &z.as_slice()[t * 2 * nl..(t + 1) * 2 * nl];
            for m in 0..nl {
                let gram = &cell.lower_gram[m * nl..(m + 1) * nl];
                for i in 0..2 {
                    out[((t * nl + m) * 2 + i, j)] = (0..nl).map(|l| gram[l] * z[l * 2 + i]).sum();
                }
            }
        }
    }
    out
}

/// The coefficients z_i(x_m) of Π^{p−1} z for every divergence row (t, m, i) and free z.
fn lower_coefficients(input: &PatchInput) -> DMatrix<f64> {
    let rows = input.cells.len() * input.n_lower * 2;
    let mut out = DMatrix::zeros(rows, input.rigid.len());
    for (j, z) in input.rigid.iter().enumerate() {
        let column = column_mut(&mut out, j);
        for (values, &x) in column.chunks_exact_mut(2).zip(&input.lower_nodes) {
            values.copy_from_slice(&input.rigid_motion(z, x));
        }
    }
    out
}

/// Defect of the compatibility condition (C) of one case for each free rigid motion z:
/// Σ_F (t_F, z)_F − (Π^{p−1} g, z)_{ω_a} (with c = 0), and the sum of its absolute terms;
/// `coefficients` are those of [`lower_coefficients`].
fn defects(
    input: &PatchInput,
    rows: &[FaceRow],
    case: usize,
    divergence: &[f64],
    coefficients: &DMatrix<f64>,
) -> Vec<(f64, f64)> {
    (0..input.rigid.len())
        .map(|j| {
            let z = &input.rigid[j];
            let face_terms =
                rows.iter().map(|row| row.rhs[case] * input.rigid_motion(z, input.faces[row.face].nodes[row.m])[row.i]);
            let column = coefficients.column(j);
            let volume_terms = divergence.iter().zip(column.iter()).map(|(g, z)| -g * z);
            face_terms.chain(volume_terms).fold((0.0, 0.0), |(sum, scale), term| (sum + term, scale + term.abs()))
        })
        .collect()
}

/// κ of the symmetry datum c = κ J that cancels the defects d along the rigid-motion
/// combinations `directions` (coefficients over `input.rigid`): (c, ∇z) = −2bκ|ω_a| for
/// z = a + b(−y, x), least squares over the directions. None if they hold no rotation:
/// Σ b² |ω_a| is then round-off (the directions are orthonormal in units of the patch
/// size), and dividing by it would turn the round-off defect of a translation into a
/// spurious skew datum (roller patches, where only a translation is free).
fn rotation_kappa(input: &PatchInput, d: &[(f64, f64)], directions: &[Vec<f64>]) -> Option<f64> {
    let combine = |c: &Vec<f64>, f: &dyn Fn(usize) -> f64| c.iter().enumerate().map(|(k, ck)| ck * f(k)).sum::<f64>();
    let (mut num, mut den) = (0.0, 0.0);
    for c in directions {
        let (dn, bn) = (combine(c, &|k| d[k].0), combine(c, &|k| input.rigid[k][2]));
        num += dn * bn;
        den += bn * bn;
    }
    (den * input.area > ROTATION_TOLERANCE).then(|| -num / (2.0 * input.area * den))
}

/// Below this, Σ b² |ω_a| of the free rigid motions is round-off of a rotation-free kernel.
const ROTATION_TOLERANCE: f64 = 1e-12;

/// Adds (κ J, m J)_T = 2κ ∫_T ψ_m to the symmetry right-hand side.
fn correct_symmetry(input: &PatchInput, kappa: f64, sym_rhs: &mut [f64]) {
    let (nb, nl) = (input.n_basis, input.n_lower);
    for (t, cell) in input.cells.iter().enumerate() {
        for m in 0..nl {
            // ∫ ψ_m = Σ_k ∫ φ_k ψ_m since Σ_k φ_k = 1
            let integral: f64 = (0..nb).map(|k| cell.lower_mass[m * nb + k]).sum();
            sym_rhs[t * nl + m] += 2.0 * kappa * integral;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Householder factors of a 7 × 3 matrix W.
    fn factors(w: &DMatrix<f64>) -> Factors {
        let mut factors = Factors::default();
        factors.matrix(w.nrows(), w.ncols()).copy_from_slice(w.as_slice());
        assert!(factors.factor(DEPENDENT_LOCAL), "independent columns");
        factors
    }

    /// Source: `Factors` (Householder QR with the reflectors kept). Goal: Q is orthogonal,
    /// W = Q R, and `apply_transpose`, `solve_transpose` give Qᵀ x and R⁻ᵀ b. Parameters: a
    /// fixed 7 × 3 matrix with a dominant diagonal, x and b fixed.
    #[test]
    fn factors_apply_an_orthogonal_q_with_w_equal_q_r() {
        let w = DMatrix::from_fn(7, 3, |i, j| ((i * 5 + j * 3) % 7) as f64 - 2.5 + if i == j { 4.0 } else { 0.0 });
        let f = factors(&w);
        let q = DMatrix::from_fn(7, 7, |i, j| {
            let mut e = [0.0; 7];
            e[j] = 1.0;
            f.apply(&mut e);
            e[i]
        });
        assert!((q.transpose() * &q - DMatrix::identity(7, 7)).amax() < 1e-14, "QᵀQ = I");
        let r = DMatrix::from_fn(7, 3, |i, j| if i <= j { f.a[j * 7 + i] } else { 0.0 });
        assert!((&q * &r - &w).amax() < 1e-13 * w.amax(), "W = Q R");
        let mut x: Vec<f64> = (0..7).map(|i| i as f64 - 3.0).collect();
        let x0 = x.clone();
        f.apply_transpose(&mut x);
        assert!((DVector::from_vec(x.clone()) - q.transpose() * DVector::from_vec(x0)).amax() < 1e-14, "Qᵀ x");
        // Rᵀ c = b
        let b = [1.0, -2.0, 0.5];
        let mut c = b;
        f.solve_transpose(&mut c);
        let rt = r.rows(0, 3).transpose();
        assert!((rt * DVector::from_row_slice(&c) - DVector::from_row_slice(&b)).amax() < 1e-14, "Rᵀ c = b");
    }

    /// Source: `Factors::factor`. Goal: dependent columns, and fewer rows than columns, are
    /// refused. Parameters: a 5 × 2 matrix with equal columns; a 2 × 3 matrix of ones.
    #[test]
    fn factors_refuse_dependent_columns() {
        let mut f = Factors::default();
        f.matrix(5, 2).iter_mut().enumerate().for_each(|(k, a)| *a = (k % 5) as f64 + 1.0);
        assert!(!f.factor(DEPENDENT_LOCAL));
        f.matrix(2, 3).fill(1.0);
        assert!(!f.factor(DEPENDENT_LOCAL), "fewer rows than columns");
    }

    #[test]
    fn orthonormal_coordinates_match_the_triangular_products() {
        let c = [2.0, 0.0, 0.0, -1.0, 3.0, 0.0, 0.5, 0.25, 1.5]; // lower triangular, row-major
        let matrix = DMatrix::from_row_slice(3, 3, &c);
        let v = [1.0, -2.0, 0.5];
        let (mut to, mut from) = (v, v);
        to_orthonormal(&c, &mut to);
        from_orthonormal(&c, &mut from);
        let vector = DVector::from_row_slice(&v);
        assert!((DVector::from_row_slice(&to) - &matrix * &vector).amax() < 1e-15, "C v");
        assert!((DVector::from_row_slice(&from) - matrix.transpose() * &vector).amax() < 1e-15, "Cᵀ v");
    }
}
