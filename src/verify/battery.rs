//! A battery of random gravity-dam sections with exact limit-equilibrium references: the draw
//! of a case from a seed, its `.geo` and scene files, its run through the `damfem` binary, and
//! the comparison of the sliding safety factor FS_LE of `summary.json` with the section's
//! statics, computed here from the polygon alone.
//!
//! # The section
//!
//! In metres, x downstream and y up, the heel at the origin: height H (the crest at y = H),
//! crest width C, downstream slope m (H:1V), an optional upstream batter b (H:1V) from the heel
//! up to y_b, and a straight base inclined by β from the heel (0, 0) to the toe (B, B tan β)
//! (β > 0: the toe higher than the heel, the base rising downstream). Above y_b the upstream
//! face is vertical at x_u = b y_b; the downstream face is one line from the toe to the crest's
//! downstream corner (x_u + C, H), so B = (x_u + C + m H)/(1 + m tan β). An optional
//! rectangular gallery near the heel is a hole free of load. The foundation is rigid (the base
//! a curve of role contact) or a meshed rock block below (the base a joint between the two
//! bodies, the dam its slave side; the rock weightless, its bottom clamped, its sides on
//! rollers). The reservoir at H_w loads the upstream face (and the reservoir floor), the
//! tailwater T_w the downstream face (and the ground); the uplift diagram runs from the heel.
//!
//! # The reference
//!
//! With γ_w = ρ_w g the loads on the dam body are the weight with the pseudo-static inertia,
//! ρ g A (a, −1) at the centroid (A the section's area less the gallery's), and on each wet
//! face segment of outward normal n the water force −∫ γ_w (H − y)₊ n ds, H its level: the
//! pressure is linear on the wet part, so the trapezoid rule is exact for the force and
//! Simpson's rule for its moment. Their resultant is R, its moment about the heel M. The base
//! has length L = B / cos β, the outward normal ν = (sin β, −cos β) and the tangent
//! τ = (cos β, sin β) from the heel to the toe. The uplift without crack (US Army Corps of
//! Engineers, EM 1110-2-2100) is γ_w times a head of s, the distance from the heel, with
//! h₁ = (H_w)₊ at the heel and h₂ = (T_w − y_toe)₊ at the toe (0 without tailwater): linear from
//! h₁ to h₂; with drains at s_d of efficiency E, linear from h₁ to
//! h₃ = h₂ + (1 − E)(h₁ − h₂)(L − s_d)/L at s_d, then linear to h₂. With a crack s_c filled by
//! the reservoir, the head is h₁ on [0, s_c], then linear to
//! h₃ = h₂ + (1 − E)(h₁ − h₂)(L − s_d)/(L − s_c) at drains beyond the crack and on to h₂, or
//! linear from h₁ to h₂ when no drains lie beyond it. U = ∫ p_u ds and M_u = ∫ p_u s ds are
//! exact on the linear pieces. The joint pushes on the dam with
//! −(p_c + p_u) ν + t τ, so the body's equilibrium gives
//!
//!   N = R·ν − U,   T = −R·τ,   s_N = −(M + M_u)/N,
//!
//! N = ∫ p_c ds the effective normal force, T = ∫ t ds and s_N the distance from the heel at
//! which N acts. The exact sliding safety factor is
//!
//!   FS = (c L_c + F N)/|T|,
//!
//! F = tan φ, c the cohesion on the closed length L_c (that of damfem's result; L without one).
//! With the crack filled (`crack = "full"`) the uplift grows with the crack damfem finds: U is
//! then damfem's `uplift_force`, and FS checks N = R·ν − U against the solved N; without a
//! result, U is that without crack, its least value, and FS the largest the case can have.
//! A result with the crack filled is also checked against the diagram at damfem's own crack
//! s_c: its U against U(s_c), its s_R against s_N(s_c), and its open length against s_c (the
//! crack settled).
//! A case holds iff FS ≥ 1. Cases are drawn that hold with FS ≥ 1.1 by friction alone, or do
//! not hold with FS ≤ 0.9 with the cohesion on the whole base, N > 0, and the effective
//! resultant within L/3 of the middle of the base (L/6 with the crack filled, so that the crack
//! stays short).

