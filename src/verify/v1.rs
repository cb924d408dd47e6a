//! V1 (docs/method.md §7): manufactured solution of linear elasticity on the unit square,
//! μ = λ = 1, u = (sin πx cos πy + x²/(2λ), −cos πx sin πy + y²/(2λ)), f = −∇·σ(u),
//! Dirichlet data u on the four sides of the structured square (tags 1–4).

use crate::elasticity::{BodyForce, Dirichlet, Material, Problem};
use crate::geometry::{Point, Tensor, Vector};
use crate::mesh::Mesh;
use std::f64::consts::PI;
use std::sync::Arc;

pub const MU: f64 = 1.0;
pub const LAMBDA: f64 = 1.0;

pub fn exact(x: Point) -> Vector {
    let (px, py) = (PI * x[0], PI * x[1]);
    [px.sin() * py.cos() + x[0] * x[0] / (2.0 * LAMBDA), -px.cos() * py.sin() + x[1] * x[1] / (2.0 * LAMBDA)]
}

pub fn exact_gradient(x: Point) -> Tensor {
    let (px, py) = (PI * x[0], PI * x[1]);
    [
        [PI * px.cos() * py.cos() + x[0] / LAMBDA, -PI * px.sin() * py.sin()],
        [PI * px.sin() * py.sin(), -PI * px.cos() * py.cos() + x[1] / LAMBDA],
    ]
}

/// f = (2μπ² sin πx cos πy − 2μ/λ − 1, −2μπ² cos πx sin πy − 2μ/λ − 1).
pub fn body_force(x: Point) -> Vector {
    let (px, py) = (PI * x[0], PI * x[1]);
    let c = 2.0 * MU / LAMBDA + 1.0;
    [2.0 * MU * PI * PI * px.sin() * py.cos() - c, -2.0 * MU * PI * PI * px.cos() * py.sin() - c]
}

/// The V1 problem on `mesh`, with Dirichlet data on the physical curves `tags`.
pub fn problem(mesh: Mesh, tags: &[i32]) -> Problem {
    Problem {
        materials: vec![Material::from_lame(LAMBDA, MU); mesh.n_cells()],
        dirichlet: tags.iter().map(|&tag| Dirichlet { tag, fix: [true; 2], value: Arc::new(exact) }).collect(),
        neumann: vec![],
        body_force: BodyForce::Field(Arc::new(body_force)),
        mesh,
    }
}
