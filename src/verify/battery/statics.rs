//! The section's statics: its outline, the water on its faces, the uplift diagram and the
//! exact N, T and s_N of the module's doc.

use super::*;
use crate::geometry::{distance, sub, Point, Vector};

/// γ_w.
pub(super) fn gamma_w() -> f64 {
    RHO_WATER * GRAVITY
}

/// a × b, the z component.
fn cross(a: Vector, b: Vector) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// The water on the segment p → q of a counter-clockwise outline, of outward normal
/// n = (q − p)^⊥ / |q − p|: the force −∫ γ_w (level − y)₊ n ds and its moment about the origin.
pub(super) fn water(p: Point, q: Point, level: f64) -> (Vector, f64) {
    let (d, length) = (sub(q, p), distance(p, q));
    let n = [d[1] / length, -d[0] / length];
    let point = |t: f64| [p[0] + t * d[0], p[1] + t * d[1]];
    let pressure = |t: f64| gamma_w() * (level - point(t)[1]).max(0.0);
    // the wet part t ∈ [t0, t1], where y(t) ≤ level
    let crossing = if d[1] == 0.0 { None } else { Some(((level - p[1]) / d[1]).clamp(0.0, 1.0)) };
    let (t0, t1) = match crossing {
        None => (0.0, 1.0),
        Some(t) if d[1] > 0.0 => (0.0, t),
        Some(t) => (t, 1.0),
    };
    let force = 0.5 * (t1 - t0) * length * (pressure(t0) + pressure(t1));
    let arm = |t: f64| pressure(t) * cross(point(t), n);
    let moment = -(t1 - t0) * length / 6.0 * (arm(t0) + 4.0 * arm(0.5 * (t0 + t1)) + arm(t1));
    ([-force * n[0], -force * n[1]], moment)
}

/// Area and centroid of a polygon (either orientation: the area is signed).
pub(super) fn area_centroid(outline: &[Point]) -> (f64, Point) {
    let (mut area, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for (i, &p) in outline.iter().enumerate() {
        let q = outline[(i + 1) % outline.len()];
        let w = cross(p, q);
        area += 0.5 * w;
        cx += (p[0] + q[0]) * w / 6.0;
        cy += (p[1] + q[1]) * w / 6.0;
    }
    (area, [cx / area, cy / area])
}

impl DamCase {
    /// x_u, the upstream face above the batter.
    pub(super) fn upstream_x(&self) -> f64 {
        self.batter.map_or(0.0, |b| b.slope * b.height)
    }

    /// The toe (B, B tan β).
    pub fn toe(&self) -> Point {
        let t = self.base_angle.tan();
        let b = (self.upstream_x() + self.crest + self.slope * self.height) / (1.0 + self.slope * t);
        [b, b * t]
    }

    /// L = B / cos β.
    pub fn length(&self) -> f64 {
        self.toe()[0] / self.base_angle.cos()
    }

    /// The outline counter-clockwise from the heel: heel, toe, the crest's downstream and
    /// upstream corners, and the batter's top.
    pub fn outline(&self) -> Vec<Point> {
        let (xu, h) = (self.upstream_x(), self.height);
        let mut outline = vec![[0.0, 0.0], self.toe(), [xu + self.crest, h], [xu, h]];
        outline.extend(self.batter.map(|b| [xu, b.height]));
        outline
    }

    /// The gallery's corners, counter-clockwise.
    pub(super) fn gallery_outline(g: &Gallery) -> [Point; 4] {
        let [x, y] = g.corner;
        [[x, y], [x + g.width, y], [x + g.width, y + g.height], [x, y + g.height]]
    }

    /// The load resultant R on the dam body and its moment M about the heel.
    fn loads_resultant(&self) -> (Vector, f64) {
        let outline = self.outline();
        let (area, centroid) = area_centroid(&outline);
        let hole = self.gallery.map(|g| area_centroid(&DamCase::gallery_outline(&g)));
        let (a, c) = match hole {
            Some((ag, cg)) => (
                area - ag,
                [(area * centroid[0] - ag * cg[0]) / (area - ag), (area * centroid[1] - ag * cg[1]) / (area - ag)],
            ),
            None => (area, centroid),
        };
        let weight = RHO_CONCRETE * GRAVITY * a;
        let body = [self.acceleration * weight, -weight];
        let (mut r, mut m) = (body, cross(c, body));
        // the upstream face from the crest down to the heel, the downstream face toe → crest
        let n = outline.len();
        let upstream = (3..n).map(|i| (outline[i], outline[(i + 1) % n], self.reservoir));
        let wet = upstream.chain(self.tailwater.map(|t| (outline[1], outline[2], t)));
        for (p, q, level) in wet {
            let (f, mf) = water(p, q, level);
            r = [r[0] + f[0], r[1] + f[1]];
            m += mf;
        }
        (r, m)
    }

    /// U and M_u = ∫ p_u s ds of the uplift with the crack s_c filled (0: none): the head h₁
    /// on [0, s_c], then linear to h₃ = h₂ + (1 − E)(h₁ − h₂)(L − s_d)/(L − s_c) at drains
    /// beyond the crack, and linear to h₂ at the toe.
    pub fn uplift(&self, crack: f64) -> (f64, f64) {
        let l = self.length();
        let h1 = self.reservoir.max(0.0);
        let h2 = self.tailwater.map_or(0.0, |t| (t - self.toe()[1]).max(0.0));
        let mut nodes = vec![(0.0, h1)];
        if crack > 0.0 {
            nodes.push((crack, h1));
        }
        if let Some(d) = self.drains.filter(|d| d.distance > crack) {
            nodes.push((d.distance, h2 + (1.0 - d.efficiency) * (h1 - h2) * (l - d.distance) / (l - crack)));
        }
        nodes.push((l, h2));
        let pieces = nodes.windows(2).map(|w| (w[0], w[1]));
        let force = pieces.clone().map(|((s0, h0), (s1, h1))| 0.5 * (s1 - s0) * (h0 + h1)).sum::<f64>();
        let moment = pieces
            .map(|((s0, h0), (s1, h1))| (s1 - s0) / 6.0 * (h0 * (2.0 * s0 + s1) + h1 * (s0 + 2.0 * s1)))
            .sum::<f64>();
        (gamma_w() * force, gamma_w() * moment)
    }

    /// N, T, U, s_N and L of the module's formulas, the uplift without crack.
    pub fn statics(&self) -> Statics {
        let (r, m) = self.loads_resultant();
        let (u, mu) = self.uplift(0.0);
        let (sin, cos) = self.base_angle.sin_cos();
        let pressing = r[0] * sin - r[1] * cos;
        let normal = pressing - u;
        Statics {
            normal,
            tangential: -(r[0] * cos + r[1] * sin),
            uplift: u,
            pressing,
            moment: m,
            position: -(m + mu) / normal,
            length: self.length(),
        }
    }
}
