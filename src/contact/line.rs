//! The straight joint from its heel (the upstream end) to its toe, on which the uplift
//! diagram, the crack from the heel and the engineer's reading of the joint (`safety`) are
//! measured: s is the distance from the heel along it.

use crate::geometry::{distance, dot, sub, Point, Vector};
use serde::Serialize;

/// A straight joint from its heel (the upstream end) to its toe.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct JointLine {
    pub heel: Point,
    /// The unit vector from the heel to the toe.
    pub along: Vector,
    /// The joint length L \[m\].
    pub length: f64,
}

impl JointLine {
    /// The joint from `heel` to `toe`.
    pub fn new(heel: Point, toe: Point) -> Self {
        let (d, length) = (sub(toe, heel), distance(heel, toe));
        JointLine { heel, along: [d[0] / length, d[1] / length], length }
    }

    /// The distance s from the heel of the point x of the joint.
    pub fn distance(&self, x: Point) -> f64 {
        dot(sub(x, self.heel), self.along)
    }

    /// Whether the point x lies on the joint's line (to 10⁻⁹ of its length).
    pub fn holds(&self, x: Point) -> bool {
        let offset = (x[0] - self.heel[0]) * self.along[1] - (x[1] - self.heel[1]) * self.along[0];
        offset.abs() <= 1e-9 * self.length
    }

    /// The point at the distance s from the heel.
    pub fn point(&self, s: f64) -> Point {
        [self.heel[0] + s * self.along[0], self.heel[1] + s * self.along[1]]
    }
}
