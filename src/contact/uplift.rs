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

use super::line::JointLine;
use crate::geometry::Point;

/// Drains in the joint: the distance s_d from the heel \[m\] and their efficiency E ∈ [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drains {
    pub distance: f64,
    pub efficiency: f64,
}

/// What the water does in the crack s_c open at the heel (docs/method.md §1.8).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CrackRule {
    /// `full` (static): the reservoir pressure H_u fills the crack, whose length the solve finds.
    Filled,
    /// `unchanged` (seismic) and `ignore` (s₀ = 0): the diagram of the crack s₀ of the state
    /// before the earthquake, whatever opens.
    Kept { prior: f64 },
    /// `none` (seismic): no pressure where the earthquake opens the joint beyond the crack s₀
    /// before it, on [s₀, s_c] (s_c found by the solve); elsewhere the diagram of s₀.
    Drained { prior: f64 },
}

impl CrackRule {
    /// Whether the pressure follows the crack of the solution (a fixed point to settle).
    pub fn follows_crack(&self) -> bool {
        !matches!(self, CrackRule::Kept { .. })
    }
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
    pub rule: CrackRule,
    /// The crack s_c \[m\] open from the heel (found by the solve where the rule follows it).
    pub crack: f64,
}

/// One linear piece of a diagram: p from `p[0]` at s = `s[0]` to `p[1]` at s = `s[1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Piece {
    s: [f64; 2],
    p: [f64; 2],
}

impl Uplift {
    /// The distance s from the heel of the point x of the joint.
    pub fn distance(&self, x: Point) -> f64 {
        self.line.distance(x)
    }

    /// p_u at the distance s from the heel, with the crack open to `crack` (0: none); at a
    /// jump (the tip of a drained crack) the value on the heel's side.
    pub fn pressure(&self, s: f64, crack: f64) -> f64 {
        Self::on(&self.pieces(crack), s)
    }

    /// The diagram as linear pieces from the heel to the toe, with the crack open to `crack`.
    fn pieces(&self, crack: f64) -> Vec<Piece> {
        let l = self.line.length;
        let crack = crack.clamp(0.0, l);
        match self.rule {
            CrackRule::Filled => self.filled(crack),
            CrackRule::Kept { prior } => self.filled(prior.clamp(0.0, l)),
            CrackRule::Drained { prior } => {
                let (prior, before) = (prior.clamp(0.0, l), self.filled(prior.clamp(0.0, l)));
                if crack <= prior {
                    return before;
                }
                let cut = |q: &Piece| {
                    let s0 = q.s[0].max(crack);
                    Piece { s: [s0, q.s[1]], p: [Self::on(&before, s0), q.p[1]] }
                };
                let mut pieces =
                    vec![Piece { s: [0.0, prior], p: [self.upstream; 2] }, Piece { s: [prior, crack], p: [0.0; 2] }];
                pieces.extend(before.iter().filter(|q| q.s[1] > crack).map(cut));
                pieces.retain(|q| q.s[1] > q.s[0]);
                pieces
            }
        }
    }

    /// The guideline's diagram with the reservoir pressure in the crack [0, c] (EM 1110-2-2100).
    fn filled(&self, c: f64) -> Vec<Piece> {
        let (h_u, h_d, l) = (self.upstream, self.downstream, self.line.length);
        let mut pieces = vec![Piece { s: [0.0, c], p: [h_u; 2] }];
        match self.drains.filter(|d| d.distance > c) {
            Some(d) => {
                let at_drains = h_d + (1.0 - d.efficiency) * (h_u - h_d) * (l - d.distance) / (l - c);
                pieces.push(Piece { s: [c, d.distance], p: [h_u, at_drains] });
                pieces.push(Piece { s: [d.distance, l], p: [at_drains, h_d] });
            }
            None => pieces.push(Piece { s: [c, l], p: [h_u, h_d] }),
        }
        pieces.retain(|q| q.s[1] > q.s[0]);
        pieces
    }

    /// The value of `pieces` at s (at a jump, the piece on the heel's side).
    fn on(pieces: &[Piece], s: f64) -> f64 {
        let q = pieces.iter().find(|q| s <= q.s[1]).or(pieces.last()).expect("a diagram has pieces");
        q.p[0] + (q.p[1] - q.p[0]) * ((s - q.s[0]) / (q.s[1] - q.s[0])).clamp(0.0, 1.0)
    }

    /// The distances from the heel where p_u has a kink or a jump: the crack tips and the drains.
    pub fn kinks(&self, crack: f64) -> Vec<f64> {
        let pieces = self.pieces(crack);
        pieces[1..].iter().map(|q| q.s[0]).collect()
    }

    /// The uplift force U = ∫ p_u ds \[N/m\] (exact: p_u is piecewise linear).
    pub fn force(&self, crack: f64) -> f64 {
        self.pieces(crack).iter().map(|q| 0.5 * (q.s[1] - q.s[0]) * (q.p[0] + q.p[1])).sum()
    }

    /// The first moment M_u = ∫ p_u s ds \[N\] about the heel (exact on each linear piece
    /// [s₀, s₁]: (s₁ − s₀)/6 (p₀ (2 s₀ + s₁) + p₁ (s₀ + 2 s₁))).
    pub fn moment(&self, crack: f64) -> f64 {
        let piece = |q: &Piece| {
            let ([s0, s1], [p0, p1]) = (q.s, q.p);
            (s1 - s0) / 6.0 * (p0 * (2.0 * s0 + s1) + p1 * (s0 + 2.0 * s1))
        };
        self.pieces(crack).iter().map(piece).sum()
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
            rule: CrackRule::Filled,
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

    #[test]
    fn the_seismic_rules_keep_the_diagram_before_and_drain_the_crack() {
        let drains = Some(Drains { distance: 5.0, efficiency: 2.0 / 3.0 });
        let before = joint(drains);
        let kept = Uplift { rule: CrackRule::Kept { prior: 10.0 }, ..joint(drains) };
        for crack in [0.0, 3.0, 30.0] {
            assert_eq!(kept.force(crack), before.force(10.0));
            assert_eq!(kept.pressure(25.0, crack), before.pressure(25.0, 10.0));
        }
        // opened to 10 m by the earthquake from 2 m before: full pressure on [0, 2], none on
        // [2, 10], then the diagram of 2 m
        let drained = Uplift { rule: CrackRule::Drained { prior: 2.0 }, ..joint(drains) };
        let p10 = before.pressure(10.0, 2.0);
        assert_eq!((drained.pressure(1.0, 10.0), drained.pressure(2.5, 10.0)), (700.0, 0.0));
        assert_eq!(drained.pressure(10.0, 10.0), 0.0);
        assert!((drained.pressure(10.0 + 1e-9, 10.0) - p10).abs() < 1e-6);
        assert_eq!(drained.pressure(20.0, 10.0), before.pressure(20.0, 2.0));
        assert!((drained.force(10.0) - 2.0 * 700.0 - 0.5 * 30.0 * (p10 + 100.0)).abs() < 1e-9);
        // ∫ p s ds of 700 on [0, 2] and of the line p10 → 100 on [10, 40]
        let moment = 700.0 * 2.0 + 30.0 / 6.0 * (p10 * 60.0 + 100.0 * 90.0);
        assert!((drained.moment(10.0) - moment).abs() < 1e-9 * moment);
        assert_eq!(drained.kinks(10.0), vec![2.0, 10.0]);
        // a crack within the one before: the diagram before
        assert_eq!(drained.force(1.0), before.force(2.0));
    }
}
