//! The vertex-patch problem of the stress reconstruction (docs/method.md §4).
//!
//! On the patch ω_a, find σ^a in broken P_p(T)^{2×2} minimising ‖σ^a − τ*‖_{ω_a} under the
//! linear constraints B σ^a = b:
//!
//! - normal-trace continuity on interior faces, ∫_F [[σ n_F]]·q = 0, q ∈ P_p(F)²;
//! - prescribed normal traces on the other faces, ∫_F σn·q = ∫_F t_F·q (t_F = 0 on faces
//!   away from a; none for the fixed components of Dirichlet faces);
//! - divergence, (∇·σ, v)_T = (g, v)_T for v ∈ P_{p−1}(T)², restricted to v orthogonal to
//!   the rigid motions z the patch leaves free (they form the kernel of Bᵀ);
//! - weak symmetry, (σ, m J)_T = (c, m J)_T for m ∈ P_{p−1}(T).
//!
//! With the mass matrix M: σ = τ̂* − M⁻¹Bᵀλ, (B M⁻¹ Bᵀ) λ = B τ̂* − b, τ̂* = M⁻¹(τ*, φ).
//! One Cholesky factorisation serves every right-hand side (total, regularisation,
//! linearisation).

use super::afw::{CellIntegrals, COMPONENTS};
use nalgebra::{DMatrix, DVector};

/// What a face of the patch imposes.
pub enum FaceKind {
    /// Shared by two cells of the patch: continuity of σn.
    Interior,
    /// σn·e_i = data for the components i with `active[i]`; `data[case][m · 2 + i]` holds
    /// ∫_F t_i q_m for each right-hand side.
    Trace { active: [bool; 2], data: Vec<Vec<f64>> },
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
    fn n_sigma(&self) -> usize {
        self.cells.len() * COMPONENTS * self.n_basis
    }

    /// Index of coefficient (cell, c, k).
    fn index(&self, cell: usize, c: usize, k: usize) -> usize {
        (cell * COMPONENTS + c) * self.n_basis + k
    }

    fn rigid_motion(&self, z: &[f64; 3], x: [f64; 2]) -> [f64; 2] {
        let (px, py) = (x[0] - self.origin[0], x[1] - self.origin[1]);
        [z[0] - z[2] * py, z[1] + z[2] * px]
    }
}

/// Solves the patch problem for every case; fails only if the constraints are dependent.
pub fn solve(input: &PatchInput) -> Result<PatchSolution, String> {
    let cases = input.target.len();
    let (faces, face_rhs) = face_rows(input);
    let (div, div_rhs, unseen) = divergence_rows(input);
    let (sym, mut sym_rhs) = symmetry_rows(input);
    let compatibility = compatibility(input, &face_rhs, &unseen, &mut sym_rhs);
    let b_rows = faces.len() + div.nrows() + sym.len();
    let n = input.n_sigma();
    let mut b = DMatrix::zeros(b_rows, n);
    let mut rhs = DMatrix::zeros(b_rows, cases);
    for (r, row) in faces.iter().enumerate() {
        b.row_mut(r).copy_from(&row.transpose());
    }
    b.rows_mut(faces.len(), div.nrows()).copy_from(&div);
    for (r, row) in sym.iter().enumerate() {
        b.row_mut(faces.len() + div.nrows() + r).copy_from(&row.transpose());
    }
    for case in 0..cases {
        let column: Vec<f64> =
            face_rhs[case].iter().chain(div_rhs[case].iter()).chain(sym_rhs[case].iter()).copied().collect();
        rhs.set_column(case, &DVector::from_vec(column));
    }
    let minv_bt = apply_inverse_mass(input, &b.transpose());
    let schur = schur_complement(input, &b, &minv_bt);
    let solver = SchurSolver::new(schur, unseen.len())?;
    let sigma = (0..cases)
        .map(|case| {
            let target = apply_inverse_mass(input, &DMatrix::from_column_slice(n, 1, &input.target[case]));
            let lambda = solver.solve(&b * &target - rhs.column(case));
            (target - &minv_bt * lambda).column(0).iter().copied().collect()
        })
        .collect();
    Ok(PatchSolution { sigma, compatibility })
}

