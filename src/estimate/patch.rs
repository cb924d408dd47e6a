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
//! condensation): with the cell's local rows B_L, mass matrix M and A = B_L M⁻¹ B_Lᵀ,
//!
//!   P = M⁻¹ − M⁻¹ B_Lᵀ A⁻¹ B_L M⁻¹,   x₀ = τ̂ − M⁻¹ B_Lᵀ A⁻¹ (B_L τ̂ − b_L),   τ̂ = M⁻¹ (τ*, φ),
//!
//! and only the multipliers λ of the face rows through a remain:
//! (Σ_T B_G P B_Gᵀ) λ = Σ_T B_G x₀ − b_G, then σ = x₀ − P B_Gᵀ λ on each cell. One Cholesky
//! factorisation serves every right-hand side (total, regularisation, linearisation).
//!
//! Rigid motions z that the patch leaves free make the rows dependent: Bᵀλ_z = 0 for the
//! multipliers λ_z = (z on the faces, −Π^{p−1}z for the divergence, b for the symmetry) of
//! z = a + b(−y, x). The data are first made compatible, λ_zᵀ b = 0 (condition (C)), and the
//! condensed matrix is made definite by adding s K Kᵀ, K the face part of the λ_z, which
//! leaves the solution of compatible systems unchanged.

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
    /// ∫_F φ_k q_m of each side, from [`super::afw::face_moments`].
    pub moments: [Vec<f64>; 2],
    /// Unit normal, outward of the first cell.
    pub normal: [f64; 2],
    /// Physical positions of the P_p face nodes (ends, then midpoint).
    pub nodes: Vec<[f64; 2]>,
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
    /// Physical positions of the P_{p−1} nodes of each cell (for Π^{p−1} z).
    pub lower_nodes: Vec<Vec<[f64; 2]>>,
    /// Rigid motions left free by the patch's Dirichlet faces, as coefficient triples
    /// (a_x, a_y, b) of z(x) = (a_x − b y, a_y + b x), y and x relative to `origin`.
    pub rigid: Vec<[f64; 3]>,
    pub origin: [f64; 2],
    /// Total area |ω_a|.
    pub area: f64,
    /// For p = 1: correct the symmetry datum of case 0 (the total) by c = κ J so that the
    /// rotations satisfy the compatibility condition (docs/method.md §4.4).
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
    rhs: Vec<f64>,
}

/// Scratch matrices of one thread, reused from patch to patch: a matrix is reallocated only
/// when its shape changes, so the condensation of the many cells with the usual shapes does
/// not allocate.
pub struct Workspace {
    cells: Vec<Condensed>,
    schur: DMatrix<f64>,
    reduced: DMatrix<f64>,
}

impl Default for Workspace {
    fn default() -> Self {
        Workspace { cells: Vec::new(), schur: empty(), reduced: empty() }
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
pub fn solve(input: &PatchInput, work: &mut Workspace) -> Result<PatchSolution, String> {
    let cases = input.target.len();
    let rows = face_rows(input);
    let data = compatible_data(input, &rows);
    let Workspace { cells, schur, reduced } = work;
    cells.resize_with(cells.len().max(input.cells.len()), Condensed::default);
    let cells = &mut cells[..input.cells.len()];
    zeroed(schur, rows.len(), rows.len());
    zeroed(reduced, rows.len(), cases);
    for (t, cell) in cells.iter_mut().enumerate() {
        condense(input, t, &rows, &data, cell)?;
        for (a, &ra) in cell.rows.iter().enumerate() {
            for (b, &rb) in cell.rows.iter().enumerate() {
                schur[(ra, rb)] += cell.coupling[(a, b)];
            }
            for case in 0..cases {
                reduced[(ra, case)] += cell.trace[(a, case)];
            }
        }
    }
    for (r, row) in rows.iter().enumerate() {
        for case in 0..cases {
            reduced[(r, case)] -= row.rhs[case];
        }
    }
    add_rigid_kernel(input, &rows, schur);
    let cholesky = std::mem::replace(schur, empty()).cholesky().ok_or("the patch constraints are not independent")?;
    cholesky.solve_mut(reduced);
    *schur = cholesky.unpack_dirty();
    let lambda = &*reduced;
    let width = input.width();
    let sigma = (0..cases)
        .map(|case| {
            let mut out = vec![0.0; input.cells.len() * width];
            for (t, cell) in cells.iter().enumerate() {
                let s = &mut out[t * width..(t + 1) * width];
                s.copy_from_slice(cell.x0.column(case).as_slice());
                for (a, &r) in cell.rows.iter().enumerate() {
                    for (sk, pk) in s.iter_mut().zip(cell.p_bt.column(a).iter()) {
                        *sk -= pk * lambda[(r, case)];
                    }
                }
            }
            out
        })
        .collect();
    Ok(PatchSolution { sigma, compatibility: data.defect })
}

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
                let rhs = (0..cases)
                    .map(|case| match &face.kind {
                        FaceKind::Trace { data, .. } => data[case][m * 2 + i],
                        _ => 0.0,
                    })
                    .collect();
                rows.push(FaceRow { face: f, m, i, rhs });
            }
        }
    }
    rows
}