use super::rng::Rng;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// Gravity \[m/s²\] and the densities of water and concrete \[kg/m³\].
const GRAVITY: f64 = 9.81;
const RHO_WATER: f64 = 1000.0;
const RHO_CONCRETE: f64 = 2400.0;
/// Young's modulus of the concrete \[Pa\] and the Poisson ratios.
const E_CONCRETE: f64 = 3.0e10;
const NU_CONCRETE: f64 = 0.2;
const NU_ROCK: f64 = 0.25;
/// The share of the cases drawn not to hold.
const FAILING_SHARE: f64 = 0.15;
/// The least FS of a case drawn to hold, the largest of one drawn not to.
const HOLDING_MARGIN: f64 = 1.1;
const FAILING_MARGIN: f64 = 0.9;
/// Cases whose exact FS lies within this relative distance of 1 may go either way.
pub const UNDECIDED: f64 = 0.02;
/// gmsh's size factor on the sizes of the `.geo` (H/12 in the dam, H/48 at the heel and the
/// toe) by element degree: a few thousand unknowns.
const SIZE_FACTOR: [f64; 2] = [0.5, 1.0];

/// Rectangular gallery: lower-left corner, width and height \[m\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gallery {
    pub corner: [f64; 2],
    pub width: f64,
    pub height: f64,
}

/// Upstream batter: slope b (H:1V) from the heel up to the height y_b \[m\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Batter {
    pub slope: f64,
    pub height: f64,
}

/// Drains at the distance s_d from the heel \[m\], with efficiency E.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drains {
    pub distance: f64,
    pub efficiency: f64,
}

/// What holds the dam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Foundation {
    /// A rigid foundation: the base is a curve of role contact.
    Rigid,
    /// A meshed rock block, E_rock = `ratio` E_concrete, joined to the dam along the base.
    Rock { ratio: f64 },
}

/// The uplift rule in the crack open at the heel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Crack {
    Ignore,
    Full,
}

impl Crack {
    pub fn name(&self) -> &'static str {
        match self {
            Crack::Ignore => "ignore",
            Crack::Full => "full",
        }
    }
}

/// One drawn case.
#[derive(Debug, Clone, PartialEq)]
pub struct DamCase {
    pub seed: u64,
    pub height: f64,
    pub crest: f64,
    /// Downstream slope m (H:1V).
    pub slope: f64,
    pub batter: Option<Batter>,
    pub gallery: Option<Gallery>,
    /// β \[rad\].
    pub base_angle: f64,
    pub foundation: Foundation,
    /// F = tan φ and c \[Pa\].
    pub friction: f64,
    pub cohesion: f64,
    /// H_w and T_w \[m\].
    pub reservoir: f64,
    pub tailwater: Option<f64>,
    pub drains: Option<Drains>,
    pub crack: Crack,
    /// Horizontal pseudo-static acceleration a \[g\].
    pub acceleration: f64,
    pub order: usize,
}

/// What the statics gives (N/m, N m/m, m): N, T, U without crack, R·ν, M, s_N and L.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Statics {
    pub normal: f64,
    pub tangential: f64,
    pub uplift: f64,
    pub pressing: f64,
    /// M, the loads' moment about the heel.
    pub moment: f64,
    pub position: f64,
    pub length: f64,
}

/// `v` rounded to `digits` decimals.
fn round(v: f64, digits: i32) -> f64 {
    let scale = 10f64.powi(digits);
    (v * scale).round() / scale
}

/// A uniform draw in [low, high), rounded to `digits` decimals.
fn draw(rng: &mut Rng, low: f64, high: f64, digits: i32) -> f64 {
    round(low + (high - low) * rng.uniform(), digits)
}

/// γ_w.
fn gamma_w() -> f64 {
    RHO_WATER * GRAVITY
}

