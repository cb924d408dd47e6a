//! # damfem
//!
//! Plane-strain elasticity for concrete dams on their foundations, with frictionless
//! unilateral contact by Nitsche's method and guaranteed a posteriori error estimates by
//! equilibrated stress reconstruction, from a gmsh `.geo` file to ParaView files.
//!
//! ## Pipeline
//!
//! ```text
//!  .geo + scene.toml    scene (materials, boundary roles, loads, contact settings)
//!    │  io::gmsh        open, mesh (P1/P2), read nodes, cells, physical groups by name
//!    ▼
//!  Mesh + tags          mesh::{topology, structured, refine}
//!    │  fem             quadrature, Lagrange P1/P2, affine maps, sparse assembly
//!    │  elasticity      plane-strain Hooke law, element kernels, loads
//!    │  contact         Nitsche terms on Γ_C, regularised projection, δ-continuation
//!    ▼
//!  solve                sparse Cholesky / LU (faer), symbolic factorisation reused; Newton
//!    ▼
//!  estimate             AFW patch problems → σ_h1 + σ_h2 + σ_h3 → η_osc … η_lin, checks
//!    ▼
//!  io::vtu / io::pvd    ParaView files
//! ```
//!
//! Data flows one way: a module never calls a module above it; `cli` drives the pipeline.
//! The method is described in `docs/method.md`.

pub mod adapt;
pub mod cli;
pub mod contact;
pub mod elasticity;
pub mod estimate;
pub mod fem;
pub mod io;
pub mod mesh;
pub mod scene;
pub mod solve;
