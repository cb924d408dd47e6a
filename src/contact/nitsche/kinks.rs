//! The quadrature of a contact face split where its integrand has a kink: at the roots of
//! P_γ(u_h) = b for every breakpoint b of the projection (and of the friction's threshold),
//! and at the uplift diagram's own kinks, so that each piece's Gauss rule is exact.

use super::{FaceDisplacement, Nitsche};
use crate::contact::projection::Smoothing;
use crate::fem::quadrature::gauss_segment_cached;

impl Nitsche {
    /// Quadrature on face k split at the kinks of `smoothing` ∘ P_γ(u_h) and, with friction,
    /// of Π_S(P^t_γ(u_h)): (s, weight·|F|).
    pub fn quadrature(&self, k: usize, u: &FaceDisplacement, smoothing: Smoothing) -> Vec<(f64, f64)> {
        self.split_rule(k, &self.kinks(k, u, smoothing))
    }

    /// The cuts of [`Nitsche::cuts`] at the breakpoints of `smoothing`, and with friction the
    /// parameters where S − P^t or P^t + S crosses a breakpoint, sorted. Between two normal
    /// cuts both are polynomials of degree ≤ 2p in s (S = −F q(P_γ) with q quadratic where
    /// P_γ is smoothed): fitted, split where they are monotone, and bisected, so that every
    /// crossing is found, two close together as well as one.
    pub fn kinks(&self, k: usize, u: &FaceDisplacement, smoothing: Smoothing) -> Vec<f64> {
        let mut cuts = self.cuts(k, u, &self.normal_law(k).breakpoints(smoothing));
        let levels = self.law(k).breakpoints(smoothing);
        if levels.is_empty() {
            return cuts;
        }
        let margins = |s: f64| {
            let point = self.point(k, s);
            let t = self.tangential(k, &point, u, smoothing);
            let p_t = self.p_tangential(k, &point, u);
            [t.threshold - p_t, p_t + t.threshold]
        };
        let mut tangential = Vec::new();
        for w in cuts.windows(2).filter(|w| w[1] > w[0]) {
            for side in 0..2 {
                for &level in &levels {
                    tangential.extend(sign_changes(|s| margins(s)[side] - level, 2 * self.order, w[0], w[1]));
                }
            }
        }
        cuts.extend(tangential);
        cuts.sort_by(f64::total_cmp);
        cuts
    }

    /// 0, 1, the kinks of the uplift and the parameters s ∈ (0, 1) where P_γ(u_h)(s) equals one
    /// of `levels`, sorted. Between the uplift's kinks P_γ is a polynomial of degree ≤ p.
    pub fn cuts(&self, k: usize, u: &FaceDisplacement, levels: &[f64]) -> Vec<f64> {
        let mut cuts = vec![0.0, 1.0];
        cuts.extend(self.uplift_kinks(k));
        cuts.sort_by(f64::total_cmp);
        let pieces: Vec<[f64; 2]> = cuts.windows(2).map(|w| [w[0], w[1]]).collect();
        for [a, b] in pieces {
            let p = |t: f64| self.p_gamma(k, &self.point(k, a + t * (b - a)), u);
            cuts.extend(crossings(p, levels).into_iter().map(|t| a + t * (b - a)));
        }
        cuts.sort_by(f64::total_cmp);
        cuts
    }

    /// The parameters s ∈ (0, 1) of face k where the uplift has a kink (crack tip, drains).
    fn uplift_kinks(&self, k: usize) -> Vec<f64> {
        let Some(up) = self.diagram(k) else { return Vec::new() };
        let face = &self.faces[k];
        let [d0, d1] = face.ends.map(|xi| up.distance(face.map.to_physical(xi)));
        up.kinks(up.crack).into_iter().map(|s| (s - d0) / (d1 - d0)).filter(|t| *t > 0.0 && *t < 1.0).collect()
    }

    /// The Gauss rule of [`JointLaw::face_points`](crate::contact::JointLaw::face_points) on each piece between consecutive `cuts`:
    /// (s, weight·|F|).
    pub fn split_rule(&self, k: usize, cuts: &[f64]) -> Vec<(f64, f64)> {
        let length = self.faces[k].length;
        let rule = gauss_segment_cached(self.law(k).face_points(self.order));
        cuts.windows(2)
            .filter(|w| w[1] > w[0])
            .flat_map(|w| {
                rule.points
                    .iter()
                    .zip(&rule.weights)
                    .map(move |(&s, &ws)| (w[0] + s * (w[1] - w[0]), ws * (w[1] - w[0]) * length))
            })
            .collect()
    }
}

/// The parameters s ∈ (0, 1) where a polynomial P of degree ≤ 2 equals one of `levels`, from
/// P(s) = a s² + b s + c fitted through P(0), P(½), P(1) (exact for degree ≤ 2).
pub fn crossings(p: impl Fn(f64) -> f64, levels: &[f64]) -> Vec<f64> {
    let (p0, pm, p1) = (p(0.0), p(0.5), p(1.0));
    let (a, b, c) = (2.0 * p1 + 2.0 * p0 - 4.0 * pm, 4.0 * pm - 3.0 * p0 - p1, p0);
    levels.iter().flat_map(|t| roots_in_unit_interval(a, b, c - t)).collect()
}

