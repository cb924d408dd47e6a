//! Joint laws on Γ_C: the tangential traction t^t = Π_S(P^t_γ) of docs/method.md §1.7.
//!
//! With the smoothing q = [·]_{reg,δ} of min(x, 0) and the threshold S ≥ 0, the clamp of x to
//! [−S, S] is
//!
//!   Π_S(x) = x + q(S − x) − q(x + S),
//!
//! exact for δ = 0 and C¹ for δ > 0 (the same smoothing as the normal part), so that η_reg
//! keeps meaning "the error that δ causes". The threshold S depends on the normal argument
//! P^n_γ through the contact pressure p_c = −q(P^n) and the closed indicator q'(P^n):
//!
//! | law | S |
//! |---|---|
//! | frictionless | 0 |
//! | Tresca | s |
//! | Coulomb | F p_c = −F q(P^n) |
//! | Mohr–Coulomb | c b(P^n) − F q(P^n): cohesion on the intact part only |
//!
//! with b the intact fraction of the normal law ([`NormalLaw::intact`]): the closed indicator
//! q'(P^n) of plain contact, 1 − o/o_c of a bond.

use super::bond::NormalLaw;
use super::projection::Smoothing;

/// The law of a joint (in `summary.json`: `{"law": "coulomb", "friction": 0.84}`).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
#[serde(tag = "law", rename_all = "snake_case")]
pub enum JointLaw {
    /// No tangential traction.
    #[default]
    Frictionless,
    /// |σ^t| ≤ s with a given threshold s \[Pa\].
    Tresca { threshold: f64 },
    /// |σ^t| ≤ F p_c, F = tan φ.
    Coulomb { friction: f64 },
    /// |σ^t| ≤ c + F p_c where the joint is closed, 0 where it is open.
    MohrCoulomb { friction: f64, cohesion: f64 },
}

/// The tangential traction Π_S(P^t) at one point and its derivatives in P^t and P^n.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tangential {
    pub value: f64,
    pub d_tangential: f64,
    pub d_normal: f64,
    /// ∂/∂P^n with the cohesion's closed indicator q'(P^n) held fixed: (q'(S − p_t) −
    /// q'(p_t + S)) (−F q'(P^n)), the derivative of a law that does not soften as the joint
    /// opens (docs/solver.md §3); d_normal for the other laws.
    pub d_normal_frozen: f64,
    /// The threshold S at the point.
    pub threshold: f64,
}

impl JointLaw {
    /// Whether the law has a tangential traction.
    pub fn has_friction(&self) -> bool {
        *self != JointLaw::Frictionless
    }

    /// The Gauss points per piece of a contact face that integrate the face terms of degree p
    /// exactly (docs/method.md §1.6). Between the cuts P_γ has degree p, and the integrands are
    /// a traction times test functions of degree ≤ p + 1 (ψ_a q_m of the reconstruction). The
    /// normal traction q(P_γ) and a constant threshold's clamp q(S − P^t) have degree ≤ 2p: p + 2
    /// points (exact to degree 2p + 3 ≥ 3p + 1). Coulomb's threshold −F q(P_γ) has degree 2p where
    /// P_γ is smoothed, its clamp q(S − P^t) then degree 4p, and ⌈(5p + 2)/2⌉ points are exact to
    /// degree 5p + 1.
    pub fn face_points(&self, order: usize) -> usize {
        match self {
            JointLaw::Frictionless | JointLaw::Tresca { .. } => order + 2,
            JointLaw::Coulomb { .. } | JointLaw::MohrCoulomb { .. } => (5 * order + 3) / 2,
        }
    }

    /// The largest shear force \[N/m\] a closed joint of `length` carries under the normal
    /// force N: s L (Tresca), F N (Coulomb), F N + c L (Mohr–Coulomb).
    pub fn capacity(&self, normal_force: f64, length: f64) -> f64 {
        match *self {
            JointLaw::Frictionless => 0.0,
            JointLaw::Tresca { threshold } => threshold * length,
            JointLaw::Coulomb { friction } => friction * normal_force,
            JointLaw::MohrCoulomb { friction, cohesion } => friction * normal_force + cohesion * length,
        }
    }

    /// The law with its strength divided by k: F/k, c/k, s/k (strength reduction).
    pub fn reduced(&self, k: f64) -> JointLaw {
        match *self {
            JointLaw::Frictionless => JointLaw::Frictionless,
            JointLaw::Tresca { threshold } => JointLaw::Tresca { threshold: threshold / k },
            JointLaw::Coulomb { friction } => JointLaw::Coulomb { friction: friction / k },
            JointLaw::MohrCoulomb { friction, cohesion } => {
                JointLaw::MohrCoulomb { friction: friction / k, cohesion: cohesion / k }
            }
        }
    }

