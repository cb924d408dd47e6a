//! The crack–uplift fixed point: the crack open at the heel that the uplift fills, and its
//! search.

use super::{ContactError, ContactProblem, Stage};
use crate::solve::{newton, NewtonOptions};

/// The crack open at the heel that the uplift fills, found by a fixed point ([`settle_crack`]):
/// solve with the crack s_c, measure the open length at the heel, and solve again until it
/// moves by at most [`Crack::TOLERANCE`] of the joint length, or a bisection brackets it that
/// closely.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Crack {
    /// s_c \[m\].
    pub length: f64,
    /// Solves of the iteration, the first included.
    pub iterations: usize,
    /// |s_c − the open length of the last solve| \[m\].
    pub change: f64,
    /// The last cracks below and above the fixed point (the open length was larger, and
    /// smaller, than the crack solved with), once both were seen \[m\].
    pub bracket: Option<[f64; 2]>,
    /// Whether the crack stops at the drain line, where the diagram jumps: with the drains
    /// counted the joint opens past them, without them it closes short of them, so no crack
    /// is a fixed point. The drains are then taken as reached (EM 1110-2-2100's T ≥ X: s_c =
    /// X, the larger uplift), and `change` is X − the open length without them.
    pub at_drains: bool,
}

/// The crack of each uplift diagram of a joint, in order (None where the crack is not filled).
pub type Cracks = Vec<Option<Crack>>;

impl Crack {
    pub const TOLERANCE: f64 = 1e-6;
    pub const MAX_ITERATIONS: usize = 40;
}

/// The crack–uplift fixed point at the δ of `contact` (docs/method.md §1.8), from the solution
/// `x` with its current cracks, one s_c per uplift diagram whose crack is filled, settled
/// together. With g(s_c) = open − s_c, the open length at the diagram's heel of the solution
/// less the crack it was solved with: s_c ← open at first, then the secant step
/// s_c − g (s_c − s_prev)/(g − g_prev) while g keeps its sign (the plain update creeps when
/// the open length follows the crack closely), moving s_c by at most 2^(k − 1) |g| after k
/// updates of one sign (the secant's root may lie far beyond the fixed point, where the joint
/// has no equilibrium), and once g has taken both signs, inside the
/// bracket of the last crack of each sign: that secant step where the last two cracks lie on
/// one side and it stays inside (false position from the far end creeps where g bends at its
/// root), else false position, or the midpoint where the bracket has not halved since the last
/// false position (safeguarded bisection: the open length may jump across the fixed point); a
/// bracket that closes on the drain line solves once just short of it. Every diagram not yet
/// settled is updated so, then Newton solves again from the last solution, until each has
/// |g| ≤ [`Crack::TOLERANCE`] L or its bracket that narrow. A crack that moves clears the
/// brackets of the others: their g changes with it.
/// Returns the solution and the crack of each diagram (None where it is not filled); the
/// Newton stages of the new solves (none if `x` already settles them) go to `stages`, those
/// of a search that fails too.
pub fn settle_crack(
    contact: &mut ContactProblem,
    x: Vec<f64>,
    options: &NewtonOptions,
    stages: &mut Vec<Stage>,
) -> Result<(Vec<f64>, Cracks), ContactError> {
    settle_crack_to(contact, x, options, Crack::TOLERANCE, stages)
}

/// [`settle_crack`] to |g| ≤ `tolerance` L.
pub fn settle_crack_to(
    contact: &mut ContactProblem,
    mut x: Vec<f64>,
    options: &NewtonOptions,
    tolerance: f64,
    stages: &mut Vec<Stage>,
) -> Result<(Vec<f64>, Cracks), ContactError> {
    let mut searches: Vec<CrackSearch> = (contact.nitsche.uplift.iter())
        .map(|up| CrackSearch { tolerance, drains: up.diagram.drains.map(|d| d.distance), ..Default::default() })
        .collect();
    for iterations in 1..=Crack::MAX_ITERATIONS {
        let open = contact.crack_lengths(&x);
        let mut cracks = vec![None; searches.len()];
        let mut next = vec![None; searches.len()];
        for (d, search) in searches.iter_mut().enumerate() {
            let up = &contact.nitsche.uplift[d].diagram;
            if !up.rule.follows_crack() {
                continue;
            }
            match search.record(up.crack, open[d], up.line.length) {
                Ok(bracket) => {
                    let (length, change) = (up.crack, (open[d] - up.crack).abs());
                    let at_drains = search.closes_on_drains() == Some(up.crack);
                    let face = contact.face_length_at(d, length);
                    if change > face && !at_drains {
                        return Err(ContactError::CrackJump { length, change, face });
                    }
                    cracks[d] = Some(Crack { length, iterations, change, bracket, at_drains });
                }
                Err(_) if iterations == Crack::MAX_ITERATIONS => {
                    return Err(ContactError::Crack { iterations, length: open[d], change: (open[d] - up.crack).abs() })
                }
                Err(s) => next[d] = Some(s),
            }
        }
        if next.iter().all(Option::is_none) {
            return Ok((x, cracks));
        }
        // a crack that moves changes the open length of the others: the signs of g they
        // recorded before no longer bracket their fixed point
        let moved: Vec<bool> = (next.iter().zip(&contact.nitsche.uplift))
            .map(|(s, up)| s.is_some_and(|s| s != up.diagram.crack))
            .collect();
        for (d, search) in searches.iter_mut().enumerate() {
            if moved.iter().enumerate().any(|(other, &m)| m && other != d) {
                (search.below, search.above, search.width, search.probed) = (None, None, None, false);
            }
        }
        for (up, s) in contact.nitsche.uplift.iter_mut().zip(next) {
            up.diagram.crack = s.unwrap_or(up.diagram.crack);
        }
        let report = newton(contact, x, options)?;
        x = report.x.clone();
        stages.push(Stage { delta: contact.smoothing.delta, report });
    }
    unreachable!("the loop returns by its last iteration")
}