/// The points of (a, b) where `f`, a polynomial of degree ≤ n, changes sign. Its fit through
/// n + 1 equispaced values is monotone between the roots of the fit's derivative ([`roots`]),
/// so each of those pieces holds at most one sign change, which is bisected on `f` itself to
/// round-off: two roots close together are found as well as one.
fn sign_changes(f: impl Fn(f64) -> f64, n: usize, a: f64, b: f64) -> Vec<f64> {
    let at = |t: f64| a + t * (b - a);
    let fit = interpolate(&(0..=n).map(|j| f(at(j as f64 / n as f64))).collect::<Vec<_>>());
    let mut ends = vec![0.0];
    ends.extend(roots(&derivative(&fit)));
    ends.push(1.0);
    let mut found = Vec::new();
    for w in ends.windows(2) {
        let (f_lo, f_hi) = (f(at(w[0])), f(at(w[1])));
        if f_lo == 0.0 && w[0] > 0.0 {
            found.push(at(w[0]));
        }
        if f_lo * f_hi < 0.0 {
            found.push(at(bisect(|t| f(at(t)), w[0], w[1])));
        }
    }
    found
}

/// The coefficients c_k of c₀ + c₁ t + … + c_n t^n through the values at t = j/n, j = 0 … n.
fn interpolate(values: &[f64]) -> Vec<f64> {
    let n = values.len() - 1;
    if n == 0 {
        return values.to_vec();
    }
    let vandermonde = nalgebra::DMatrix::from_fn(n + 1, n + 1, |j, k| (j as f64 / n as f64).powi(k as i32));
    let lu = vandermonde.lu();
    lu.solve(&nalgebra::DVector::from_column_slice(values)).expect("distinct nodes").as_slice().to_vec()
}

fn derivative(c: &[f64]) -> Vec<f64> {
    c.iter().enumerate().skip(1).map(|(k, ck)| k as f64 * ck).collect()
}

/// c₀ + c₁ t + … + c_n t^n by Horner's rule.
fn horner(c: &[f64], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, ck| acc * t + ck)
}

/// The sign changes in (0, 1) of the polynomial c, sorted: between consecutive roots of its
/// derivative (found recursively) it is monotone, and each sign change there is bisected.
fn roots(c: &[f64]) -> Vec<f64> {
    if c.len() <= 1 {
        return Vec::new();
    }
    let mut ends = vec![0.0];
    ends.extend(roots(&derivative(c)));
    ends.push(1.0);
    ends.windows(2)
        .filter(|w| horner(c, w[0]) * horner(c, w[1]) < 0.0)
        .map(|w| bisect(|t| horner(c, t), w[0], w[1]))
        .collect()
}

/// The sign change of the continuous `f` in (lo, hi), f(lo) f(hi) < 0, bisected to round-off.
fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let negative_at_lo = f(lo) < 0.0;
    while hi - lo > 4.0 * f64::EPSILON * hi.abs().max(1.0) {
        let mid = 0.5 * (lo + hi);
        if (f(mid) < 0.0) == negative_at_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Roots in (0, 1) of a s² + b s + c, by the cancellation-free quadratic formula; a nearly
/// vanishing a (relative to b and c) is treated as linear.
fn roots_in_unit_interval(a: f64, b: f64, c: f64) -> Vec<f64> {
    let inside = |s: &f64| *s > 0.0 && *s < 1.0;
    let size = a.abs().max(b.abs()).max(c.abs());
    if size == 0.0 {
        return vec![];
    }
    if a.abs() <= 1e-12 * size {
        return if b != 0.0 { vec![-c / b].into_iter().filter(inside).collect() } else { vec![] };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return vec![];
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let mut roots = vec![q / a];
    if q != 0.0 {
        roots.push(c / q);
    }
    roots.into_iter().filter(inside).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_roots() {
        // (s − 0.25)(s − 0.6) = s² − 0.85 s + 0.15
        let mut r = roots_in_unit_interval(1.0, -0.85, 0.15);
        r.sort_by(f64::total_cmp);
        assert!((r[0] - 0.25).abs() < 1e-15 && (r[1] - 0.6).abs() < 1e-15);
        assert_eq!(roots_in_unit_interval(0.0, 2.0, -1.0), vec![0.5]);
        assert!(roots_in_unit_interval(1.0, 0.0, 1.0).is_empty());
    }

    /// Source: docs/method.md §1.6 (faces split at every kink). Goal: the crossings of a
    /// polynomial of degree ≤ 4 are all found, also two within one eighth of the interval (a
    /// Coulomb margin S − P^t that dips past a breakpoint and back, missed by brackets on
    /// eight sub-intervals). Parameters: (s − 0.906)(s − 0.927) on (0, 1) and on (0.5, 1),
    /// and (s − 0.1)(s − 0.11)(s − 0.6)(s − 0.95) on (0, 1).
    #[test]
    fn close_crossings_are_found() {
        let close = |s: f64| (s - 0.906) * (s - 0.927);
        for (a, n) in [(0.0, 2), (0.5, 2), (0.0, 4)] {
            let found = sign_changes(close, n, a, 1.0);
            assert_eq!(found.len(), 2, "{found:?}");
            assert!((found[0] - 0.906).abs() < 1e-14 && (found[1] - 0.927).abs() < 1e-14, "{found:?}");
        }
        let quartic = |s: f64| (s - 0.1) * (s - 0.11) * (s - 0.6) * (s - 0.95);
        let found = sign_changes(quartic, 4, 0.0, 1.0);
        assert_eq!(found.len(), 4, "{found:?}");
        for (s, r) in found.iter().zip([0.1, 0.11, 0.6, 0.95]) {
            assert!((s - r).abs() < 1e-14, "{found:?}");
        }
    }
}