/// Solver of the Schur complement S = B M⁻¹ Bᵀ: Cholesky, or, when `deficiency` rigid motions
/// remain in its kernel (patches of one or two cells at a free corner), the pseudo-inverse
/// without those directions; the right-hand side is compatible, so both solve S λ = r.
enum SchurSolver {
    Cholesky(nalgebra::Cholesky<f64, nalgebra::Dyn>),
    Pseudo(nalgebra::SymmetricEigen<f64, nalgebra::Dyn>, usize),
}

impl SchurSolver {
    fn new(schur: DMatrix<f64>, deficiency: usize) -> Result<Self, String> {
        if deficiency == 0 {
            return schur
                .cholesky()
                .map(SchurSolver::Cholesky)
                .ok_or_else(|| "the patch constraints are not independent".into());
        }
        Ok(SchurSolver::Pseudo(schur.symmetric_eigen(), deficiency))
    }

    fn solve(&self, r: DVector<f64>) -> DVector<f64> {
        match self {
            SchurSolver::Cholesky(c) => c.solve(&r),
            SchurSolver::Pseudo(e, deficiency) => {
                let mut order: Vec<usize> = (0..e.eigenvalues.len()).collect();
                order.sort_by(|&i, &j| e.eigenvalues[i].total_cmp(&e.eigenvalues[j]));
                let mut lambda = DVector::zeros(r.len());
                for &j in &order[*deficiency..] {
                    let v = e.eigenvectors.column(j);
                    lambda += v * (v.dot(&r) / e.eigenvalues[j]);
                }
                lambda
            }
        }
    }
}

/// Face moment rows and their right-hand sides per case.
fn face_rows(input: &PatchInput) -> (Vec<DVector<f64>>, Vec<Vec<f64>>) {
    let cases = input.target.len();
    let mut rows = Vec::new();
    let mut rhs = vec![Vec::new(); cases];
    for face in &input.faces {
        let (sides, active): (usize, [bool; 2]) = match &face.kind {
            FaceKind::Interior => (2, [true; 2]),
            FaceKind::Trace { active, .. } => (1, *active),
        };
        for m in 0..=input.order {
            for i in (0..2).filter(|&i| active[i]) {
                let mut row = DVector::zeros(input.n_sigma());
                for side in 0..sides {
                    let sign = if side == 0 { 1.0 } else { -1.0 };
                    for k in 0..input.n_basis {
                        let moment = face.moments[side][m * input.n_basis + k];
                        for j in 0..2 {
                            // (τ n)_i = τ_ij n_j; both sides use the first cell's normal
                            row[input.index(face.cells[side], 2 * i + j, k)] += sign * moment * face.normal[j];
                        }
                    }
                }
                rows.push(row);
                for (case, r) in rhs.iter_mut().enumerate() {
                    r.push(match &face.kind {
                        FaceKind::Interior => 0.0,
                        FaceKind::Trace { data, .. } => data[case][m * 2 + i],
                    });
                }
            }
        }
    }
    (rows, rhs)
}

