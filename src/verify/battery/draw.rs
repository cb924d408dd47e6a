//! The draw of a case from its seed: the section, its loads and its strength.

use super::*;
use crate::verify::rng::Rng;

/// `v` rounded to `digits` decimals.
fn round(v: f64, digits: i32) -> f64 {
    let scale = 10f64.powi(digits);
    (v * scale).round() / scale
}

/// A uniform draw in [low, high), rounded to `digits` decimals.
fn draw(rng: &mut Rng, low: f64, high: f64, digits: i32) -> f64 {
    round(low + (high - low) * rng.uniform(), digits)
}

impl DamCase {
    /// The case of `seed`: case i of a battery of seed S is the case of seed S + i.
    pub fn new(seed: u64) -> DamCase {
        let mut rng = Rng::new(seed);
        let holds = rng.uniform() >= FAILING_SHARE;
        loop {
            let mut case = DamCase::geometry(seed, &mut rng);
            case.loads(&mut rng);
            if case.strength(&mut rng, holds) {
                return case;
            }
        }
    }

    /// The section, the foundation and the degree, before loads and strength.
    fn geometry(seed: u64, rng: &mut Rng) -> DamCase {
        let height = draw(rng, 20.0, 120.0, 1);
        let batter = (rng.uniform() < 0.4)
            .then(|| Batter { slope: draw(rng, 0.05, 0.2, 2), height: draw(rng, 0.2 * height, 0.5 * height, 2) });
        let foundation = if rng.uniform() < 0.4 {
            Foundation::Rock { ratio: round(draw(rng, 0.1f64.ln(), 3f64.ln(), 6).exp(), 3) }
        } else {
            Foundation::Rigid
        };
        let mut case = DamCase {
            seed,
            height,
            crest: draw(rng, 0.08 * height, 0.15 * height, 2),
            slope: draw(rng, 0.6, 0.9, 2),
            batter,
            gallery: None,
            base_angle: draw(rng, -5.0, 6.0, 1).to_radians(),
            foundation,
            friction: 0.0,
            cohesion: 0.0,
            bond: None,
            reservoir: 0.0,
            tailwater: None,
            drains: None,
            crack: Crack::Ignore,
            acceleration: 0.0,
            order: 1 + (rng.uniform() < 0.5) as usize,
        };
        if rng.uniform() < 0.4 {
            case.gallery = case.fitting_gallery(draw(rng, 2.0, 3.5, 1), draw(rng, 2.5, 4.0, 1));
        }
        case
    }

    /// A gallery of `width` × `height` 2.5 m from the upstream face and above the base, if it
    /// fits 2.5 m inside the downstream face and below mid-height.
    fn fitting_gallery(&self, width: f64, height: f64) -> Option<Gallery> {
        let x = self.upstream_x() + 2.5;
        let y = (x + width) * self.base_angle.tan().max(0.0) + 2.5;
        let downstream = self.toe()[0] - self.slope * (y + height - self.toe()[1]);
        (x + width + 2.5 <= downstream && y + height <= 0.5 * self.height).then_some(Gallery {
            corner: [x, y],
            width,
            height,
        })
    }

    /// The reservoir, the tailwater, the uplift rule and the acceleration.
    fn loads(&mut self, rng: &mut Rng) {
        let h = self.height;
        self.reservoir = draw(rng, 0.7 * h, h, 2);
        let toe = self.toe()[1];
        self.tailwater = (rng.uniform() < 0.4).then(|| round(toe + draw(rng, 0.05 * h, 0.25 * h, 2), 2));
        self.drains = (rng.uniform() < 0.5).then(|| Drains {
            distance: match self.gallery {
                Some(g) => round((g.corner[0] + 0.5 * g.width) / self.base_angle.cos(), 2),
                None => draw(rng, 0.05 * self.length(), 0.15 * self.length(), 2),
            },
            efficiency: draw(rng, 0.3, 0.8, 2),
        });
        self.crack = if rng.uniform() < 0.5 { Crack::Full } else { Crack::Ignore };
        self.acceleration = if rng.uniform() < 0.5 { 0.0 } else { draw(rng, 0.01, 0.2, 3) };
    }

    /// Draws φ ∈ [30°, 55°] and c so that the case holds (FS ≥ 1.1 by friction alone) or not
    /// (FS ≤ 0.9 with c on the whole base), N > 0 and the effective resultant lies near the
    /// middle of the base; false if none can.
    fn strength(&mut self, rng: &mut Rng, holds: bool) -> bool {
        let s = self.statics();
        let reach = if self.crack == Crack::Full { 1.0 / 6.0 } else { 1.0 / 3.0 };
        if s.normal <= 0.0 || (s.position - 0.5 * s.length).abs() > reach * s.length {
            return false;
        }
        self.cohesion = if rng.uniform() < 0.2 { draw(rng, 50.0, 500.0, 0) * 1e3 } else { 0.0 };
        let (low, high) = (30f64.to_radians().tan(), 55f64.to_radians().tan());
        let shear = s.tangential.abs();
        let (low, high) = match holds {
            true => (low.max(HOLDING_MARGIN * shear / s.normal), high),
            false => (low, high.min((FAILING_MARGIN * shear - self.cohesion * s.length) / s.normal)),
        };
        if low >= high {
            return false;
        }
        let phi = draw(rng, low.atan().to_degrees(), high.atan().to_degrees(), 3);
        self.friction = round(phi.to_radians().tan(), 4).clamp(low, high);
        true
    }
}

/// The cases of seeds `seed`, …, `seed + count − 1`.
pub fn cases(seed: u64, count: usize) -> Vec<DamCase> {
    (0..count as u64).map(|i| DamCase::new(seed.wrapping_add(i))).collect()
}
