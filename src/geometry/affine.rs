//! Affine maps from the reference triangle and the reference segment to physical space.
//!
//! Triangle: `x = v0 + J ξ` with the columns of `J` equal to `v1 − v0` and `v2 − v0`; physical
//! gradients are `∇φ = J⁻ᵀ ∇̂φ̂` and `dx = |det J| dξ`.
//! Segment: `x(s) = a + s (b − a)` for `s ∈ [0, 1]`, `ds_phys = |b − a| ds`.

use super::{Point, Vector};

/// Affine map of the reference triangle `(0,0), (1,0), (0,1)` onto a physical triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AffineMap {
    /// Image of the reference origin (vertex 0).
    pub origin: Point,
    /// `J[r][c] = ∂x_r / ∂ξ_c`.
    pub jacobian: [[f64; 2]; 2],
    /// `det J` (positive for counter-clockwise vertices).
    pub det: f64,
    /// `J⁻ᵀ`.
    pub inv_t: [[f64; 2]; 2],
}

impl AffineMap {
    /// Map sending the reference vertices to `v[0], v[1], v[2]`. Panics on a degenerate triangle.
    pub fn new(v: [Point; 3]) -> Self {
        let j = [[v[1][0] - v[0][0], v[2][0] - v[0][0]], [v[1][1] - v[0][1], v[2][1] - v[0][1]]];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        assert!(det != 0.0, "degenerate triangle {v:?}");
        let inv_t = [[j[1][1] / det, -j[1][0] / det], [-j[0][1] / det, j[0][0] / det]];
        Self { origin: v[0], jacobian: j, det, inv_t }
    }

    /// `x = origin + J ξ`.
    pub fn to_physical(&self, xi: Point) -> Point {
        let j = &self.jacobian;
        [self.origin[0] + j[0][0] * xi[0] + j[0][1] * xi[1], self.origin[1] + j[1][0] * xi[0] + j[1][1] * xi[1]]
    }

    /// `∇φ = J⁻ᵀ ∇̂φ̂`.
    pub fn physical_gradient(&self, ref_grad: Vector) -> Vector {
        let m = &self.inv_t;
        [m[0][0] * ref_grad[0] + m[0][1] * ref_grad[1], m[1][0] * ref_grad[0] + m[1][1] * ref_grad[1]]
    }

    /// Area `|det J| / 2`.
    pub fn area(&self) -> f64 {
        0.5 * self.det.abs()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobian_times_inverse_transpose_is_identity() {
        let m = AffineMap::new([[0.1, 0.2], [1.3, 0.4], [0.35, 1.1]]);
        for r in 0..2 {
            for c in 0..2 {
                // (J⁻ᵀ)ᵀ J = J⁻¹ J = I
                let s: f64 = (0..2).map(|k| m.inv_t[k][r] * m.jacobian[k][c]).sum();
                assert!((s - if r == c { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
        }
        assert!(m.det > 0.0);
    }
}