/// Writes the coefficients of the face row (m, i) of `face` on its side `side` into `out`:
/// ± ∫_F (τ n)_i q_m = ± Σ_{k,j} τ_{ij,k} n_j ∫_F φ_k q_m (both sides use the first cell's
/// normal, the second with a minus sign).
fn face_coefficients(input: &PatchInput, face: &PatchFace, side: usize, m: usize, i: usize, out: &mut [f64]) {
    let nb = input.n_basis;
    let sign = if side == 0 { 1.0 } else { -1.0 };
    out.fill(0.0);
    for k in 0..nb {
        let moment = sign * face.moments[side][m * nb + k];
        for j in 0..2 {
            out[(2 * i + j) * nb + k] = moment * face.normal[j];
        }
    }
}

/// One cell after static condensation of its local rows, with its scratch matrices.
struct Condensed {
    /// Indices of the face rows that touch the cell, and the side of their face it is on.
    rows: Vec<usize>,
    sides: Vec<usize>,
    /// P B_Gᵀ (width × rows).
    p_bt: DMatrix<f64>,
    /// B_G P B_Gᵀ.
    coupling: DMatrix<f64>,
    /// x₀ per case (width × cases) and B_G x₀.
    x0: DMatrix<f64>,
    trace: DMatrix<f64>,
    /// Scratch: B_L and b_L, B_Gᵀ, M⁻¹B_Lᵀ, A, V, V B_Gᵀ, F, L⁻¹ b_L − V F.
    b_local: DMatrix<f64>,
    b_rhs: DMatrix<f64>,
    b_global_t: DMatrix<f64>,
    minv_blt: DMatrix<f64>,
    gram: DMatrix<f64>,
    v: DMatrix<f64>,
    v_bgt: DMatrix<f64>,
    target: DMatrix<f64>,
    w: DMatrix<f64>,
}

impl Default for Condensed {
    fn default() -> Self {
        Condensed {
            rows: Vec::new(),
            sides: Vec::new(),
            p_bt: empty(),
            coupling: empty(),
            x0: empty(),
            trace: empty(),
            b_local: empty(),
            b_rhs: empty(),
            b_global_t: empty(),
            minv_blt: empty(),
            gram: empty(),
            v: empty(),
            v_bgt: empty(),
            target: empty(),
            w: empty(),
        }
    }
}

