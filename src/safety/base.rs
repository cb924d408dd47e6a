//! The base stresses of a solved joint: the mean effective normal stress at the heel, at the
//! toe and from the crack tip, means over a length because the elastic stress is singular at
//! the corners. 2D: the joint is a line; in 3D the windows become areas of the base.

use crate::contact::{local_displacement, ContactSolution, JointLine};
use crate::elasticity::{Discretisation, Problem};
use serde::Serialize;

/// The mean effective normal stress σ'^n \[Pa\] (tension positive) over `length` \[m\] at the heel
/// and at the toe.
#[derive(Serialize)]
pub struct BaseStresses {
    pub length: f64,
    pub heel: f64,
    pub toe: f64,
    /// The mean over `length` from the end of the closed part at the heel (the crack tip; the
    /// heel itself without a crack), to compare with beam theory beyond a crack.
    pub heel_closed: f64,
}

/// The mean σ'^n of `solution` over `length` at the heel and at the toe of `line`, and from
/// its crack tip.
pub fn base_stresses(
    solution: &ContactSolution,
    problem: &Problem,
    disc: &Discretisation,
    line: &JointLine,
    length: f64,
) -> BaseStresses {
    let mean = |window| mean_normal_stress(solution, problem, disc, line, window);
    let tip = solution.crack_from_heel(line).min(line.length - length);
    BaseStresses {
        length,
        heel: mean([0.0, length]),
        toe: mean([line.length - length, line.length]),
        heel_closed: mean([tip, tip + length]),
    }
}

/// The mean effective normal stress σ'^n = q(P_γ) = −p_c \[Pa\] (tension positive) of the
/// solved equations of `solution` over the part of `line` at the distances `window` =
/// \[s₀, s₁\] from the heel, integrated exactly on pieces split at the kinks of p_c and at s₀, s₁.
pub fn mean_normal_stress(
    solution: &ContactSolution,
    problem: &Problem,
    disc: &Discretisation,
    line: &JointLine,
    window: [f64; 2],
) -> f64 {
    let (nitsche, smoothing) = (&solution.nitsche, solution.smoothing);
    let u_full = disc.dofs.expand(&solution.x);
    let mut dofs = Vec::new();
    let mut integral = 0.0;
    for k in (0..nitsche.faces.len()).filter(|&k| solution.on_line(k, line)) {
        let [d0, d1] = [0.0, 1.0].map(|t| line.distance(nitsche.position(k, t)));
        // the window's ends in the face parameter t: s(t) = d0 + t (d1 − d0)
        let [a, b] = window.map(|s| (s - d0) / (d1 - d0));
        let (lo, hi) = (a.min(b).max(0.0), a.max(b).min(1.0));
        if lo >= hi {
            continue;
        }
        let u = local_displacement(&problem.mesh, nitsche, k, &u_full, &mut dofs);
        let mut cuts = nitsche.kinks(k, &u, smoothing);
        cuts.extend([lo, hi]);
        cuts.sort_by(f64::total_cmp);
        integral += (nitsche.split_rule(k, &cuts).into_iter())
            .filter(|&(t, _)| t > lo && t < hi)
            .map(|(t, w)| nitsche.normal_law(k).value(nitsche.p_gamma(k, &nitsche.point(k, t), &u), smoothing) * w)
            .sum::<f64>();
    }
    integral / (window[1] - window[0])
}