/// a × b, the z component.
fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// The water on the segment p → q of a counter-clockwise outline, of outward normal
/// n = (q − p)^⊥ / |q − p|: the force −∫ γ_w (level − y)₊ n ds and its moment about the origin.
fn water(p: [f64; 2], q: [f64; 2], level: f64) -> ([f64; 2], f64) {
    let (d, length) = ([q[0] - p[0], q[1] - p[1]], (q[0] - p[0]).hypot(q[1] - p[1]));
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
fn area_centroid(outline: &[[f64; 2]]) -> (f64, [f64; 2]) {
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

    /// x_u, the upstream face above the batter.
    fn upstream_x(&self) -> f64 {
        self.batter.map_or(0.0, |b| b.slope * b.height)
    }

    /// The toe (B, B tan β).
    pub fn toe(&self) -> [f64; 2] {
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
    pub fn outline(&self) -> Vec<[f64; 2]> {
        let (xu, h) = (self.upstream_x(), self.height);
        let mut outline = vec![[0.0, 0.0], self.toe(), [xu + self.crest, h], [xu, h]];
        outline.extend(self.batter.map(|b| [xu, b.height]));
        outline
    }

    /// The gallery's corners, counter-clockwise.
    fn gallery_outline(g: &Gallery) -> [[f64; 2]; 4] {
        let [x, y] = g.corner;
        [[x, y], [x + g.width, y], [x + g.width, y + g.height], [x, y + g.height]]
    }

    /// The load resultant R on the dam body and its moment M about the heel.
    fn loads_resultant(&self) -> ([f64; 2], f64) {
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

    /// "rigid" or "rock".
    pub fn kind(&self) -> &'static str {
        match self.foundation {
            Foundation::Rigid => "rigid",
            Foundation::Rock { .. } => "rock",
        }
    }

    /// E_rock / E_concrete, if there is rock.
    pub fn rock_ratio(&self) -> Option<f64> {
        match self.foundation {
            Foundation::Rigid => None,
            Foundation::Rock { ratio } => Some(ratio),
        }
    }

    /// The `.geo` file.
    pub fn geo(&self) -> String {
        let h = self.height;
        let mut geo = format!(
            "// Battery case of seed {}: a gravity dam, plane strain, SI units.\nh = {};\nhb = {};\nhr = {};\n",
            self.seed,
            h / 12.0,
            h / 48.0,
            h / 4.0
        );
        let outline = self.outline();
        let sizes = ["hb", "hb", "h", "h", "h"];
        for (i, p) in outline.iter().enumerate() {
            writeln!(geo, "Point({}) = {{{}, {}, 0, {}}};", i + 1, p[0], p[1], sizes[i]).unwrap();
        }
        let n = outline.len();
        for i in 0..n {
            writeln!(geo, "Line({}) = {{{}, {}}};", i + 1, i + 1, (i + 1) % n + 1).unwrap();
        }
        let upstream = (4..=n).map(|i| i.to_string()).collect::<Vec<_>>().join(", ");
        let loops = (1..=n).map(|i| i.to_string()).collect::<Vec<_>>().join(", ");
        writeln!(geo, "Curve Loop(1) = {{{loops}}};").unwrap();
        let mut physical = format!(
            "Physical Curve(\"base\") = {{1}};\nPhysical Curve(\"downstream\") = {{2}};\n\
             Physical Curve(\"crest\") = {{3}};\nPhysical Curve(\"upstream\") = {{{upstream}}};\n"
        );
        match self.gallery {
            Some(g) => {
                let size = g.width.min(g.height) / 3.0;
                for (i, p) in DamCase::gallery_outline(&g).iter().enumerate() {
                    writeln!(geo, "Point({}) = {{{}, {}, 0, {size}}};", 11 + i, p[0], p[1]).unwrap();
                }
                for i in 0..4 {
                    writeln!(geo, "Line({}) = {{{}, {}}};", 11 + i, 11 + i, 11 + (i + 1) % 4).unwrap();
                }
                geo.push_str("Curve Loop(2) = {11, 12, 13, 14};\nPlane Surface(1) = {1, 2};\n");
                physical.push_str("Physical Curve(\"gallery\") = {11, 12, 13, 14};\n");
            }
            None => geo.push_str("Plane Surface(1) = {1};\n"),
        }
        physical.push_str("Physical Surface(\"concrete\") = {1};\n");
        if let Foundation::Rock { .. } = self.foundation {
            geo.push_str(&self.rock_geo());
            physical.push_str(
                "Physical Curve(\"reservoir_floor\") = {21};\nPhysical Curve(\"ground\") = {22};\n\
                 Physical Curve(\"rock_sides\") = {23, 25};\nPhysical Curve(\"rock_bottom\") = {24};\n\
                 Physical Surface(\"rock\") = {2};\n",
            );
        }
        geo + &physical
    }

    /// The rock block's points, lines and surface: extent B up- and downstream, depth B below
    /// the lower end of the base.
    fn rock_geo(&self) -> String {
        let toe = self.toe();
        let extent = toe[0];
        let bottom = toe[1].min(0.0) - extent;
        let points = [[-extent, 0.0], [toe[0] + extent, toe[1]], [toe[0] + extent, bottom], [-extent, bottom]];
        let mut geo = String::new();
        for (i, p) in points.iter().enumerate() {
            writeln!(geo, "Point({}) = {{{}, {}, 0, hr}};", 21 + i, p[0], p[1]).unwrap();
        }
        geo.push_str(
            "Line(21) = {21, 1};\nLine(22) = {2, 22};\nLine(23) = {22, 23};\nLine(24) = {23, 24};\n\
             Line(25) = {24, 21};\nCurve Loop(3) = {21, 1, 22, 23, 24, 25};\nPlane Surface(2) = {-3};\n",
        );
        geo
    }

    /// The scene file, its geometry `geometry` beside it.
    pub fn scene(&self, geometry: &str) -> String {
        let mut toml = format!(
            "# Battery case of seed {}.\ngeometry = {geometry:?}\n\n[mesh]\norder = {}\n\n\
             [materials.concrete]\nE = {E_CONCRETE:?}\nnu = {NU_CONCRETE:?}\nrho = {RHO_CONCRETE:?}\n\n",
            self.seed, self.order
        );
        if let Some(ratio) = self.rock_ratio() {
            toml += &format!("[materials.rock]\nE = {:?}\nnu = {NU_ROCK:?}\nrho = 0.0\n\n", ratio * E_CONCRETE);
        }
        // the reference has no hydrodynamic pressure
        toml += &format!(
            "[loads]\ngravity = {GRAVITY:?}\nacceleration = [{:?}, 0.0]\nwestergaard = false\n\n",
            self.acceleration
        );
        let hydrostatic = |curve: &str, level: f64| {
            format!("[boundary.{curve}]\nrole = \"neumann\"\nhydrostatic = {{ level = {level:?}, density = {RHO_WATER:?} }}\n\n")
        };
        let free = |curve: &str| format!("[boundary.{curve}]\nrole = \"free\"\n\n");
        let tailwater = |curve: &str| self.tailwater.map_or_else(|| free(curve), |t| hydrostatic(curve, t));
        toml += &hydrostatic("upstream", self.reservoir);
        toml += &tailwater("downstream");
        toml += &free("crest");
        if self.gallery.is_some() {
            toml += &free("gallery");
        }
        let mut law = format!("friction = {:?}\n", self.friction);
        if self.cohesion > 0.0 {
            law += &format!("cohesion = {:?}\n", self.cohesion);
        }
        toml += &match self.foundation {
            Foundation::Rigid => format!("[boundary.base]\nrole = \"contact\"\n\n[contact]\n{law}max_iter = 100\n\n"),
            Foundation::Rock { .. } => {
                hydrostatic("reservoir_floor", self.reservoir)
                    + &tailwater("ground")
                    + "[boundary.rock_bottom]\nrole = \"dirichlet\"\n\n\
                       [boundary.rock_sides]\nrole = \"dirichlet\"\nfix = \"x\"\n\n"
                    + &format!("[joints.base]\n{law}slave = \"concrete\"\n\n[contact]\nmax_iter = 100\n\n")
            }
        };
        toml += &format!("[uplift]\nheadwater = {:?}\n", self.reservoir);
        if let Some(t) = self.tailwater {
            toml += &format!("tailwater = {t:?}\n");
        }
        if let Some(d) = self.drains {
            toml += &format!("drains = {{ x = {:?}, efficiency = {:?} }}\n", d.distance, d.efficiency);
        }
        toml + &format!("crack = \"{}\"\nheel = [0.0, 0.0]\n", self.crack.name())
    }

    /// Writes `case.geo` and `case.toml` into `dir`; the scene's path.
    pub fn write(&self, dir: &Path) -> std::io::Result<PathBuf> {
        std::fs::create_dir_all(dir)?;
        std::fs::write(dir.join("case.geo"), self.geo())?;
        let scene = dir.join("case.toml");
        std::fs::write(&scene, self.scene("case.geo"))?;
        Ok(scene)
    }

    /// gmsh's size factor of this case's run.
    pub fn size_factor(&self) -> f64 {
        SIZE_FACTOR[self.order - 1]
    }
}

/// How a run of `damfem solve` ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Exit 0: a solution.
    Result,
    /// Exit 3, or exit 1 with "no equilibrium": the dam does not hold.
    Verdict,
    /// Exit 4: the solver failed.
    Failure,
    /// Any other exit.
    Error,
}

impl Outcome {
    pub fn name(&self) -> &'static str {
        match self {
            Outcome::Result => "result",
            Outcome::Verdict => "verdict",
            Outcome::Failure => "failure",
            Outcome::Error => "error",
        }
    }
}

