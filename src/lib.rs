//! # damfem
//!
//! Plane-strain elasticity for concrete dams on their foundations, with unilateral contact
//! and friction (Tresca, Coulomb, Mohr–Coulomb) on the joint by Nitsche's method and guaranteed a posteriori error estimates by
//! equilibrated stress reconstruction, from a gmsh `.geo` file to ParaView files; and the
//! elasticity of solids on tetrahedra (a `.geo` with volumes: `elasticity::solid`, solved by
//! sparse Cholesky or by CG with PETSc's multigrid, `solve::petsc`), without contact or
//! estimator yet.
//!
//! ## Pipeline
//!
//! ```text
//!  .geo + scene.toml    scene: materials, boundary roles, loads; builds the Problem and
//!    │                  its ContactJoint (Γ_C tags, joint law, Nitsche parameters)
//!    │  io::gmsh        open, mesh (P1/P2), read nodes, cells, physical groups by name
//!    ▼
//!  Mesh + tags          mesh: topology, vertex patches, structured test meshes
//!    │  fem             quadrature, Lagrange P1/P2, sparse assembly, transfer
//!    │  elasticity      plane-strain Hooke law, element kernels, loads, the linear solve
//!    │                  refined to a pair of doubles x + lo (Displacement)
//!    │  contact         Nitsche terms on Γ_C, joint laws, the smoothing of min(x, 0) at δ
//!    ▼
//!  solve                sparse Cholesky / LU (faer), symbolic factorisation reused; Newton,
//!    │                  its steps by the dense Schur complement on the contact layer, started
//!    │                  by nested iteration on coarser meshes of the .geo, or on the P1
//!    │                  problem of a P2 .msh's triangles (Scene::solve_contact)
//!    ▼
//!  contact::ContactSolution   the iterate (refined to a pair x + lo after a full Newton
//!    │                  step), its linearisation point and smoothing, face states;
//!    │                  the joint's N, T, U, crack and base stresses; safety reads the
//!    │                  resultant, the strength reduction and the classical method from it
//!    ▼
//!  estimate             AFW patch problems → σ_h1 + σ_h2 + σ_h3 → η_osc … η_lin, checks
//!    ▼
//!  adapt                Newton stopped by η_lin, δ by η_reg (on the last mesh Newton
//!    │                  finished to its tolerance); marking, gmsh remeshing with a
//!    │                  size field from η_T, the displacement moved to the new mesh
//!    ▼
//!  io::vtu / io::pvd    ParaView files; cli writes summaries, histories, plots and the
//!                       dam-safety report (`damfem safety`, per load combination)
//! ```
//!
//! Under them all, `geometry` holds the dimension D = 2, points and vectors with their
//! arithmetic, the affine map of a cell, the straight facet and the frame of its normal, and
//! the tetrahedron of a solid (`Mesh<3>`).
//!
//! Data flows one way: a module never calls a module above it; `cli` drives the pipeline and
//! holds no numerical work of its own. The method is described in `docs/method.md`.
//!
//! ## Status and limits
//!
//! A curve of role `contact` is a joint with a rigid obstacle, frictionless or frictional,
//! with uplift in the joint. A curve shared by two meshed bodies may be a joint between them
//! (`[joints.<curve>]`: its nodes split by `mesh::interface`, two-body Nitsche contact, the
//! master–slave form), with uplift on both of its sides (one diagram along all the joints, or
//! each joint its own); the estimator covers it, each side's patches taking their side's
//! traction (docs/method.md §5.6), and `damfem safety` runs on a straight one. The estimator covers the Nitsche variant θ = 0 and triangles of
//! moderate aspect ratio (docs/method.md §4.1); its bound holds for iterates that solve the
//! linearised problem of their last Newton step (every converged or full-step iterate), and
//! an estimate whose reconstruction fails an equilibration check is refused, never reported.
//! Known limit: Newton on Coulomb joints can stall (its line search keeps ‖F‖ monotone); it
//! stops with an error. On a softening (Mohr–Coulomb) joint its stalled steps take the
//! Jacobian with the cohesion's closed indicator held fixed (docs/solver.md §3).

pub mod adapt;
pub mod cli;
pub mod contact;
pub mod elasticity;
pub mod estimate;
pub mod fem;
pub mod geometry;
pub mod io;
pub mod mesh;
pub mod safety;
pub mod scene;
pub mod solve;
pub mod verify;
