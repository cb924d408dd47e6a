//! Condition (C): the patch data made compatible with the rigid motions the patch leaves free.

use super::algebra::column_mut;
use super::{FaceRow, PatchInput};
use nalgebra::{DMatrix, DVector};

/// K = the face rows' part of λ_z for the free rigid motions z (z_i at the face nodes), one
/// column per motion.
pub(super) fn rigid_kernel(input: &PatchInput, rows: &[FaceRow]) -> DMatrix<f64> {
    DMatrix::from_fn(rows.len(), input.rigid.len(), |r, j| {
        input.rigid_motion(&input.rigid[j], input.faces[rows[r].face].nodes[rows[r].m])[rows[r].i]
    })
}

/// Divergence and symmetry right-hand sides per case (layouts of [`PatchInput::divergence`]
/// and `[case][cell · n_lower + m]`), and the compatibility defect of the total with its scale.
pub(super) struct CompatibleData {
    pub(super) divergence: Vec<Vec<f64>>,
    pub(super) symmetry: Vec<Vec<f64>>,
    pub(super) defect: (f64, f64),
}

/// The divergence and symmetry data of every case, made compatible, and the remaining
/// compatibility defect of the total. The total (case 0) satisfies (C) by construction up
/// to the p = 1 rotations, cancelled by c = κ J; the other cases get a rigid-motion term
/// Π^{p−1} r_i in their divergence data, r_i the rigid motion that restores (C)
/// (docs/method.md §4.3), and a κ J term along the motions with Π^{p−1} z = 0.
pub(super) fn compatible_data(input: &PatchInput, rows: &[FaceRow]) -> CompatibleData {
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