    /// S, dS/dP^n and dS/dP^n with the cohesion's intact fraction held fixed (−F q'(P^n) for
    /// Mohr–Coulomb, dS/dP^n for the other laws) at the normal argument `p_n`.
    fn threshold(&self, p_n: f64, q: Smoothing, normal: &NormalLaw) -> (f64, f64, f64) {
        match *self {
            JointLaw::Frictionless => (0.0, 0.0, 0.0),
            JointLaw::Tresca { threshold } => (threshold, 0.0, 0.0),
            JointLaw::Coulomb { friction } => {
                let ds = -friction * q.derivative(p_n);
                (-friction * q.value(p_n), ds, ds)
            }
            JointLaw::MohrCoulomb { friction, cohesion } => {
                let ds_frozen = -friction * q.derivative(p_n);
                let (intact, d_intact) = normal.intact(p_n, q);
                let s = cohesion * intact - friction * q.value(p_n);
                (s, cohesion * d_intact + ds_frozen, ds_frozen)
            }
        }
    }

    /// Whether the threshold softens: S falls as P^n rises towards the open state (the
    /// cohesion of Mohr–Coulomb, lost where the joint opens).
    pub fn softens(&self) -> bool {
        matches!(self, JointLaw::MohrCoulomb { cohesion, .. } if *cohesion > 0.0)
    }

    /// Π_S(p_t) with S at `p_n` (the cohesion on the intact fraction of the `normal` law), and
    /// its derivatives: ∂/∂p_t = 1 − q'(S − p_t) − q'(p_t + S), ∂/∂p_n = (q'(S − p_t) −
    /// q'(p_t + S)) dS/dP^n. With [`Smoothing::CLOSED`] a frictional joint is held closed and
    /// sticking (S = ∞): Π = p_t, the bonded interface.
    pub fn tangential(&self, p_n: f64, p_t: f64, q: Smoothing, normal: &NormalLaw) -> Tangential {
        if q == Smoothing::CLOSED && self.has_friction() {
            let (d_tangential, d_normal) = (1.0, 0.0);
            return Tangential {
                value: p_t,
                d_tangential,
                d_normal,
                d_normal_frozen: d_normal,
                threshold: f64::INFINITY,
            };
        }
        let (s, ds, ds_frozen) = self.threshold(p_n, q, normal);
        let (upper, lower) = (q.derivative(s - p_t), q.derivative(p_t + s));
        Tangential {
            value: p_t + q.value(s - p_t) - q.value(p_t + s),
            d_tangential: 1.0 - upper - lower,
            d_normal: (upper - lower) * ds,
            d_normal_frozen: (upper - lower) * ds_frozen,
            threshold: s,
        }
    }

