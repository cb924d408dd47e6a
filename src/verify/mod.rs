//! Verification tools: code that checks the production code. The tests, the examples and the
//! benchmarks use it; no production run does. `v1` and `v3` are the manufactured solutions of
//! docs/method.md §7; `dual_norm` the reference of the estimator, the dual norm of the residual
//! on a finer space, with the mesh refinement it needs in `refine`.

pub mod battery;
pub mod cases;
pub mod dual_norm;
pub mod meshes;
pub mod refine;
pub mod rng;
pub mod sweep;
pub mod units;
pub mod v1;
pub mod v3;
