//! Verification tools: code that checks the production code. The tests, the examples and the
//! benchmarks use it; no production run does.

pub mod meshes;
pub mod rng;
pub mod sweep;
pub mod units;
