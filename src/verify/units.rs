//! The same problem in other units, to check that results do not depend on them.

use crate::elasticity::{BodyForce, Material, Problem, Traction};
use std::sync::Arc;

/// The same problem in units where stresses are divided by `sigma0` and lengths by `length`:
/// x' = x/L, u' = u/L, E' = E/σ₀, g_N' = g_N/σ₀, f' = f L/σ₀. Hydrostatic pressure
/// ρ_w g (H_w − y) becomes (ρ_w L/σ₀) g (H_w/L − y'), self-weight ρ g becomes (ρ L/σ₀) g.
/// The displacement times L must equal the original one.
pub fn rescale(problem: &Problem, sigma0: f64, length: f64) -> Problem {
    let mut scaled = problem.clone();
    for p in &mut scaled.mesh.points {
        *p = [p[0] / length, p[1] / length];
    }
    for m in &mut scaled.materials {
        *m = Material { young: m.young / sigma0, poisson: m.poisson, density: m.density * length / sigma0 };
    }
    for bc in &mut scaled.neumann {
        bc.traction = rescale_traction(bc.traction.clone(), sigma0, length);
    }
    if let BodyForce::Field(f) = scaled.body_force.clone() {
        scaled.body_force = BodyForce::Field(Arc::new(move |x| {
            let v = f([x[0] * length, x[1] * length]);
            [v[0] * length / sigma0, v[1] * length / sigma0]
        }));
    }
    for bc in &mut scaled.dirichlet {
        let value = bc.value.clone();
        bc.value = Arc::new(move |x| {
            let g = value([x[0] * length, x[1] * length]);
            [g[0] / length, g[1] / length]
        });
    }
    scaled
}

/// `traction` in the units of [`rescale`].
fn rescale_traction(traction: Traction, sigma0: f64, length: f64) -> Traction {
    match traction {
        Traction::Constant(t) => Traction::Constant([t[0] / sigma0, t[1] / sigma0]),
        Traction::Hydrostatic { density, gravity, level } => {
            Traction::Hydrostatic { density: density * length / sigma0, gravity, level: level / length }
        }
        Traction::Westergaard { density, gravity, level, depth, acceleration } => Traction::Westergaard {
            density: density * length / sigma0,
            gravity,
            level: level / length,
            depth: depth / length,
            acceleration,
        },
        Traction::Field(f) => Traction::Field(Arc::new(move |x| {
            let t = f([x[0] * length, x[1] * length]);
            [t[0] / sigma0, t[1] / sigma0]
        })),
        Traction::Silt { gradient, level } => {
            Traction::Silt { gradient: gradient * length / sigma0, level: level / length }
        }
        Traction::Ice { pressure, bottom, top } => {
            Traction::Ice { pressure: pressure / sigma0, bottom: bottom / length, top: top / length }
        }
        Traction::Sum(parts) => Traction::Sum(parts.into_iter().map(|t| rescale_traction(t, sigma0, length)).collect()),
    }
}
