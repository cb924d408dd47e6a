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

mod draw;
mod files;
mod record;
mod run;
mod statics;
#[cfg(test)]
mod tests;

pub use draw::cases;
pub use record::{header, row, summary, Record, STRENGTH_GAP};
pub use run::{run, run_with, Outcome, Run};

use crate::geometry::Point;

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
    pub corner: Point,
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
    /// A bond on the joint (docs/method.md §1.13; not drawn, None unless set). The statics are
    /// those of the joint without it: FS_LE counts the whole N, the bond's tension included.
    pub bond: Option<crate::contact::Bond>,
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