/// The search of one diagram's crack in [`settle_crack_to`].
#[derive(Debug, Clone, Copy, Default)]
struct CrackSearch {
    /// The last crack with g > 0 and the last with g < 0, each with its g.
    below: Option<(f64, f64)>,
    above: Option<(f64, f64)>,
    /// The width of the bracket at the last false-position step (None: none yet).
    width: Option<f64>,
    /// The last crack updated and its g.
    previous: Option<(f64, f64)>,
    /// The search stops at |g| ≤ tolerance L.
    tolerance: f64,
    /// The drain line s_d, where the diagram jumps as the crack reaches it.
    drains: Option<f64>,
    /// Whether the crack just short of the drains was solved since the bracket was last cleared.
    probed: bool,
    /// The updates in a row whose g kept the sign of the one before.
    kept_sign: i32,
}

impl CrackSearch {
    /// Records g = open − s_c for the crack s_c of a joint of length `length`. Ok(the bracket)
    /// once settled; Err(the next crack) otherwise. A bracket around the drain line is first
    /// cut there; one that closes on it from below is settled at s_c = s_d ([`Crack::at_drains`]).
    fn record(&mut self, crack: f64, open: f64, length: f64) -> Result<Option<[f64; 2]>, f64> {
        let (g, tolerance) = (open - crack, self.tolerance * length);
        *(if g > 0.0 { &mut self.below } else { &mut self.above }) = Some((crack, g));
        let bracket = self.below.zip(self.above).map(|((a, _), (b, _))| [a.min(b), a.max(b)]);
        if g.abs() <= tolerance {
            return Ok(bracket);
        }
        if bracket.is_some_and(|[a, b]| b - a <= tolerance) {
            return match self.closes_on_drains() {
                Some(s_d) if crack != s_d => Err(s_d),
                _ => Ok(bracket),
            };
        }
        // a bracket from a crack with g > 0 to the drains with g < 0: one solve just short of
        // the drains tells whether the joint opens past them there (the crack stops at them)
        // before a bisection narrows the bracket down to the tolerance
        if let Some(s_d) = self.closes_on_drains().filter(|_| !self.probed) {
            self.probed = true;
            return Err(s_d - 0.5 * tolerance);
        }
        if let Some(s_d) = self.drains.filter(|&s_d| bracket.is_some_and(|[a, b]| a < s_d && s_d < b)) {
            return Err(s_d);
        }
        // the secant step only where it moves s_c the way g points: where |g| grows with the
        // crack (the crack feeds itself) it points back, to cracks whose g has the same sign
        let same_side = self.previous.is_some_and(|(_, g_prev)| (g_prev > 0.0) == (g > 0.0));
        self.kept_sign = if same_side { self.kept_sign + 1 } else { 0 };
        let secant = self
            .previous
            .filter(|&(_, g_prev)| g_prev != g)
            .map(|(s, g_prev)| crack - g * (crack - s) / (g - g_prev))
            .filter(|s| s.is_finite() && (s - crack) * g > 0.0);
        self.previous = Some((crack, g));
        Err(match bracket {
            // inside the bracket, the secant of two cracks on one side where it stays inside:
            // false position from a far end creeps where g bends at its root
            Some([a, b]) => secant.filter(|&s| same_side && a < s && s < b).unwrap_or_else(|| self.within()),
            None => secant
                .map(|s| crack + (s - crack).clamp(-self.reach(g), self.reach(g)))
                .unwrap_or(open)
                .clamp(0.0, length),
        })
    }

    /// How far the secant step may move s_c before a bracket: 2^(k − 1) |g| after k updates
    /// whose g kept its sign, so |g| (the plain update's step) at first. Where g falls slowly
    /// the secant's root lies far beyond the fixed point, where the joint may have no
    /// equilibrium (battery case 91: from 4.77 m to 23.7 m, the fixed point at 8.67 m); where
    /// it creeps, the reach doubles until the secant takes over.
    fn reach(&self, g: f64) -> f64 {
        2f64.powi(self.kept_sign - 1) * g.abs()
    }

