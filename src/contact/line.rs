//! The straight joint from its heel (the upstream end) to its toe, on which the uplift
//! diagram, the crack from the heel and the engineer's reading of the joint (`safety`) are
//! measured: s is the distance from the heel along it.

use crate::geometry::distance;
use serde::Serialize;

/// A straight joint from its heel (the upstream end) to its toe.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct JointLine {
    pub heel: [f64; 2],
    /// The unit vector from the heel to the toe.
    pub along: [f64; 2],
    /// The joint length L \[m\].
    pub length: f64,
}

impl JointLine {
    /// The joint from `heel` to `toe`.
    pub fn new(heel: [f64; 2], toe: [f64; 2]) -> Self {
        let length = distance(heel, toe);
        JointLine { heel, along: [(toe[0] - heel[0]) / length, (toe[1] - heel[1]) / length], length }
    }

    /// The distance s from the heel of the point x of the joint.
    pub fn distance(&self, x: [f64; 2]) -> f64 {
        (x[0] - self.heel[0]) * self.along[0] + (x[1] - self.heel[1]) * self.along[1]
    }

    /// Whether the point x lies on the joint's line (to 10⁻⁹ of its length).
    pub fn holds(&self, x: [f64; 2]) -> bool {
        let offset = (x[0] - self.heel[0]) * self.along[1] - (x[1] - self.heel[1]) * self.along[0];
        offset.abs() <= 1e-9 * self.length
    }

    /// The point at the distance s from the heel.
    pub fn point(&self, s: f64) -> [f64; 2] {
        [self.heel[0] + s * self.along[0], self.heel[1] + s * self.along[1]]
    }
}
