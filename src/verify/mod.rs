//! Verification tools: code that checks the production code. The tests, the examples and the
//! benchmarks use it; no production run does. `v1` and `v3` are the manufactured solutions of
//! docs/method.md §7. The reference of the estimator, the dual norm of the residual on a finer
//! space, is `estimate::reference`, since `--effectivity` computes it in production runs.

pub mod battery;
pub mod cases;
pub mod meshes;
pub mod rng;
pub mod sweep;
pub mod units;
pub mod v1;
pub mod v3;
