//! Condition estimates of sparse matrices.

use super::SparseLu;
use crate::fem::sparse::SparsePattern;

/// ‖A‖₁ of a matrix on `pattern`.
fn norm_1(pattern: &SparsePattern, values: &[f64]) -> f64 {
    let col_ptr = pattern.symbolic().col_ptr();
    (0..pattern.n())
        .map(|c| values[col_ptr[c]..col_ptr[c + 1]].iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Hager–Higham (LAPACK dlacon) estimate of κ₁(A) = ‖A‖₁ ‖A⁻¹‖₁, a lower bound that is
/// almost always within a factor 3, from a few solves with A and Aᵀ. None if A is singular.
pub fn condition_1(pattern: &SparsePattern, values: &[f64]) -> Option<f64> {
    let n = pattern.n();
    if n == 0 {
        return None;
    }
    let symbolic = SparseLu::analyse(pattern).ok()?;
    let lu = symbolic.factor(pattern, values).ok()?;
    let solve = |rhs: &[f64], transpose: bool| if transpose { lu.solve_transpose(rhs) } else { lu.solve(rhs) };
    let norm1 = |v: &[f64]| v.iter().map(|a| a.abs()).sum::<f64>();
    let mut x = vec![1.0 / n as f64; n];
    let mut estimate = 0.0;
    for iteration in 0..5 {
        let y = solve(&x, false);
        let new = norm1(&y);
        if iteration > 0 && new <= estimate {
            break;
        }
        estimate = new;
        let signs: Vec<f64> = y.iter().map(|v| if *v >= 0.0 { 1.0 } else { -1.0 }).collect();
        let z = solve(&signs, true);
        let (j, z_max) = z.iter().enumerate().fold((0, 0.0), |m, (i, v)| if v.abs() > m.1 { (i, v.abs()) } else { m });
        let ztx: f64 = z.iter().zip(&x).map(|(a, b)| a * b).sum();
        if z_max <= ztx {
            break;
        }
        x.fill(0.0);
        x[j] = 1.0;
    }
    // Higham's alternative vector b_i = (−1)^i (1 + i/(n−1)) guards against bad cases
    let b: Vec<f64> = (0..n)
        .map(|i| {
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            sign * (1.0 + i as f64 / (n.max(2) - 1) as f64)
        })
        .collect();
    let alternative = 2.0 * norm1(&solve(&b, false)) / (3.0 * n as f64);
    let estimate = estimate.max(alternative);
    estimate.is_finite().then_some(norm_1(pattern, values) * estimate)
}
