//! The projection \[x\]_{R⁻} = min(x, 0) and its C¹ regularisation \[x\]_{reg,δ}.
//!
//! Quadratic smoothing (docs/method.md §1.4):
//!
//!   \[x\]_{reg,δ} = x                 for x ≤ −δ,
//!               = −(x − δ)²/(4δ)    for |x| < δ,
//!               = 0                 for x ≥ δ,
//!
//! with derivative 1, (δ − x)/(2δ), 0 on the same pieces. It is monotone, 1-Lipschitz,
//! lies below min(x, 0) and differs from it by at most δ/4 (at x = 0). With δ = 0 it is the
//! plain projection with the semismooth derivative 1 for x < 0, 0 for x ≥ 0.

/// The quadratic C¹ smoothing \[x\]_{reg,δ} of min(x, 0) with half-width δ ≥ 0 (δ = 0: the
/// plain projection): a monotone, 1-Lipschitz approximation of min(x, 0). δ is a stress \[Pa\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Smoothing {
    pub delta: f64,
}

impl Smoothing {
    /// The plain projection min(x, 0) with its semismooth derivative.
    pub const NONE: Smoothing = Smoothing { delta: 0.0 };

    /// δ = −∞: the identity \[x\] = x with derivative 1, every point held closed (the fully
    /// active state of a bilateral joint).
    pub const CLOSED: Smoothing = Smoothing { delta: f64::NEG_INFINITY };

    /// The projected value \[x\]_{reg,δ}.
    pub fn value(&self, x: f64) -> f64 {
        let d = self.delta;
        if x <= -d {
            x
        } else if x >= d {
            0.0
        } else {
            -(x - d) * (x - d) / (4.0 * d)
        }
    }

    /// Its derivative (at the kink of δ = 0, the generalised derivative 0).
    pub fn derivative(&self, x: f64) -> f64 {
        let d = self.delta;
        if x <= -d && !(d == 0.0 && x == 0.0) {
            1.0
        } else if x >= d {
            0.0
        } else {
            (d - x) / (2.0 * d)
        }
    }

    /// Its second derivative, −1/(2δ) for |x| < δ and 0 elsewhere (0 for δ = 0: the
    /// semismooth choice). The closed indicator q'(P^n) of a cohesive joint has it as slope.
    pub fn second_derivative(&self, x: f64) -> f64 {
        let d = self.delta;
        if d > 0.0 && x.abs() < d {
            -0.5 / d
        } else {
            0.0
        }
    }

    /// The points where \[x\]_{reg,δ} is not a polynomial; quadrature splits faces there.
    pub fn breakpoints(&self) -> Vec<f64> {
        if self.delta == f64::NEG_INFINITY {
            vec![]
        } else if self.delta == 0.0 {
            vec![0.0]
        } else {
            vec![-self.delta, self.delta]
        }
    }
}

/// The exact projection min(x, 0).
pub fn negative_part(x: f64) -> f64 {
    x.min(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smoothing_properties() {
        let p = Smoothing { delta: 0.3 };
        let xs: Vec<f64> = (-200..=200).map(|k| k as f64 * 0.005).collect();
        for &x in &xs {
            let (v, exact) = (p.value(x), negative_part(x));
            assert!(v <= exact + 1e-15 && exact - v <= 0.3 / 4.0 + 1e-15, "bound at {x}");
            let h = 1e-6;
            let fd = (p.value(x + h) - p.value(x - h)) / (2.0 * h);
            assert!((fd - p.derivative(x)).abs() < 1e-6, "derivative at {x}");
        }
        assert!((negative_part(0.0) - p.value(0.0) - 0.3 / 4.0).abs() < 1e-15);
        // C¹ at ±δ
        for x in [-0.3, 0.3] {
            assert!((p.value(x - 1e-9) - p.value(x + 1e-9)).abs() < 1e-8);
        }
        let plain = Smoothing::NONE;
        assert_eq!((plain.value(-2.0), plain.value(1.0)), (-2.0, 0.0));
        assert_eq!((plain.derivative(-2.0), plain.derivative(1.0), plain.derivative(0.0)), (1.0, 0.0, 0.0));
    }
}
