//! Uplift: the pore-water pressure p_u in the joint (docs/method.md §1.8).
//!
//! The diagrams are those of the US Army Corps of Engineers (EM 1110-2-2100, Stability Analysis
//! of Concrete Structures, 2005, §3-3 and Appendix C; EM 1110-2-2200, Gravity Dam Design, 1995),
//! which CADAM implements by default (Leclerc, Léger and Tinawi, CADAM User's Manual, 2001;
//! CADAM3D's help shows the USACE cases: drains without cracking, cracking not extending beyond
//! the drains, a crack extending beyond them). In their notation, along a base of length L from
//! the heel (x = 0) to the toe, with γ_w = ρ_w g, H1 the headwater and H2 the tailwater head
//! above the base, drains at x = X with effectiveness E (K = 1 − E) and a crack of length T open
//! from the heel, the uplift is γ_w times the head
//!
//! - no drains, no crack: linear from H1 at the heel to H2 at the toe;
//! - drains: linear from H1 to H3 = H2 + K (H1 − H2)(L − X)/L at the drain line, then linear to
//!   H2;
//! - a crack short of the drains (T < X): H1 on [0, T] (the reservoir fills the crack), then
//!   linear to H3 = H2 + K (H1 − H2)(L − X)/(L − T) at the drain line, then linear to H2;
//! - a crack that reaches the drains (T ≥ X), or a crack without drains: H1 on [0, T], then
//!   linear from H1 at T to H2 at the toe (the drains no longer count).
//!
//! Here s is the distance from the heel, s_d = X, s_c = T, E the efficiency, H_u = γ_w H1 =
//! ρ_w g (headwater − y_heel)₊ and H_d = γ_w H2 = ρ_w g (tailwater − y_toe)₊ (the two ends of a
//! straight, possibly inclined joint). The formulas are written here from the guideline's
//! description of its figures; tests/verification/uplift.rs checks damfem's values at the heel,
//! the drain line, the toe and between, for several X, E, tailwaters and cracks, against them,
//! coded independently (not against the figures themselves). Where damfem differs from the
//! guideline:
//!
//! - a drainage gallery above the tailwater: the guideline takes the gallery's floor in place
//!   of H2 in H3; damfem has no gallery elevation (its drains discharge at the tailwater);
//! - the crack: the guideline's T comes from beam theory (the length where the linear base
//!   pressure would be tensile), damfem's s_c is the open length of the elastic solution with
//!   the crack's own pressure (the fixed point of docs/method.md §1.8);
//! - other agencies' rules (the US Bureau of Reclamation's H2 + (H1 − H2)/3 at the drain line,
//!   without the factor (L − X)/L) are not offered.
//!
//! The pressure acts on the effective normal stress σ'^n = σ^n + p_u, which obeys the contact
//! conditions; the joint carries the total traction (σ'^n − p_u) ν + σ^t τ.

use super::resultant::JointLine;

/// Drains in the joint: the distance s_d from the heel \[m\] and their efficiency E ∈ [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drains {
    pub distance: f64,
    pub efficiency: f64,
}

/// The uplift diagram of a straight joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Uplift {
    /// The joint from its heel to its toe, of length L.
    pub line: JointLine,
    /// H_u and H_d \[Pa\].
    pub upstream: f64,
    pub downstream: f64,
    pub drains: Option<Drains>,
    /// Whether the reservoir pressure fills the open crack at the heel.
    pub crack_filled: bool,
    /// The crack s_c \[m\] open from the heel that the pressure fills (found by the solve).
    pub crack: f64,
}

impl Uplift {
    /// The distance s from the heel of the point x of the joint.
    pub fn distance(&self, x: [f64; 2]) -> f64 {
        self.line.distance(x)
    }

