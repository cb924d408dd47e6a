//! Helpers shared by the integration tests.
#![allow(dead_code)]

/// Least-squares slope of log(e) against log(h).
pub fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    damfem::adapt::history::loglog_slope(&h.iter().copied().zip(e.iter().copied()).collect::<Vec<_>>())
}
