//! Helpers shared by the integration tests.
#![allow(dead_code)]

/// Least-squares slope of log(e) against log(h).
pub fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    damfem::adapt::history::loglog_slope(&h.iter().copied().zip(e.iter().copied()).collect::<Vec<_>>())
}

/// max over the nodes of max_i |u_h,i − u_i| for the exact solution `u`.
pub fn max_nodal_error(points: &[[f64; 2]], u_h: &[[f64; 2]], u: impl Fn([f64; 2]) -> [f64; 2]) -> f64 {
    points.iter().zip(u_h).map(|(&x, v)| (v[0] - u(x)[0]).abs().max((v[1] - u(x)[1]).abs())).fold(0.0, f64::max)
}
