//! Error measures and a posteriori error estimation (docs/method.md §2–§4).
//!
//! [`dual_norm`] computes the dual norm of the residual on a finer space, the reference
//! against which estimators are verified.

pub mod afw;
pub mod checks;
pub mod dual_norm;
pub mod estimators;
pub mod face;
pub mod patch;
pub mod reconstruction;
