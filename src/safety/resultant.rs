//! The joint as a dam engineer reads it (docs/method.md §1.9): a straight joint from its heel
//! to its toe, the resultant of the contact pressure on it, its position and eccentricity, and
//! the middle-third check.
//!
//! With s the distance from the heel and L the joint length, N = ∫ p_c ds, T = ∫ t^t ds,
//! U = ∫ p_u ds, and the resultant of the contact pressure acts at
//!
//!   x_R = ∫ x p_c ds / N,   s_R = (x_R − x_heel)·τ_joint,   e = s_R − L/2,
//!
//! inside the middle third when |e| ≤ L/6: a linear base pressure N/L (1 ± 6e/L) is then
//! compressive over the whole base, the resultant-location criterion for usual loads of the US
//! Army Corps of Engineers (EM 1110-2-2100, Stability Analysis of Concrete Structures, 2005),
//! which CADAM also applies.

use crate::contact::{ContactSolution, JointForces, JointLine};
use crate::geometry::Point;
use serde::Serialize;

/// The resultant of the joint traction on a straight joint.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Resultant {
    /// N = ∫ p_c ds \[N/m\], compression positive: the effective normal force (W − U on a
    /// horizontal joint).
    pub normal_force: f64,
    /// T = ∫ t^t ds \[N/m\] along τ = (−ν_y, ν_x).
    pub tangential_force: f64,
    /// U = ∫ p_u ds \[N/m\] (0 without uplift).
    pub uplift_force: f64,
    /// The point x_R where N acts.
    pub point: Point,
    /// Its distance s_R from the heel \[m\].
    pub position: f64,
    /// e = s_R − L/2 \[m\], positive towards the toe.
    pub eccentricity: f64,
    /// |e| ≤ L/6.
    pub middle_third: bool,
    /// L \[m\].
    pub length: f64,
}

impl Resultant {
    /// The resultant of N, T and U with the first moment M = ∫ x p_c ds of the contact
    /// pressure, on `line`; None when N ≤ 0 (nothing presses on the joint).
    pub fn new(line: &JointLine, forces: [f64; 3], moment: [f64; 2]) -> Option<Self> {
        let [normal_force, tangential_force, uplift_force] = forces;
        (normal_force > 0.0).then(|| {
            let point = [moment[0] / normal_force, moment[1] / normal_force];
            let position = line.distance(point);
            let eccentricity = position - 0.5 * line.length;
            Resultant {
                normal_force,
                tangential_force,
                uplift_force,
                point,
                position,
                eccentricity,
                middle_third: eccentricity.abs() <= line.length / 6.0,
                length: line.length,
            }
        })
    }
}

/// The forces on the faces of `solution` on the straight joint `line`
/// ([`ContactSolution::forces`]): its contact length, N, T and FS_LE along it.
pub fn forces_on(solution: &ContactSolution, line: &JointLine) -> JointForces {
    solution.forces(|k| solution.on_line(k, line))
}

/// The resultant of the traction of the faces of `solution` on the straight joint `line`
/// (docs/method.md §1.9); None when nothing presses on the joint.
pub fn resultant(solution: &ContactSolution, line: &JointLine) -> Option<Resultant> {
    let faces = solution.faces_on(line);
    let moment = faces.iter().fold([0.0; 2], |m, f| [m[0] + f.pressure_moment[0], m[1] + f.pressure_moment[1]]);
    let JointForces { normal_force, tangential_force, .. } = forces_on(solution, line);
    let uplift = faces.iter().map(|f| f.uplift * f.length).sum();
    Resultant::new(line, [normal_force, tangential_force, uplift], moment)
}