/// What a run of `damfem solve` gave: its outcome, exit code, the message of a failed run,
/// and from `summary.json` the Newton steps (summed over the levels of nested iteration, and
/// the most on one mesh), FS_LE, N, T, U, the contact
/// length, the crack and the resultant's distance from the heel; the wall time \[s\].
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    pub outcome: Outcome,
    pub code: Option<i32>,
    pub message: String,
    pub newton_steps: Option<u64>,
    pub newton_steps_per_mesh: Option<u64>,
    pub safety_factor: Option<f64>,
    pub normal: Option<f64>,
    pub tangential: Option<f64>,
    pub uplift: Option<f64>,
    pub contact_length: Option<f64>,
    pub crack_length: Option<f64>,
    /// The crack s_c of the uplift diagram (`crack = "full"`), and whether it stopped at the
    /// drain line (`contact::Crack::at_drains`).
    pub diagram_crack: Option<f64>,
    pub at_drains: bool,
    pub position: Option<f64>,
    /// FS_SR's bracket \[held, failed\] (`--strength-reduction`).
    pub strength: Option<[f64; 2]>,
    pub seconds: f64,
}

/// `damfem solve <scene> -o <dir>/out --size-factor f` by the binary `damfem`, the case
/// written into `dir`.
pub fn run(damfem: &Path, case: &DamCase, dir: &Path) -> std::io::Result<Run> {
    run_with(damfem, case, dir, &[])
}

