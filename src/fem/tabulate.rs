//! Lagrange basis functions tabulated at the points of a triangle or tetrahedron quadrature
//! rule.
//!
//! Tabulating once per (degree, rule) keeps the element loops free of basis evaluations.

use super::{lagrange, quadrature, tetrahedron};

/// Values and reference gradients of the P_order basis at the points of a rule on the
/// reference simplex of dimension D.
#[derive(Debug, Clone)]
pub struct Tabulation<const D: usize = 2> {
    pub order: usize,
    /// Number of basis functions.
    pub n_basis: usize,
    /// Reference points and weights (weights sum to 1/2 on the triangle, 1/6 on the
    /// tetrahedron).
    pub points: Vec<[f64; D]>,
    pub weights: Vec<f64>,
    /// φ_i(ξ_q) at `values[q * n_basis + i]`.
    pub values: Vec<f64>,
    /// ∇̂φ_i(ξ_q) at `gradients[q * n_basis + i]`.
    pub gradients: Vec<[f64; D]>,
}

impl Tabulation {
    /// Tabulates P_order at the points of the triangle rule exact to `degree`.
    pub fn new(order: usize, degree: usize) -> Self {
        let rule = quadrature::triangle_cached(degree);
        Self::of_rule(
            order,
            lagrange::n_basis(order),
            (&rule.points, &rule.weights),
            lagrange::values,
            lagrange::gradients,
        )
    }
}

impl Tabulation<3> {
    /// Tabulates P_order at the points of the tetrahedron rule exact to `degree`.
    pub fn tetrahedron(order: usize, degree: usize) -> Self {
        let rule = quadrature::tetrahedron_cached(degree);
        let n_basis = tetrahedron::n_basis(order);
        Self::of_rule(order, n_basis, (&rule.points, &rule.weights), tetrahedron::values, tetrahedron::gradients)
    }
}

impl<const D: usize> Tabulation<D> {
    /// The `n_basis` functions of P_order, evaluated by `values` and `gradients`, at the
    /// points of a rule.
    fn of_rule(
        order: usize,
        n_basis: usize,
        (points, weights): (&[[f64; D]], &[f64]),
        values: fn(usize, [f64; D], &mut [f64]),
        gradients: fn(usize, [f64; D], &mut [[f64; D]]),
    ) -> Self {
        let nq = points.len();
        let (mut phi, mut grad) = (vec![0.0; nq * n_basis], vec![[0.0; D]; nq * n_basis]);
        for (q, &xi) in points.iter().enumerate() {
            values(order, xi, &mut phi[q * n_basis..(q + 1) * n_basis]);
            gradients(order, xi, &mut grad[q * n_basis..(q + 1) * n_basis]);
        }
        Tabulation { order, n_basis, points: points.to_vec(), weights: weights.to_vec(), values: phi, gradients: grad }
    }

    pub fn n_points(&self) -> usize {
        self.weights.len()
    }

    /// The integrals ∫_T̂ φ̂_i ≈ Σ_q w_q φ̂_i(ξ_q) of the basis over the reference cell.
    pub fn integrals(&self) -> Vec<f64> {
        (0..self.n_basis).map(|i| (0..self.n_points()).map(|q| self.weights[q] * self.phi(q)[i]).sum()).collect()
    }

    /// Basis values at point q.
    pub fn phi(&self, q: usize) -> &[f64] {
        &self.values[q * self.n_basis..(q + 1) * self.n_basis]
    }

    /// Reference gradients at point q.
    pub fn grad(&self, q: usize) -> &[[f64; D]] {
        &self.gradients[q * self.n_basis..(q + 1) * self.n_basis]
    }
}
