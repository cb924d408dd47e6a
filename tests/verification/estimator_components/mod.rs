//! Component-wise verification of the equilibrated-stress estimator (docs/method.md §2–§5):
//! the guaranteed bound for un-converged Newton iterates, η_reg = O(δ), the terms that must
//! vanish exactly, checks that do fail on a tampered reconstruction, and equilibration on
//! gmsh meshes of the scenes.
//!
//! Notation: η_* are the global estimators (Σ_T η_T²)^{1/2} of damfem::estimate::estimators,
//! "dual" is the Riesz lower bound ‖r‖_{C,h} ≤ ‖R(u_h)‖ of damfem::estimate::reference on the
//! coarse mesh refined once (P2), "worst" the largest relative equilibration violation of
//! damfem::estimate::checks.

mod guarantee;
mod newton_iterates;
mod regularisation;
mod scenes;
mod support;
mod tampering;
mod vanishing_terms;
