//! Straight segments: the boundary facets and cell edges of a mesh (also in reference
//! coordinates).

use super::{distance, dot, sub, Point, Vector};

/// The segment from `a` to `b`, parametrised over [0, 1] by x(s) = a + s (b − a).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    pub a: Point,
    pub b: Point,
}

impl Segment {
    pub fn new(a: Point, b: Point) -> Self {
        Self { a, b }
    }

    /// `x(s) = a + s (b − a)`.
    pub fn point(&self, s: f64) -> Point {
        [self.a[0] + s * (self.b[0] - self.a[0]), self.a[1] + s * (self.b[1] - self.a[1])]
    }

    /// `|b − a|`.
    pub fn length(&self) -> f64 {
        distance(self.a, self.b)
    }

    /// Unit tangent `t = (b − a) / |b − a|`.
    pub fn tangent(&self) -> Vector {
        let (d, l) = (sub(self.b, self.a), self.length());
        [d[0] / l, d[1] / l]
    }

    /// The unit normal (t_y, −t_x): the tangent turned clockwise.
    pub fn normal(&self) -> Vector {
        let t = self.tangent();
        [t[1], -t[0]]
    }

    /// Unit normal pointing away from `inside` (any point of the cell not on the segment,
    /// e.g. its centroid or opposite vertex): `(t_y, −t_x)`, flipped if needed. For an edge
    /// `vᵢ → vᵢ₊₁` of a counter-clockwise cell no flip occurs.
    pub fn outward_normal(&self, inside: Point) -> Vector {
        let n = self.normal();
        if dot(n, sub(inside, self.a)) > 0.0 {
            [-n[0], -n[1]]
        } else {
            n
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_normal_points_out_of_ccw_cell() {
        let v = [[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]];
        let c = [2.0 / 3.0, 1.0 / 3.0];
        let n = Segment::new(v[0], v[1]).outward_normal(c);
        assert_eq!(n, [0.0, -1.0]);
        let n = Segment::new(v[1], v[0]).outward_normal(c);
        assert_eq!(n, [0.0, -1.0]);
        let s = Segment::new(v[1], v[2]);
        assert!((s.length() - 5f64.sqrt()).abs() < 1e-15);
        let n = s.outward_normal(v[0]);
        assert!((n[0] - 1.0 / 5f64.sqrt()).abs() < 1e-15 && n[1] > 0.0);
        assert_eq!(s.point(0.5), [1.0, 0.5]);
    }
}
