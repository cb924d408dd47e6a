//! # damfem
//!
//! Plane-strain linear elasticity for concrete dams on their foundations, from a gmsh `.geo`
//! file to ParaView files.
//!
//! ## Pipeline
//!
//! ```text
//!  .geo + scene.toml
//!    │  io::gmsh        open, mesh (P1/P2), read nodes, cells, physical groups by name
//!    ▼
//!  Mesh + tags          mesh::{topology, structured}
//!    │  fem             quadrature, Lagrange P1/P2, affine maps, sparse assembly
//!    │  elasticity      plane-strain Hooke law, element kernels, loads
//!    ▼
//!  solve                sparse Cholesky (faer), symbolic factorisation reused
//!    ▼
//!  io::vtu / io::pvd    ParaView files
//! ```
//!
//! Data flows one way: a module never calls a module above it. The method is described in
//! `docs/method.md`.

pub mod cli;
pub mod contact;
pub mod elasticity;
pub mod estimate;
pub mod fem;
pub mod io;
pub mod mesh;
pub mod scene;
pub mod solve;
