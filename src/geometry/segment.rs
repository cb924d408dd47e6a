//! Straight segments: the boundary facets and cell edges of a mesh (also in reference
//! coordinates).

/// The segment from `a` to `b`, parametrised over [0, 1] by x(s) = a + s (b − a).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    pub a: [f64; 2],
    pub b: [f64; 2],
}

impl Segment {
    pub fn new(a: [f64; 2], b: [f64; 2]) -> Self {
        Self { a, b }
    }

    /// `x(s) = a + s (b − a)`.
    pub fn point(&self, s: f64) -> [f64; 2] {
        [self.a[0] + s * (self.b[0] - self.a[0]), self.a[1] + s * (self.b[1] - self.a[1])]
    }

    /// `|b − a|`.
    pub fn length(&self) -> f64 {
        (self.b[0] - self.a[0]).hypot(self.b[1] - self.a[1])
    }

    /// Unit tangent `t = (b − a) / |b − a|`.
    pub fn tangent(&self) -> [f64; 2] {
        let l = self.length();
        [(self.b[0] - self.a[0]) / l, (self.b[1] - self.a[1]) / l]
    }

    /// The unit normal (t_y, −t_x): the tangent turned clockwise.
    pub fn normal(&self) -> [f64; 2] {
        let t = self.tangent();
        [t[1], -t[0]]
    }

    /// Unit normal pointing away from `inside` (any point of the cell not on the segment,
    /// e.g. its centroid or opposite vertex): `(t_y, −t_x)`, flipped if needed. For an edge
    /// `vᵢ → vᵢ₊₁` of a counter-clockwise cell no flip occurs.
    pub fn outward_normal(&self, inside: [f64; 2]) -> [f64; 2] {
        let n = self.normal();
        let d = [inside[0] - self.a[0], inside[1] - self.a[1]];
        if n[0] * d[0] + n[1] * d[1] > 0.0 {
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
