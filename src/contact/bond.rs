//! The normal law of a joint: plain unilateral contact, or a cohesive bond with tensile
//! strength and linear softening (docs/method.md §1.13).
//!
//! With the opening o = g − u^n ≥ 0 and the effective normal traction σ'^n = σ^n + p_u, a
//! bond of tensile strength σ_t and fracture energy G_f carries σ'^n ≤ σ_t at o = 0 and
//! softens linearly once open,
//!
//!   σ'^n = σ_t (1 − o/o_c) for 0 ≤ o ≤ o_c,   0 beyond,   o_c = 2 G_f / σ_t,
//!
//! so that ∫₀^{o_c} σ'^n do = G_f. Nitsche's argument P_γ = σ'^n + γ o turns the law into a
//! function of P_γ alone wherever γ o_c > σ_t (the penalty stiffer than the softening slope
//! σ_t / o_c), with w = γ o_c and a = σ_t / (w − σ_t):
//!
//!   N(P) = P (P ≤ σ_t: bonded),   σ_t (w − P)/(w − σ_t) (σ_t ≤ P ≤ w: softening),   0 (P ≥ w),
//!
//!   N(P) = (1 + a) q(P − σ_t) − a q(P − w),   q = min(·, 0) or its smoothing [·]_{reg,δ},
//!
//! and the opening o = (P − N(P))/γ, its damage o/o_c = (P − σ_t)/(w − σ_t) clamped to [0, 1].
//! A Mohr–Coulomb cohesion acts on the intact fraction
//!
//!   b(P) = 1 − o/o_c = (q(P − σ_t) − q(P − w)) / (w − σ_t),
//!
//! where plain contact has the closed indicator b(P) = q'(P). Without a bond N = q: the law of
//! docs/method.md §1.2. The law is holonomic: the damage follows the present opening, and a
//! bond whose opening falls heals (the irreversible law is not built yet).

use super::projection::Smoothing;

/// A joint's bond (in `summary.json`: `{"tensile_strength": 5e5, "fracture_energy": 100}`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Bond {
    /// σ_t \[Pa\].
    pub tensile_strength: f64,
    /// G_f \[N/m\].
    pub fracture_energy: f64,
}

impl Bond {
    /// o_c = 2 G_f / σ_t \[m\]: the opening at which the bond is broken.
    pub fn critical_opening(&self) -> f64 {
        2.0 * self.fracture_energy / self.tensile_strength
    }

    /// The bond with its strength divided by k (strength reduction): σ_t/k and G_f/k, o_c kept.
    pub fn reduced(&self, k: f64) -> Bond {
        Bond { tensile_strength: self.tensile_strength / k, fracture_energy: self.fracture_energy / k }
    }

    /// Whether a face of Nitsche parameter γ resolves the softening: γ o_c > σ_t.
    pub fn resolved_by(&self, gamma: f64) -> bool {
        gamma * self.critical_opening() > self.tensile_strength
    }
}

/// The normal law N(P_γ) of one face: plain contact, or a bond at the face's γ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalLaw {
    /// (σ_t, w = γ o_c) of a bond; None: plain contact.
    bond: Option<[f64; 2]>,
}

/// The state of a point of a bonded joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BondState {
    /// o = 0 (P ≤ σ_t).
    Bonded,
    /// 0 < o < o_c.
    Softening,
    /// o ≥ o_c: an open crack.
    Broken,
}

impl NormalLaw {
    /// Plain unilateral contact, N = q.
    pub const CONTACT: NormalLaw = NormalLaw { bond: None };

    /// The law of a face of Nitsche parameter `gamma` with `bond` (None: plain contact).
    pub fn new(bond: Option<Bond>, gamma: f64) -> NormalLaw {
        NormalLaw { bond: bond.map(|b| [b.tensile_strength, gamma * b.critical_opening()]) }
    }

    /// a = σ_t / (w − σ_t).
    fn slope([t, w]: [f64; 2]) -> f64 {
        t / (w - t)
    }

    /// N(P) = (1 + a) q(P − σ_t) − a q(P − w), or q(P).
    pub fn value(&self, p: f64, q: Smoothing) -> f64 {
        match self.bond {
            None => q.value(p),
            Some(b @ [t, w]) => {
                let a = Self::slope(b);
                (1.0 + a) * q.value(p - t) - a * q.value(p - w)
            }
        }
    }

    /// N'(P) = (1 + a) q'(P − σ_t) − a q'(P − w), or q'(P): negative where the bond softens.
    pub fn derivative(&self, p: f64, q: Smoothing) -> f64 {
        match self.bond {
            None => q.derivative(p),
            Some(b @ [t, w]) => {
                let a = Self::slope(b);
                (1.0 + a) * q.derivative(p - t) - a * q.derivative(p - w)
            }
        }
    }

    /// The intact fraction b(P) on which a cohesion acts, and b'(P): (q(P − σ_t) − q(P − w))/(w
    /// − σ_t) with a bond, the closed indicator q'(P) and q''(P) without.
    pub fn intact(&self, p: f64, q: Smoothing) -> (f64, f64) {
        match self.bond {
            None => (q.derivative(p), q.second_derivative(p)),
            Some([t, w]) => {
                let span = w - t;
                ((q.value(p - t) - q.value(p - w)) / span, (q.derivative(p - t) - q.derivative(p - w)) / span)
            }
        }
    }

