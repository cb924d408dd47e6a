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

mod algebra;
mod compatibility;
mod condensation;

use super::afw::{CellIntegrals, COMPONENTS};
use crate::geometry::{sub, Point, Vector, D};
use algebra::{column, dot, from_orthonormal, Factors, MAX_WIDTH};
use compatibility::{compatible_data, rigid_kernel};
use condensation::Condensed;
use nalgebra::DMatrix;

/// Why a patch problem has no solution: dependent constraints, which a patch of a mesh that
/// the scene's checks accept does not have.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum PatchError {
    #[error("the patch constraints are not independent")]
    FaceRows,
    #[error("the local constraints of a cell are not independent")]
    LocalRows,
    #[error("the weak symmetry rows of a cell are not independent")]
    SymmetryRows,
}

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
    pub normal: Vector,
    /// Physical positions of the face nodes: ends, then midpoint (a node for p = 2 only).
    pub nodes: [Point; 3],
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
    pub lower_nodes: Vec<Point>,
    /// Rigid motions left free by the patch's Dirichlet faces, as coefficient triples
    /// (a_x, a_y, b) of z(x) = (a_x − b y, a_y + b x), y and x relative to `origin`.
    pub rigid: Vec<[f64; 3]>,
    pub origin: Point,
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

    fn rigid_motion(&self, z: &[f64; 3], x: Point) -> Vector {
        let [px, py] = sub(x, self.origin);
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
pub fn solve(input: &PatchInput, work: &mut Workspace) -> Result<PatchSolution, PatchError> {
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
    fn factor(&mut self) -> Result<(), PatchError> {
        match self.factors.factor(DEPENDENT) {
            true => Ok(()),
            false => Err(PatchError::FaceRows),
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
            for i in (0..D).filter(|&i| active[i]) {
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
        for j in 0..D {
            out[j * nb + k] = moment * face.normal[j];
        }
    }
}
