//! L² projection onto P_p of a face, for the data oscillation terms and the trace checks.

use crate::fem::lagrange;
use nalgebra::{DMatrix, DVector};

/// ‖v − Π_F^p v‖_F and ‖w − Π_F^p v‖_F-type residuals of a field sampled at the points of a
/// face rule. `rule` holds (s, weight · |F|) with s ∈ [0, 1] along the face.
pub struct FaceProjection {
    order: usize,
    /// q_m(s_j) for every rule point j.
    q: Vec<[f64; 3]>,
    weights: Vec<f64>,
    /// Cholesky factor of the face mass matrix ∫_F q_m q_l.
    mass: nalgebra::Cholesky<f64, nalgebra::Dyn>,
}

impl FaceProjection {
    pub fn new(order: usize, rule: &[(f64, f64)]) -> Self {
        let q: Vec<[f64; 3]> = rule
            .iter()
            .map(|&(s, _)| {
                let mut v = [0.0; 3];
                lagrange::segment_values(order, s, &mut v);
                v
            })
            .collect();
        let weights: Vec<f64> = rule.iter().map(|r| r.1).collect();
        let n = order + 1;
        let mass = DMatrix::from_fn(n, n, |m, l| q.iter().zip(&weights).map(|(v, w)| v[m] * v[l] * w).sum());
        FaceProjection { order, q, weights, mass: mass.cholesky().expect("the face mass matrix is positive definite") }
    }

    /// Coefficients of Π_F^p of the scalar samples `v`.
    pub fn project(&self, v: &[f64]) -> DVector<f64> {
        let n = self.order + 1;
        let moments =
            DVector::from_fn(n, |m, _| self.q.iter().zip(&self.weights).zip(v).map(|((q, w), vj)| q[m] * w * vj).sum());
        self.mass.solve(&moments)
    }

    /// ‖v − Π_F^p v‖_F for the scalar samples `v`.
    pub fn oscillation(&self, v: &[f64]) -> f64 {
        let alpha = self.project(v);
        self.distance(v, &alpha)
    }

    /// ‖w − Π_F^p v‖_F for samples `w` of a face polynomial of degree ≤ p and samples `v`.
    pub fn trace_defect(&self, w: &[f64], v: &[f64]) -> f64 {
        let alpha = self.project(v);
        self.distance(w, &alpha)
    }

    /// ‖v‖_F of samples `v`.
    pub fn norm(&self, v: &[f64]) -> f64 {
        v.iter().zip(&self.weights).map(|(x, w)| x * x * w).sum::<f64>().sqrt()
    }

    /// ‖w − Σ_m α_m q_m‖_F.
    fn distance(&self, w: &[f64], alpha: &DVector<f64>) -> f64 {
        self.q
            .iter()
            .zip(&self.weights)
            .zip(w)
            .map(|((q, weight), wj)| {
                let projected: f64 = (0..=self.order).map(|m| alpha[m] * q[m]).sum();
                (wj - projected).powi(2) * weight
            })
            .sum::<f64>()
            .sqrt()
    }
}
