//! The dam engineer's checks beside the finite elements.
//!
//! [`classical`] is the guideline's gravity method (a rigid section on a plane base, a linear
//! base pressure, the uplift diagram and its crack iteration) computed from the loads of the
//! same problem that the finite elements solve, so that the two answers differ by the method
//! alone. [`criteria`] holds the requirements of each category of load combination, which
//! both answers are checked against. [`strength`] is the strength reduction: FS_SR, the finite
//! elements' own sliding factor. The room is 2D: the joint is a line (`contact::JointLine`),
//! its resultant a point on it, its [`base`] stresses means over windows of it; the 3D issue
//! makes it a plane, a point on it and areas of it.

pub mod base;
pub mod check;
pub mod classical;
pub mod criteria;
pub mod resultant;
pub mod strength;