/// [`run`] with the flags `extra` too.
pub fn run_with(damfem: &Path, case: &DamCase, dir: &Path, extra: &[&str]) -> std::io::Result<Run> {
    let scene = case.write(dir)?;
    let out = dir.join("out");
    let start = Instant::now();
    let output = Command::new(damfem)
        .arg("solve")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .arg("--size-factor")
        .arg(case.size_factor().to_string())
        .args(extra)
        .output()?;
    let seconds = start.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&output.stderr);
    let code = output.status.code();
    let outcome = match code {
        Some(0) => Outcome::Result,
        Some(3) => Outcome::Verdict,
        Some(1) if stderr.contains("no equilibrium") => Outcome::Verdict,
        Some(4) => Outcome::Failure,
        _ => Outcome::Error,
    };
    let message = stderr
        .lines()
        .find(|l| l.starts_with("verdict:") || l.starts_with("error:"))
        .or_else(|| stderr.lines().last())
        .unwrap_or("")
        .to_string();
    let summary = match outcome {
        Outcome::Result => std::fs::read_to_string(out.join("summary.json")).ok(),
        _ => None,
    };
    let json: serde_json::Value = summary.and_then(|s| serde_json::from_str(&s).ok()).unwrap_or_default();
    let c = &json["contact"];
    let curve = &c["curves"][0];
    let either = |key: &str| c[key].as_f64().or_else(|| curve[key].as_f64());
    let coarse: Vec<u64> =
        c["coarse"].as_array().map_or(Vec::new(), |l| l.iter().filter_map(|s| s["newton_steps"].as_u64()).collect());
    let safety_factor = either("sliding_safety_factor");
    // a result without its safety factor is an error of the run
    let (outcome, message) = match (outcome, safety_factor) {
        (Outcome::Result, None) => (Outcome::Error, "exit 0 without sliding_safety_factor in summary.json".into()),
        _ => (outcome, message),
    };
    Ok(Run {
        outcome,
        code,
        message,
        newton_steps: c["newton_steps"].as_u64().map(|n| n + coarse.iter().sum::<u64>()),
        newton_steps_per_mesh: c["newton_steps"].as_u64().map(|n| coarse.iter().fold(n, |m, &k| m.max(k))),
        safety_factor,
        normal: either("normal_force"),
        tangential: either("tangential_force"),
        uplift: either("uplift_force"),
        contact_length: curve["contact_length"].as_f64(),
        crack_length: c["crack_length"].as_f64(),
        diagram_crack: curve["crack"]["length"].as_f64(),
        at_drains: curve["crack"]["at_drains"].as_bool() == Some(true),
        position: c["resultant"]["position"].as_f64(),
        strength: ["held", "failed"]
            .map(|k| json["strength_reduction"][k].as_f64())
            .into_iter()
            .collect::<Option<Vec<_>>>()
            .map(|v| [v[0], v[1]]),
        seconds,
    })
}