    /// p_u at the distance s from the heel, with the crack open to `crack` (0: none).
    pub fn pressure(&self, s: f64, crack: f64) -> f64 {
        let (h_u, h_d, l) = (self.upstream, self.downstream, self.line.length);
        let crack = if self.crack_filled { crack.clamp(0.0, l) } else { 0.0 };
        if s <= crack {
            return h_u;
        }
        let line = |s0: f64, p0: f64, s1: f64, p1: f64| p0 + (p1 - p0) * ((s - s0) / (s1 - s0)).clamp(0.0, 1.0);
        match self.drains.filter(|d| d.distance > crack) {
            Some(d) => {
                let at_drains = h_d + (1.0 - d.efficiency) * (h_u - h_d) * (l - d.distance) / (l - crack);
                if s <= d.distance {
                    line(crack, h_u, d.distance, at_drains)
                } else {
                    line(d.distance, at_drains, l, h_d)
                }
            }
            None => line(crack, h_u, l, h_d),
        }
    }

    /// The distances from the heel where p_u has a kink: the crack tip and the drains.
    pub fn kinks(&self, crack: f64) -> Vec<f64> {
        let crack = if self.crack_filled { crack } else { 0.0 };
        let mut kinks = vec![crack];
        kinks.extend(self.drains.map(|d| d.distance).filter(|&s| s > crack));
        kinks.retain(|&s| s > 0.0 && s < self.line.length);
        kinks
    }

    /// The uplift force U = ∫ p_u ds \[N/m\] (exact: p_u is piecewise linear).
    pub fn force(&self, crack: f64) -> f64 {
        let mut points = vec![0.0, self.line.length];
        points.extend(self.kinks(crack));
        points.sort_by(f64::total_cmp);
        points.windows(2).map(|w| 0.5 * (w[1] - w[0]) * (self.pressure(w[0], crack) + self.pressure(w[1], crack))).sum()
    }

    /// The first moment M_u = ∫ p_u s ds \[N\] about the heel (exact on each linear piece
    /// [s₀, s₁]: (s₁ − s₀)/6 (p₀ (2 s₀ + s₁) + p₁ (s₀ + 2 s₁))).
    pub fn moment(&self, crack: f64) -> f64 {
        let mut points = vec![0.0, self.line.length];
        points.extend(self.kinks(crack));
        points.sort_by(f64::total_cmp);
        let p = |s: f64| self.pressure(s, crack);
        points
            .windows(2)
            .map(|w| (w[1] - w[0]) / 6.0 * (p(w[0]) * (2.0 * w[0] + w[1]) + p(w[1]) * (w[0] + 2.0 * w[1])))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn joint(drains: Option<Drains>) -> Uplift {
        Uplift {
            line: JointLine { heel: [0.0, 0.0], along: [1.0, 0.0], length: 40.0 },
            upstream: 700.0,
            downstream: 100.0,
            drains,
            crack_filled: true,
            crack: 0.0,
        }
    }

    #[test]
    fn the_diagrams_join_their_corner_values() {
        let plain = joint(None);
        assert_eq!((plain.pressure(0.0, 0.0), plain.pressure(40.0, 0.0)), (700.0, 100.0));
        assert!((plain.pressure(10.0, 0.0) - 550.0).abs() < 1e-12);
        assert!((plain.force(0.0) - 0.5 * 40.0 * 800.0).abs() < 1e-9);
        // a trapezoid 700 → 100 over 40 m: ∫ p s ds = 40² (700/6 + 100/3)
        assert!((plain.moment(0.0) - 1600.0 * (700.0 / 6.0 + 100.0 / 3.0)).abs() < 1e-7);
        // drains at 5 m, 2/3 effective: 100 + (1/3)(600)(35/40) = 275 at the drains
        let drained = joint(Some(Drains { distance: 5.0, efficiency: 2.0 / 3.0 }));
        assert!((drained.pressure(5.0, 0.0) - 275.0).abs() < 1e-12);
        assert!((drained.pressure(2.5, 0.0) - 487.5).abs() < 1e-12);
        // a crack to 10 m past the drains: full pressure on the crack, then linear to the toe
        assert_eq!(drained.pressure(9.0, 10.0), 700.0);
        assert!((drained.pressure(25.0, 10.0) - 400.0).abs() < 1e-12);
        assert_eq!(drained.kinks(10.0), vec![10.0]);
        assert_eq!(drained.kinks(2.0), vec![2.0, 5.0]);
        // a crack short of the drains keeps them: 100 + (1/3)(600)(35/38) at 5 m
        assert!((drained.pressure(5.0, 2.0) - (100.0 + 200.0 * 35.0 / 38.0)).abs() < 1e-12);
    }
}