/// Divergence rows, restricted to test fields orthogonal to the free rigid motions, their
/// right-hand sides per case, and the free rigid motions with Π^{p−1} z = 0 (as
/// coefficients over `input.rigid`), which the restriction cannot remove: they stay in the
/// kernel of B M⁻¹ Bᵀ.
fn divergence_rows(input: &PatchInput) -> (DMatrix<f64>, Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let (nb, nl) = (input.n_basis, input.n_lower);
    let n_rows = input.cells.len() * nl * 2;
    let mut d = DMatrix::zeros(n_rows, input.n_sigma());
    for (t, cell) in input.cells.iter().enumerate() {
        for m in 0..nl {
            for i in 0..2 {
                for k in 0..nb {
                    for j in 0..2 {
                        // (∂_j τ_ij, ψ_m)_T
                        d[((t * nl + m) * 2 + i, input.index(t, 2 * i + j, k))] = cell.divergence[(m * nb + k) * 2 + j];
                    }
                }
            }
        }
    }
    let mut rhs: Vec<Vec<f64>> = input.divergence.clone();
    if input.rigid.is_empty() {
        return (d, rhs, Vec::new());
    }
    // W[row, z] = (ψ_m e_i, z)_T; Qᵀ of W = QR maps the rows onto [range W; null Wᵀ]
    let w = DMatrix::from_fn(n_rows, input.rigid.len(), |row, zi| {
        let (t, m, i) = (row / (2 * nl), (row / 2) % nl, row % 2);
        (0..nl)
            .map(|l| {
                input.cells[t].lower_gram[m * nl + l] * input.rigid_motion(&input.rigid[zi], input.lower_nodes[t][l])[i]
            })
            .sum()
    });
    let svd = w.clone().svd(true, true);
    let largest = svd.singular_values.max();
    let kept: Vec<usize> =
        (0..svd.singular_values.len()).filter(|&j| svd.singular_values[j] > 1e-12 * largest).collect();
    if kept.len() == input.rigid.len() {
        // W of full rank r, W = QR (Householder): the last n_rows − r rows of Qᵀ are an
        // orthonormal basis of the test fields orthogonal to range(W) = {Π^{p−1} z}
        let qr = w.qr();
        let restrict = |mut m: DMatrix<f64>| {
            qr.q_tr_mul(&mut m);
            m.rows(kept.len(), n_rows - kept.len()).into_owned()
        };
        for column in &mut rhs {
            *column = restrict(DMatrix::from_column_slice(n_rows, 1, column)).iter().copied().collect();
        }
        return (restrict(d), rhs, Vec::new());
    }
    // otherwise (small patches) the test fields orthogonal to range(W): the eigenvectors of
    // I − P_W with eigenvalue 1
    let u: DMatrix<f64> = svd.u.expect("requested");
    let u_k: DMatrix<f64> = u.select_columns(&kept);
    let complement: DMatrix<f64> = DMatrix::identity(n_rows, n_rows) - &u_k * u_k.transpose();
    let eigen = complement.symmetric_eigen();
    let keep: Vec<usize> = (0..n_rows).filter(|&j| eigen.eigenvalues[j] > 0.5).collect();
    let q = DMatrix::from_fn(n_rows, keep.len(), |r, c| eigen.eigenvectors[(r, keep[c])]);
    let d = q.transpose() * d;
    for column in &mut rhs {
        *column = (q.transpose() * DVector::from_vec(column.clone())).iter().copied().collect();
    }
    // rigid motions with Π^{p−1} z = 0: the kernel of W, the complement of its row space
    let v_t: DMatrix<f64> = svd.v_t.expect("requested");
    let v_k: DMatrix<f64> = v_t.select_rows(&kept);
    let r = input.rigid.len();
    let kernel = (DMatrix::<f64>::identity(r, r) - v_k.transpose() * &v_k).symmetric_eigen();
    let unseen: Vec<Vec<f64>> = (0..r)
        .filter(|&j| kernel.eigenvalues[j] > 0.5)
        .map(|j| kernel.eigenvectors.column(j).iter().copied().collect())
        .collect();
    (d, rhs, unseen)
}

/// Weak-symmetry rows (τ_xy − τ_yx, ψ_m)_T and zero right-hand sides.
fn symmetry_rows(input: &PatchInput) -> (Vec<DVector<f64>>, Vec<Vec<f64>>) {
    let (nb, nl) = (input.n_basis, input.n_lower);
    let mut rows = Vec::new();
    for (t, cell) in input.cells.iter().enumerate() {
        for m in 0..nl {
            let mut row = DVector::zeros(input.n_sigma());
            for k in 0..nb {
                row[input.index(t, 1, k)] = cell.lower_mass[m * nb + k]; // τ:J = τ_xy − τ_yx
                row[input.index(t, 2, k)] = -cell.lower_mass[m * nb + k];
            }
            rows.push(row);
        }
    }
    let n = rows.len();
    (rows, vec![vec![0.0; n]; input.target.len()])
}