/// A case, its run and its exact reference.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    pub case: DamCase,
    pub run: Run,
    pub statics: Statics,
    /// N = R·ν − U and FS of the module's formulas, with damfem's U (crack filled) and L_c
    /// (cohesion) when it has a result.
    pub normal: f64,
    pub exact: f64,
}

impl Record {
    pub fn new(case: DamCase, run: Run) -> Record {
        let statics = case.statics();
        let uplift = match (case.crack, run.uplift) {
            (Crack::Full, Some(u)) => u,
            _ => statics.uplift,
        };
        let normal = statics.pressing - uplift;
        let closed = run.contact_length.unwrap_or(statics.length);
        let exact = (case.cohesion * closed + case.friction * normal) / statics.tangential.abs();
        Record { case, run, statics, normal, exact }
    }

    /// |FS_LE − FS| / FS.
    pub fn error(&self) -> Option<f64> {
        self.run.safety_factor.map(|fs| (fs - self.exact).abs() / self.exact)
    }

    /// |N_h − N| / N and |T_h − T| / |T| of damfem's joint forces.
    pub fn force_errors(&self) -> Option<(f64, f64)> {
        let (n, t) = (self.run.normal?, self.run.tangential?);
        Some((
            (n - self.normal).abs() / self.normal,
            (t - self.statics.tangential).abs() / self.statics.tangential.abs(),
        ))
    }

    /// Whether the case holds exactly.
    pub fn holds(&self) -> bool {
        self.exact >= 1.0
    }

    /// Whether the exact FS is within [`UNDECIDED`] of 1, where either answer is right.
    pub fn undecided(&self) -> bool {
        (self.exact - 1.0).abs() <= UNDECIDED
    }

    /// A result where the case holds, a verdict where it does not (either near FS = 1).
    pub fn agrees(&self) -> bool {
        match self.run.outcome {
            Outcome::Result => self.holds() || self.undecided(),
            Outcome::Verdict => !self.holds() || self.undecided(),
            Outcome::Failure | Outcome::Error => false,
        }
    }

    /// The crack s_c of the result's uplift diagram (0 with the crack ignored).
    fn diagram_crack(&self) -> Option<f64> {
        match self.case.crack {
            Crack::Ignore => self.run.safety_factor.map(|_| 0.0),
            Crack::Full => self.run.diagram_crack,
        }
    }

    /// |U_h − U(s_c)| / U(s_c) of a result, at its own crack s_c.
    pub fn uplift_error(&self) -> Option<f64> {
        let (u, _) = self.case.uplift(self.diagram_crack()?);
        Some((self.run.uplift? - u).abs() / u)
    }

    /// |s_R − s_N(s_c)| / L of a result, s_N(s_c) = −(M + M_u(s_c))/(R·ν − U(s_c)).
    pub fn position_error(&self) -> Option<f64> {
        let (u, mu) = self.case.uplift(self.diagram_crack()?);
        let s = -(self.statics.moment + mu) / (self.statics.pressing - u);
        Some((self.run.position? - s).abs() / self.statics.length)
    }

    /// Whether a result with the crack filled has its open length more than 10⁻³ L from the
    /// crack s_c of its diagram: the crack's fixed point did not settle. A crack that stopped at
    /// the drain line settled if s_c = s_d and the joint closes short of it there.
    pub fn unsettled(&self) -> bool {
        let (open, crack) = (self.run.crack_length, self.run.diagram_crack);
        let Some((open, crack)) = open.zip(crack).filter(|_| self.case.crack == Crack::Full) else { return false };
        if self.run.at_drains {
            return self.case.drains.is_none_or(|d| d.distance != crack || open > crack);
        }
        (open - crack).abs() > 1e-3 * self.statics.length
    }
}

