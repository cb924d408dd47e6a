//! V3: manufactured Signorini solution with contact on x < ½ and separation on x > ½.
//! Source: docs/method.md §7 V3. Ω = (0,1)², μ = λ = 1 (E = 2.5, ν = 1/4), Γ_C = {y = 0},
//! Γ_D = {x = 0} with u = (0, −y/8), Γ_N = {x = 1} ∪ {y = 1} with g_N = σ(u)n;
//! ψ = (x − ½)₊⁴, φ = (½ − x)₊³, u = (−y ψ', ψ − y φ).

use crate::elasticity::{BodyForce, Dirichlet, Material, Neumann, Problem, Traction};
use crate::geometry::{Point, Tensor, Vector};
use crate::mesh::structured::{LEFT, RIGHT, TOP};
use crate::mesh::Mesh;
use std::sync::Arc;

const MU: f64 = 1.0;
const LAMBDA: f64 = 1.0;

/// (ψ, ψ', ψ'', ψ''') at x.
pub fn psi(x: f64) -> [f64; 4] {
    let t = (x - 0.5).max(0.0);
    [t.powi(4), 4.0 * t.powi(3), 12.0 * t * t, 24.0 * t]
}

/// (φ, φ', φ'') at x.
pub fn phi(x: f64) -> [f64; 3] {
    let t = (0.5 - x).max(0.0);
    [t.powi(3), -3.0 * t * t, 6.0 * t]
}

pub fn u(p: Point) -> Vector {
    let (s, f) = (psi(p[0]), phi(p[0]));
    [-p[1] * s[1], s[0] - p[1] * f[0]]
}

pub fn grad_u(p: Point) -> Tensor {
    let (s, f) = (psi(p[0]), phi(p[0]));
    [[-p[1] * s[2], -s[1]], [s[1] - p[1] * f[1], -f[0]]]
}

/// [σ_xx, σ_yy, σ_xy].
pub fn sigma(p: Point) -> [f64; 3] {
    let (s, f, y) = (psi(p[0]), phi(p[0]), p[1]);
    let c = 2.0 * MU + LAMBDA;
    [-c * y * s[2] - LAMBDA * f[0], -c * f[0] - LAMBDA * y * s[2], -MU * y * f[1]]
}

pub fn f(p: Point) -> Vector {
    let (s, f, y) = (psi(p[0]), phi(p[0]), p[1]);
    [(2.0 * MU + LAMBDA) * y * s[3] + (LAMBDA + MU) * f[1], MU * y * f[2] + LAMBDA * s[2]]
}

/// The V3 problem (without its contact condition, which lives on the bottom side).
pub fn problem(mesh: Mesh) -> Problem {
    let right = Traction::Field(Arc::new(|x| {
        let s = sigma(x);
        [s[0], s[2]]
    }));
    let top = Traction::Field(Arc::new(|x| {
        let s = sigma(x);
        [s[2], s[1]]
    }));
    Problem {
        materials: vec![Material::from_lame(LAMBDA, MU); mesh.n_cells()],
        dirichlet: vec![Dirichlet { tag: LEFT, fix: [true; 2], value: Arc::new(u) }],
        neumann: vec![Neumann { tag: RIGHT, traction: right }, Neumann { tag: TOP, traction: top }],
        body_force: BodyForce::Field(Arc::new(f)),
        mesh,
    }
}