/// Local rows of cell t (divergence, symmetry, σn = 0 on the opposite side) into `b` and their
/// right-hand sides per case into `rhs`.
fn local_rows(input: &PatchInput, t: usize, data: &CompatibleData, b: &mut DMatrix<f64>, rhs: &mut DMatrix<f64>) {
    let (nb, nl, width, cases) = (input.n_basis, input.n_lower, input.width(), input.target.len());
    let cell = input.cells[t];
    let opposite = input.faces.iter().filter(|f| matches!(f.kind, FaceKind::Opposite) && f.cells[0] == t);
    let n_rows = 3 * nl + opposite.clone().count() * 2 * (input.order + 1);
    zeroed(b, n_rows, width);
    zeroed(rhs, n_rows, cases);
    for m in 0..nl {
        for i in 0..2 {
            let r = m * 2 + i;
            for k in 0..nb {
                for j in 0..2 {
                    b[(r, (2 * i + j) * nb + k)] = cell.divergence[(m * nb + k) * 2 + j];
                    // (∂_j τ_ij, ψ_m)_T
                }
            }
            for case in 0..cases {
                rhs[(r, case)] = data.divergence[case][(t * nl + m) * 2 + i];
            }
        }
        let r = 2 * nl + m;
        for k in 0..nb {
            b[(r, nb + k)] = cell.lower_mass[m * nb + k]; // (τ:J, ψ_m) with τ:J = τ_xy − τ_yx
            b[(r, 2 * nb + k)] = -cell.lower_mass[m * nb + k];
        }
        for case in 0..cases {
            rhs[(r, case)] = data.symmetry[case][t * nl + m];
        }
    }
    let mut row = vec![0.0; width];
    let mut r = 3 * nl;
    for face in opposite {
        for m in 0..=input.order {
            for i in 0..2 {
                face_coefficients(input, face, 0, m, i, &mut row);
                b.row_mut(r).copy_from_slice(&row);
                r += 1;
            }
        }
    }
}

/// Static condensation of cell t into `c`: with A = B_L M⁻¹ B_Lᵀ = L Lᵀ and V = L⁻¹ B_L M⁻¹,
/// P = M⁻¹ − VᵀV, so P B_Gᵀ = M⁻¹B_Gᵀ − Vᵀ(V B_Gᵀ) and, with F = (τ*, φ),
/// x₀ = P F + Vᵀ L⁻¹ b_L = M⁻¹F + Vᵀ(L⁻¹ b_L − V F).
fn condense(
    input: &PatchInput,
    t: usize,
    rows: &[FaceRow],
    data: &CompatibleData,
    c: &mut Condensed,
) -> Result<(), String> {
    let (width, cases) = (input.width(), input.target.len());
    local_rows(input, t, data, &mut c.b_local, &mut c.b_rhs);
    global_block(input, t, rows, c);
    let n_local = c.b_local.nrows();
    let n_global = c.rows.len();
    shaped(&mut c.minv_blt, width, n_local);
    c.minv_blt.tr_copy_from(&c.b_local);
    apply_inverse_mass(input, t, &mut c.minv_blt);
    shaped(&mut c.gram, n_local, n_local);
    c.b_local.mul_to(&c.minv_blt, &mut c.gram);
    let a = std::mem::replace(&mut c.gram, empty())
        .cholesky()
        .ok_or("the local constraints of a cell are not independent")?;
    shaped(&mut c.v, n_local, width);
    c.v.tr_copy_from(&c.minv_blt);
    a.l_dirty().solve_lower_triangular_mut(&mut c.v);
    shaped(&mut c.p_bt, width, n_global);
    c.p_bt.copy_from(&c.b_global_t);
    apply_inverse_mass(input, t, &mut c.p_bt);
    shaped(&mut c.v_bgt, n_local, n_global);
    c.v.mul_to(&c.b_global_t, &mut c.v_bgt);
    c.p_bt.gemm_tr(-1.0, &c.v, &c.v_bgt, 1.0);
    shaped(&mut c.target, width, cases);
    for case in 0..cases {
        c.target.column_mut(case).copy_from_slice(&input.target[case][t * width..(t + 1) * width]);
    }
    shaped(&mut c.w, n_local, cases);
    c.w.copy_from(&c.b_rhs);
    a.l_dirty().solve_lower_triangular_mut(&mut c.w);
    c.w.gemm(-1.0, &c.v, &c.target, 1.0);
    shaped(&mut c.x0, width, cases);
    c.x0.copy_from(&c.target);
    apply_inverse_mass(input, t, &mut c.x0);
    c.x0.gemm_tr(1.0, &c.v, &c.w, 1.0);
    c.gram = a.unpack_dirty();
    shaped(&mut c.coupling, n_global, n_global);
    c.p_bt.tr_mul_to(&c.b_global_t, &mut c.coupling);
    shaped(&mut c.trace, n_global, cases);
    c.b_global_t.tr_mul_to(&c.x0, &mut c.trace);
    Ok(())
}