/// The cases of seeds `seed`, …, `seed + count − 1`.
pub fn cases(seed: u64, count: usize) -> Vec<DamCase> {
    (0..count as u64).map(|i| DamCase::new(seed.wrapping_add(i))).collect()
}

/// The table's header: the seed, the foundation, the degree, H \[m\], m, β \[°\], E_rock/E_concrete,
/// φ \[°\], c \[MPa\], the crack rule, a \[g\], the outcome, the Newton steps, FS_LE, the exact FS,
/// their relative difference and the wall time \[s\].
pub fn header() -> String {
    let names = [
        "seed", "kind", "p", "H", "m", "β°", "rock", "φ°", "c MPa", "crack", "a g", "outcome", "newton", "FS_LE", "FS",
        "error", "time s",
    ];
    let widths = [6, 5, 2, 6, 5, 5, 5, 5, 5, 6, 5, 8, 6, 7, 7, 8, 6];
    names.iter().zip(widths).map(|(n, w)| format!("{n:>w$}")).collect::<Vec<_>>().join(" ")
}

/// The row of a record under [`header`].
pub fn row(r: &Record) -> String {
    let c = &r.case;
    let opt = |v: Option<f64>, digits: usize| v.map_or("–".to_string(), |v| format!("{v:.digits$}"));
    format!(
        "{:>6} {:>5} {:>2} {:>6.1} {:>5.2} {:>5.1} {:>5} {:>5.1} {:>5.2} {:>6} {:>5.3} {:>8} {:>6} {:>7} {:>7.4} {:>8} {:>6.2}",
        c.seed,
        c.kind(),
        c.order,
        c.height,
        c.slope,
        c.base_angle.to_degrees(),
        opt(c.rock_ratio(), 2),
        c.friction.atan().to_degrees(),
        c.cohesion / 1e6,
        c.crack.name(),
        c.acceleration,
        r.run.outcome.name(),
        r.run.newton_steps.map_or("–".to_string(), |n| n.to_string()),
        opt(r.run.safety_factor, 4),
        r.exact,
        r.error().map_or("–".to_string(), |e| format!("{e:.1e}")),
        r.run.seconds
    )
}

/// The largest value of `f` over the records that have one.
fn largest(records: &[Record], f: impl Fn(&Record) -> Option<f64>) -> f64 {
    records.iter().filter_map(f).fold(0.0, f64::max)
}

/// The seeds of the `records` that `pick`, comma-separated.
fn seeds(records: &[Record], pick: impl Fn(&Record) -> bool) -> String {
    records.iter().filter(|r| pick(r)).map(|r| r.case.seed.to_string()).collect::<Vec<_>>().join(", ")
}