/// Defect of the compatibility condition (C) of one case for each free rigid motion z:
/// Σ_F (t_F, z)_F − (Π^{p−1} g, z)_{ω_a} (with c = 0), and the sum of its absolute terms.
fn defects(input: &PatchInput, face_rhs: &[f64], divergence: &[f64]) -> Vec<(f64, f64)> {
    let nl = input.n_lower;
    input
        .rigid
        .iter()
        .map(|z| {
            let mut row = 0;
            let (mut faces, mut scale) = (0.0, 0.0);
            for face in &input.faces {
                let active = match &face.kind {
                    FaceKind::Interior => [true; 2],
                    FaceKind::Trace { active, .. } => *active,
                };
                for m in 0..=input.order {
                    for i in (0..2).filter(|&i| active[i]) {
                        let term = face_rhs[row] * input.rigid_motion(z, face.nodes[m])[i];
                        faces += term;
                        scale += term.abs();
                        row += 1;
                    }
                }
            }
            let mut volume = 0.0;
            for t in 0..input.cells.len() {
                for m in 0..nl {
                    let zm = input.rigid_motion(z, input.lower_nodes[t][m]);
                    for i in 0..2 {
                        let term = divergence[(t * nl + m) * 2 + i] * zm[i];
                        volume += term;
                        scale += term.abs();
                    }
                }
            }
            (faces - volume, scale)
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

/// Makes the data compatible where (C) is needed. The total (case 0) must satisfy (C) for
/// every free z, so that ∇·σ^a = Π^{p−1} g_a exactly: for p = 1 the rotational defect is
/// cancelled by c = κ J, (c, ∇z) = −2bκ|ω_a|. The other cases only need (C) along the
/// motions with Π^{p−1} z = 0 (`unseen`), which the restricted divergence cannot absorb.
/// Returns the largest remaining defect of the total and the largest sum of its terms.
fn compatibility(
    input: &PatchInput,
    face_rhs: &[Vec<f64>],
    unseen: &[Vec<f64>],
    sym_rhs: &mut [Vec<f64>],
) -> (f64, f64) {
    if input.rigid.is_empty() {
        return (0.0, 0.0);
    }
    let all: Vec<Vec<f64>> =
        (0..input.rigid.len()).map(|k| (0..input.rigid.len()).map(|j| f64::from(j == k)).collect()).collect();
    let mut total = (0.0, 0.0);
    for case in 0..input.target.len() {
        let d = defects(input, &face_rhs[case], &input.divergence[case]);
        let directions = if case == 0 { &all } else { unseen };
        let kappa = if input.rotation_correction { rotation_kappa(input, &d, directions) } else { None };
        if let Some(kappa) = kappa {
            correct_symmetry(input, kappa, &mut sym_rhs[case]);
        }
        if case == 0 {
            let kappa = kappa.unwrap_or(0.0);
            let remaining = input.rigid.iter().zip(&d).map(|(z, d)| (d.0 + 2.0 * z[2] * kappa * input.area).abs());
            total = (remaining.fold(0.0, f64::max), d.iter().map(|d| d.1).fold(0.0, f64::max));
        }
    }
    total
}

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

/// S = B M⁻¹ Bᵀ = Σ_T B_T M_T⁻¹ B_Tᵀ, each cell contributing only to the rows that touch it.
fn schur_complement(input: &PatchInput, b: &DMatrix<f64>, minv_bt: &DMatrix<f64>) -> DMatrix<f64> {
    let width = COMPONENTS * input.n_basis;
    let mut schur = DMatrix::zeros(b.nrows(), b.nrows());
    for t in 0..input.cells.len() {
        let start = t * width;
        let rows: Vec<usize> =
            (0..b.nrows()).filter(|&r| b.view((r, start), (1, width)).iter().any(|&v| v != 0.0)).collect();
        let block = b.select_rows(&rows).columns(start, width).into_owned();
        let scaled = minv_bt.rows(start, width).select_columns(&rows);
        let product = block * scaled;
        for (i, &ri) in rows.iter().enumerate() {
            for (j, &rj) in rows.iter().enumerate() {
                schur[(ri, rj)] += product[(i, j)];
            }
        }
    }
    schur
}

/// M⁻¹ X for the block-diagonal mass matrix of the patch (same cell block for every
/// component).
fn apply_inverse_mass(input: &PatchInput, x: &DMatrix<f64>) -> DMatrix<f64> {
    let nb = input.n_basis;
    let mut out = x.clone();
    for (t, cell) in input.cells.iter().enumerate() {
        let inverse = DMatrix::from_row_slice(nb, nb, &cell.mass_inverse);
        for c in 0..COMPONENTS {
            let start = input.index(t, c, 0);
            out.rows_mut(start, nb).copy_from(&(&inverse * x.rows(start, nb)));
        }
    }
    out
}