/// The face rows that touch cell t (`c.rows`, `c.sides`) and their coefficients on it,
/// transposed (B_Gᵀ, into `c.b_global_t`).
fn global_block(input: &PatchInput, t: usize, rows: &[FaceRow], c: &mut Condensed) {
    c.rows.clear();
    c.sides.clear();
    for (r, row) in rows.iter().enumerate() {
        let face = &input.faces[row.face];
        if let Some(side) = face.cells.iter().position(|&cell| cell == t) {
            if side == 0 || matches!(face.kind, FaceKind::Interior) {
                c.rows.push(r);
                c.sides.push(side);
            }
        }
    }
    zeroed(&mut c.b_global_t, input.width(), c.rows.len());
    let mut row = vec![0.0; input.width()];
    for (a, (&r, &side)) in c.rows.iter().zip(&c.sides).enumerate() {
        face_coefficients(input, &input.faces[rows[r].face], side, rows[r].m, rows[r].i, &mut row);
        c.b_global_t.column_mut(a).copy_from_slice(&row);
    }
}

/// X ← M⁻¹ X on cell t: the same mass block for every component, i.e. for each block of n_basis
/// entries of each column of X (width rows).
fn apply_inverse_mass(input: &PatchInput, t: usize, x: &mut DMatrix<f64>) {
    let nb = input.n_basis;
    let inverse = &input.cells[t].mass_inverse; // row-major
    let mut product = [0.0; 6];
    for block in x.as_mut_slice().chunks_exact_mut(nb) {
        for (k, p) in product[..nb].iter_mut().enumerate() {
            *p = inverse[k * nb..(k + 1) * nb].iter().zip(block.iter()).map(|(m, v)| m * v).sum();
        }
        block.copy_from_slice(&product[..nb]);
    }
}

/// Adds s K Kᵀ to the condensed matrix, K = the face rows' part of λ_z for the free rigid
/// motions z (z_i at the face nodes), s = tr S / tr KᵀK.
fn add_rigid_kernel(input: &PatchInput, rows: &[FaceRow], schur: &mut DMatrix<f64>) {
    if input.rigid.is_empty() {
        return;
    }
    let kernel = DMatrix::from_fn(rows.len(), input.rigid.len(), |r, j| {
        input.rigid_motion(&input.rigid[j], input.faces[rows[r].face].nodes[rows[r].m])[rows[r].i]
    });
    let s = schur.trace() / kernel.norm_squared();
    *schur += s * &kernel * kernel.transpose();
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
    let (projections, coefficients) = (rigid_projections(input), lower_coefficients(input));
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

/// (ψ_m e_i, z)_T for every divergence row (t, m, i) and free rigid motion z.
fn rigid_projections(input: &PatchInput) -> DMatrix<f64> {
    let nl = input.n_lower;
    DMatrix::from_fn(input.cells.len() * nl * 2, input.rigid.len(), |row, j| {
        let (t, m, i) = (row / (2 * nl), (row / 2) % nl, row % 2);
        (0..nl)
            .map(|l| {
                input.cells[t].lower_gram[m * nl + l] * input.rigid_motion(&input.rigid[j], input.lower_nodes[t][l])[i]
            })
            .sum()
    })
}

/// The coefficients z_i(x_m) of Π^{p−1} z for every divergence row (t, m, i) and free z.
fn lower_coefficients(input: &PatchInput) -> DMatrix<f64> {
    let nl = input.n_lower;
    DMatrix::from_fn(input.cells.len() * nl * 2, input.rigid.len(), |row, j| {
        let (t, m, i) = (row / (2 * nl), (row / 2) % nl, row % 2);
        input.rigid_motion(&input.rigid[j], input.lower_nodes[t][m])[i]
    })
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