/// The closing summary: the share of cases with a result or a correct verdict, the largest
/// FS error of the c = 0 results, the median and largest Newton steps (the most on one mesh,
/// and summed over the levels of nested iteration), the largest errors of N, T, U and s_R, the
/// seeds of the results whose crack did not settle, and each case that went wrong with its
/// exit code and message.
pub fn summary(records: &[Record]) -> String {
    let agreeing = records.iter().filter(|r| r.agrees()).count();
    let median_and_largest = |steps: fn(&Run) -> Option<u64>| {
        let mut steps: Vec<u64> = records.iter().filter_map(|r| steps(&r.run)).collect();
        steps.sort_unstable();
        let count = |n: Option<&u64>| n.map_or("–".to_string(), |n| n.to_string());
        format!("median {}, largest {}", count(steps.get(steps.len() / 2)), count(steps.last()))
    };
    let unsettled = seeds(records, Record::unsettled);
    let mut text = format!(
        "{agreeing} of {} cases ({:.1} %) with a result where they hold or a verdict where they do not\n\
         largest |FS_LE − FS|/FS of the c = 0 results: {:.2e}\n\
         Newton steps of the results on one mesh: {}; summed over the levels: {}\n\
         largest |N_h − N|/N, |T_h − T|/|T|, |U_h − U(s_c)|/U, |s_R − s_N(s_c)|/L of the results: \
         {:.2e}, {:.2e}, {:.2e}, {:.2e}\n\
         results whose crack did not settle (open length ≠ s_c by more than 10⁻³ L): seeds [{}]\n\
         results whose crack stopped at the drain line: seeds [{}]\n",
        records.len(),
        100.0 * agreeing as f64 / records.len().max(1) as f64,
        largest(records, |r| r.error().filter(|_| r.case.cohesion == 0.0)),
        median_and_largest(|r| r.newton_steps_per_mesh),
        median_and_largest(|r| r.newton_steps),
        largest(records, |r| r.force_errors().map(|e| e.0)),
        largest(records, |r| r.force_errors().map(|e| e.1)),
        largest(records, Record::uplift_error),
        largest(records, Record::position_error),
        unsettled,
        seeds(records, |r| r.run.at_drains),
    );
    for r in records.iter().filter(|r| !r.agrees()) {
        writeln!(
            text,
            "seed {}: {} (exit {}) where FS = {:.4}: {}",
            r.case.seed,
            r.run.outcome.name(),
            r.run.code.map_or("by signal".to_string(), |c| c.to_string()),
            r.exact,
            r.run.message
        )
        .unwrap();
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    // A rectangle 10 m wide and 20 m high, its heel at the origin, the water at 20 m on its
    // upstream side x = 0: the thrust γ_w 20²/2 at a third of the height.
    #[test]
    fn water_on_a_vertical_face_is_the_hydrostatic_triangle() {
        let (f, m) = water([0.0, 20.0], [0.0, 0.0], 20.0);
        let thrust = gamma_w() * 200.0;
        assert!((f[0] - thrust).abs() < 1e-9 * thrust && f[1].abs() < 1e-9 * thrust, "{f:?}");
        assert!((m + thrust * 20.0 / 3.0).abs() < 1e-9 * thrust * 20.0, "{m}");
    }

    // Scene A under its usual load (geo/scene_a_uplift.toml, docs/results.md "Dam safety"): H = 50 m,
    // B = 40 m, C = 5 m, reservoir at 45 m, drains 5 m from the heel, 2/3 effective. The
    // weight is W = 2.6487·10⁷ N/m, the thrust γ_w 45²/2 = 9.9326·10⁶ N/m, the uplift without
    // crack 3.6785·10⁶ N/m; with the crack past the drains, the triangle-and-strip
    // γ_w 45 (s_c + (L − s_c)/2).
    #[test]
    fn scene_a_has_the_forces_of_the_readme() {
        let case = DamCase {
            seed: 0,
            height: 50.0,
            crest: 5.0,
            slope: 0.7,
            batter: None,
            gallery: None,
            base_angle: 0.0,
            foundation: Foundation::Rigid,
            friction: 0.8391,
            cohesion: 0.0,
            reservoir: 45.0,
            tailwater: None,
            drains: Some(Drains { distance: 5.0, efficiency: 0.6667 }),
            crack: Crack::Full,
            acceleration: 0.0,
            order: 2,
        };
        let s = case.statics();
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-4 * b.abs();
        assert!(close(s.length, 40.0) && close(s.pressing, 2.6487e7), "{s:?}");
        assert!(close(s.tangential, -9.9326e6) && close(s.uplift, 3.6785e6), "{s:?}");
        let (u, _) = case.uplift(6.0);
        assert!(close(u, gamma_w() * 45.0 * (6.0 + 17.0)), "{u}");
    }

    // The section drawn is closed and counter-clockwise, the base from the heel to the toe at
    // angle β, and the drawn case is as asked: N > 0, and FS ≥ 1.1 or ≤ 0.9.
    #[test]
    fn drawn_sections_are_admissible() {
        for case in cases(1, 200) {
            let (area, _) = area_centroid(&case.outline());
            assert!(area > 0.0, "{case:?}");
            let toe = case.toe();
            assert!((toe[1].atan2(toe[0]) - case.base_angle).abs() < 1e-12);
            let s = case.statics();
            let fs = (case.cohesion * s.length + case.friction * s.normal) / s.tangential.abs();
            let friction_alone = case.friction * s.normal / s.tangential.abs();
            assert!(s.normal > 0.0 && (friction_alone >= 1.1 - 1e-9 || fs <= 0.9 + 1e-9), "{case:?}");
        }
    }
}