    /// The values of P where N or the intact fraction is not a polynomial: the breakpoints of q,
    /// shifted to σ_t and to w with a bond (and at 0 too, where friction's pressure −q(P) has
    /// its own).
    pub fn breakpoints(&self, q: Smoothing) -> Vec<f64> {
        let mut levels = q.breakpoints();
        if let Some([t, w]) = self.bond {
            let own = q.breakpoints();
            levels.extend(own.iter().map(|b| b + t).chain(own.iter().map(|b| b + w)));
        }
        levels
    }

    /// The P above which the joint carries no traction: the broken bond's w = γ o_c, or 0 (open)
    /// without a bond. Below it the joint is in contact or bonded; a crack is where it is not.
    pub fn carries_below(&self) -> f64 {
        self.bond.map_or(0.0, |[_, w]| w)
    }

    /// The damage o/o_c ∈ [0, 1] of the exact law at P (0 without a bond).
    pub fn damage(&self, p: f64) -> f64 {
        self.bond.map_or(0.0, |[t, w]| ((p - t) / (w - t)).clamp(0.0, 1.0))
    }

    /// The state of the exact law at P (None without a bond).
    pub fn state(&self, p: f64) -> Option<BondState> {
        let [t, w] = self.bond?;
        Some(if p <= t {
            BondState::Bonded
        } else if p < w {
            BondState::Softening
        } else {
            BondState::Broken
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Source: the module doc. Goal: N(P) with the opening o = (P − N)/γ is the linear
    /// softening law σ'^n = σ_t (1 − o/o_c) on the open part, σ'^n = P ≤ σ_t at o = 0 and 0 past
    /// o_c; the intact fraction is 1 − o/o_c; σ_t → 0 gives plain contact. Parameters: σ_t = 2,
    /// G_f = 3 (o_c = 3), γ = 10, P on a grid over [−10, 40].
    #[test]
    fn the_law_is_linear_softening_in_the_opening() {
        let bond = Bond { tensile_strength: 2.0, fracture_energy: 3.0 };
        let (gamma, oc) = (10.0, bond.critical_opening());
        assert_eq!(oc, 3.0);
        let law = NormalLaw::new(Some(bond), gamma);
        let q = Smoothing::NONE;
        for i in -100..=400 {
            let p = 0.1 * i as f64 + 0.003;
            let n = law.value(p, q);
            let o = (p - n) / gamma;
            let expected = if o <= 1e-12 {
                assert!(n <= 2.0 + 1e-12 && (n - p).abs() < 1e-12, "bonded at P = {p}: N = {n}");
                continue;
            } else if o < oc {
                2.0 * (1.0 - o / oc)
            } else {
                0.0
            };
            assert!((n - expected).abs() < 1e-12, "P = {p}: N = {n}, law {expected}");
            let (b, _) = law.intact(p, q);
            assert!((b - (1.0 - (o / oc).min(1.0))).abs() < 1e-12, "intact fraction at P = {p}");
            assert!((law.damage(p) - (o / oc).min(1.0)).abs() < 1e-12);
        }
        let weak = NormalLaw::new(Some(Bond { tensile_strength: 1e-9, fracture_energy: 3.0 }), gamma);
        for p in [-5.0, -0.1, 0.2, 7.0] {
            assert!((weak.value(p, q) - q.value(p)).abs() <= 1e-9);
        }
        assert!(bond.resolved_by(gamma) && !bond.resolved_by(0.6));
    }

    /// Source: the module doc. Goal: the derivatives of N and of the intact fraction match
    /// central differences with the smoothing, and N lies within δ/4 (1 + 2a) of the exact law.
    /// Parameters: σ_t = 2, G_f = 3, γ = 10, δ = 0.4, P over [−10, 40].
    #[test]
    fn the_smoothed_law_has_its_derivatives() {
        let law = NormalLaw::new(Some(Bond { tensile_strength: 2.0, fracture_energy: 3.0 }), 10.0);
        let q = Smoothing { delta: 0.4 };
        let a = 2.0 / 28.0;
        for i in -1000..=4000 {
            let p = 0.01 * i as f64 + 0.0007;
            let h = 1e-6;
            let fd = (law.value(p + h, q) - law.value(p - h, q)) / (2.0 * h);
            assert!((fd - law.derivative(p, q)).abs() < 1e-6, "N' at {p}");
            let fd = (law.intact(p + h, q).0 - law.intact(p - h, q).0) / (2.0 * h);
            assert!((fd - law.intact(p, q).1).abs() < 1e-6, "b' at {p}");
            let bound = 0.1 * (1.0 + 2.0 * a) + 1e-12;
            assert!((law.value(p, q) - law.value(p, Smoothing::NONE)).abs() <= bound, "δ at {p}");
        }
        assert_eq!(law.breakpoints(q), vec![-0.4, 0.4, 1.6, 2.4, 29.6, 30.4]);
        assert_eq!(NormalLaw::CONTACT.breakpoints(q), vec![-0.4, 0.4]);
    }
}