    /// The values of S − P^t and P^t + S at which Π_S(P^t) has a kink (the breakpoints of q).
    pub fn breakpoints(&self, q: Smoothing) -> Vec<f64> {
        if self.has_friction() {
            q.breakpoints()
        } else {
            Vec::new()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LAWS: [JointLaw; 3] = [
        JointLaw::Tresca { threshold: 0.7 },
        JointLaw::Coulomb { friction: 0.6 },
        JointLaw::MohrCoulomb { friction: 0.6, cohesion: 0.3 },
    ];

    #[test]
    fn the_plain_clamp_sticks_inside_and_slips_at_the_threshold() {
        let q = Smoothing::NONE;
        let law = JointLaw::Coulomb { friction: 0.5 };
        // p_n = −2: p_c = 2, S = 1
        assert_eq!(law.tangential(-2.0, 0.4, q, &NormalLaw::CONTACT).value, 0.4);
        assert_eq!(law.tangential(-2.0, 0.4, q, &NormalLaw::CONTACT).d_tangential, 1.0);
        let slip = law.tangential(-2.0, 3.0, q, &NormalLaw::CONTACT);
        assert_eq!((slip.value, slip.d_tangential, slip.d_normal), (1.0, 0.0, -0.5));
        let slip = law.tangential(-2.0, -3.0, q, &NormalLaw::CONTACT);
        assert_eq!((slip.value, slip.d_tangential, slip.d_normal), (-1.0, 0.0, 0.5));
        // open joint: no traction
        assert_eq!(law.tangential(1.0, 3.0, q, &NormalLaw::CONTACT).value, 0.0);
        let mc = JointLaw::MohrCoulomb { friction: 0.5, cohesion: 0.25 };
        assert_eq!(mc.tangential(-2.0, 3.0, q, &NormalLaw::CONTACT).value, 1.25);
        assert_eq!(mc.tangential(0.5, 3.0, q, &NormalLaw::CONTACT).value, 0.0);
    }

    /// Source: docs/solver.md §4 (the start from the closed, sticking state). Goal: with
    /// Smoothing::CLOSED every frictional law sticks, Π = p_t with derivatives 1 and 0, also
    /// where P^n > 0 or |p_t| exceeds the law's threshold. Parameters: LAWS, p_n ∈ {−2, 0.5},
    /// p_t ∈ {−3, 0.4, 3}.
    #[test]
    fn the_closed_state_sticks() {
        for law in LAWS {
            for (p_n, p_t) in [(-2.0, 0.4), (-2.0, 3.0), (0.5, -3.0)] {
                let t = law.tangential(p_n, p_t, Smoothing::CLOSED, &NormalLaw::CONTACT);
                assert_eq!((t.value, t.d_tangential, t.d_normal), (p_t, 1.0, 0.0), "{law:?} at ({p_n}, {p_t})");
            }
        }
    }

    /// Source: docs/solver.md §3 (the frozen Jacobian of a stalled run). Goal: d_normal_frozen
    /// is the derivative in P^n of Π_S with S = c q'(p̄) − F q(P^n), the cohesion's indicator
    /// held at p̄ (central differences), and d_normal itself for the laws that do not soften.
    /// Parameters: LAWS, δ = 0.05, (p_n, p_t) on a grid of step 0.05 across both kinks.
    #[test]
    fn the_frozen_derivative_holds_the_cohesion_fixed() {
        let q = Smoothing { delta: 0.05 };
        for law in LAWS {
            for i in -40..=40 {
                for j in -40..=40 {
                    let (p_n, p_t) = (0.05 * i as f64 + 0.0071, 0.05 * j as f64 + 0.0123);
                    let t = law.tangential(p_n, p_t, q, &NormalLaw::CONTACT);
                    let JointLaw::MohrCoulomb { friction, cohesion } = law else {
                        assert_eq!(t.d_normal_frozen, t.d_normal, "{law:?}");
                        continue;
                    };
                    let clamp = |s: f64| p_t + q.value(s - p_t) - q.value(p_t + s);
                    let frozen = |p: f64| clamp(cohesion * q.derivative(p_n) - friction * q.value(p));
                    let h = 1e-7;
                    let fd = (frozen(p_n + h) - frozen(p_n - h)) / (2.0 * h);
                    assert!((fd - t.d_normal_frozen).abs() < 1e-5, "{law:?} at ({p_n}, {p_t}): {fd} against {t:?}");
                }
            }
        }
        assert!(LAWS[2].softens() && !LAWS[1].softens());
    }

    #[test]
    fn smoothed_clamp_is_within_delta_and_its_derivatives_match_differences() {
        for delta in [0.0, 0.05] {
            let q = Smoothing { delta };
            for law in LAWS {
                for i in -40..=40 {
                    for j in -40..=40 {
                        let (p_n, p_t) = (0.05 * i as f64 + 0.0071, 0.05 * j as f64 + 0.0123);
                        let t = law.tangential(p_n, p_t, q, &NormalLaw::CONTACT);
                        let exact = law.tangential(p_n, p_t, Smoothing::NONE, &NormalLaw::CONTACT);
                        assert!(t.value.abs() <= t.threshold + 1e-15, "{law:?}: |Π_S| ≤ S");
                        if delta == 0.0 {
                            continue;
                        }
                        // the clamp moves by at most δ/4 per kink (two kinks) plus S's own change
                        let s_change = (t.threshold - exact.threshold).abs();
                        assert!((t.value - exact.value).abs() <= delta / 2.0 + s_change + 1e-12, "{law:?}");
                        let h = 1e-7;
                        let fd_t = (law.tangential(p_n, p_t + h, q, &NormalLaw::CONTACT).value
                            - law.tangential(p_n, p_t - h, q, &NormalLaw::CONTACT).value)
                            / (2.0 * h);
                        let fd_n = (law.tangential(p_n + h, p_t, q, &NormalLaw::CONTACT).value
                            - law.tangential(p_n - h, p_t, q, &NormalLaw::CONTACT).value)
                            / (2.0 * h);
                        assert!((fd_t - t.d_tangential).abs() < 1e-5, "{law:?} d/dp_t at ({p_n}, {p_t})");
                        assert!((fd_n - t.d_normal).abs() < 1e-5, "{law:?} d/dp_n at ({p_n}, {p_t})");
                    }
                }
            }
        }
    }
}