    /// The next crack inside the bracket: false position
    /// s = a − g_a (b − a)/(g_b − g_a) on its ends a (g_a > 0) and b (g_b < 0) where the bracket
    /// has at least halved since the last such step, else its midpoint (the open length may jump
    /// across the fixed point, where false position creeps).
    fn within(&mut self) -> f64 {
        let ((a, g_a), (b, g_b)) = self.below.zip(self.above).expect("a bracket has both ends");
        let width = (b - a).abs();
        if self.width.is_none_or(|w| width <= 0.5 * w) {
            self.width = Some(width);
            return a - g_a * (b - a) / (g_b - g_a);
        }
        0.5 * (a + b)
    }

    /// The drain line s_d if the bracket closes on it from below: g > 0 short of it, g < 0 at it.
    fn closes_on_drains(&self) -> Option<f64> {
        let (below, above) = (self.below.map(|(s, _)| s), self.above.map(|(s, _)| s));
        self.drains.filter(|&s_d| above == Some(s_d) && below.is_some_and(|b| b < s_d))
    }
}

#[cfg(test)]
mod tests {
    use super::CrackSearch;

    // A crack that feeds itself. Source: the base of geo/dam_lifts_on_rock_uplift.toml under a
    // 55 m reservoir with its friction raised to 1.5 (docs/solver.md §8), whose open lengths
    // were 5.67 m with s_c = 0 and 17.53 m with s_c = 5.67 m. Goal: g = open − s_c grows with
    // s_c, so the secant through the two points has its root behind both (at −5.2 m); the next
    // crack must move the way g points (past the last crack, here the plain update s_c ← open),
    // not back to 0 (clamped), where g > 0 is already known and the search would stay.
    // Parameters: a joint of 40 m.
    #[test]
    fn a_crack_that_feeds_itself_grows() {
        let mut search = CrackSearch { tolerance: super::Crack::TOLERANCE, ..Default::default() };
        assert_eq!(search.record(0.0, 5.67, 40.0), Err(5.67));
        let next = search.record(5.67, 17.53, 40.0).unwrap_err();
        assert_eq!(next, 17.53, "the secant's root lies behind both cracks");
        // g falling towards 0 keeps the secant step: through (5.67, 11.86) and (17.53, 2.0)
        let next = search.record(17.53, 19.53, 40.0).unwrap_err();
        let secant = 17.53 - 2.0 * (17.53 - 5.67) / (2.0 - 11.86);
        assert!((next - secant).abs() < 1e-12 && next > 19.53, "{next} against {secant}");
    }

    // A crack whose g falls slowly. Source: battery case of seed 91 (`damfem::verify::battery`,
    // its coarse level at λ = 1), whose open lengths were 4.7718 m with s_c = 0, 8.5787 m with
    // s_c = 4.7718 m and 8.6870 m with s_c = 8.5787 m; the fixed point lies at 8.6708 m.
    // Goal: the secant through the first two points has its root at 23.7 m, where the joint
    // had no equilibrium; the search must move by at most |g| (the plain update) after one
    // update of g's sign, and take the secant once it fits in twice |g|.
    // Parameters: a joint of 44.88 m.
    #[test]
    fn a_crack_whose_g_falls_slowly_stays_within_reach() {
        let mut search = CrackSearch { tolerance: super::Crack::TOLERANCE, ..Default::default() };
        assert_eq!(search.record(0.0, 4.7718, 44.88), Err(4.7718));
        let next = search.record(4.7718, 8.5787, 44.88).unwrap_err();
        assert!((next - 8.5787).abs() < 1e-12, "{next}: the secant's root is at 23.7 m");
        let next = search.record(8.5787, 8.6870, 44.88).unwrap_err();
        let secant = 8.5787 - 0.1083 * (8.5787 - 4.7718) / (0.1083 - 3.8069);
        assert!((next - secant).abs() < 1e-9 && (next - 8.6708).abs() < 0.02, "{next} against {secant}");
    }

    // A crack that jumps at the drain line. Source: battery case of seed 63
    // (`damfem::verify::battery`, drains 2.87 m from the heel), whose open length was 3.05 m
    // for every crack short of the drains and 2.26 m for every crack past them. Goal: no crack
    // has g = 0; the search must settle at s_c = s_d (the drains reached, the larger uplift)
    // whichever side its bisection ends on, not on the side of its last solve, and without a
    // bisection down to the tolerance: in 6 solves (0, the open length, s_d, just short of
    // s_d, s_d again).
    // Parameters: a joint of 41.75 m.
    #[test]
    fn a_crack_that_jumps_at_the_drains_stops_there() {
        let s_d = 2.87;
        let open = |s: f64| if s < s_d { 3.05 } else { 2.26 };
        let mut search = CrackSearch { tolerance: super::Crack::TOLERANCE, drains: Some(s_d), ..Default::default() };
        let mut crack = 0.0;
        for solves in 1..=super::Crack::MAX_ITERATIONS {
            match search.record(crack, open(crack), 41.75) {
                Ok(_) => {
                    assert_eq!((crack, search.closes_on_drains()), (s_d, Some(s_d)));
                    assert!(solves <= 6, "{solves} solves");
                    return;
                }
                Err(next) => crack = next,
            }
        }
        panic!("the search did not settle: last crack {crack}");
    }
}
