//! Unilateral contact on Γ_C with a rigid foundation, or across a joint between two meshed
//! bodies (docs/method.md §1.10), by Nitsche's method.
//!
//! A [`ContactJoint`] is the one description of a contact boundary, built by the scene: where
//! (the physical tags of Γ_C), for each of its curves which law and which Nitsche parameters
//! ([`CurveLaw`]), and the uplift diagrams with the curves each acts on ([`CurveUplift`]). On a
//! mesh it becomes the faces of [`Nitsche`](nitsche::Nitsche), each reading the law and the
//! uplift of its curve. [`ContactProblem`] is the nonlinear system F(x) = 0 over the free
//! displacement dofs,
//!
//!   F(u; v) = (σ(u), ε(v)) − (f, v) − (g_N, v)_{Γ_N} + Σ_F R_F(u; v),
//!
//! with the face terms R_F of [`nitsche`] and the [`Smoothing`](projection::Smoothing) of the
//! projection at δ. The bulk stiffness K and load b are assembled once; each evaluation adds
//! the face terms of the cells that own a contact face. A solve returns a [`ContactSolution`]:
//! the iterate, the linearisation point and smoothing it was computed with, and the state of
//! every face.
//!
//! The joint's description is in `joint`, the system and the state of its faces in `problem`,
//! the continuation in δ and nested iteration in `continuation`, the solution in `solution`,
//! the crack–uplift fixed point in `crack` and the errors in `error`.

pub mod bond;
mod continuation;
mod crack;
mod error;
mod joint;
pub mod law;
mod line;
pub mod nitsche;
pub mod path;
mod problem;
pub mod projection;
mod solution;
pub mod uplift;

pub use bond::{Bond, BondState, NormalLaw};
pub use continuation::{
    continuation, continuation_counted, nested_start, newton_steps, solve_by_continuation, solve_from,
    solve_system_along, solve_system_from, CarriedState, CoarseLevel, Continuation, NestedStart, Stage,
};
pub use crack::{settle_crack, settle_crack_to, Crack, Cracks};
pub use error::ContactError;
pub use joint::{ContactJoint, CurveLaw, CurveUplift};
pub use law::JointLaw;
pub use line::JointLine;
pub use path::{LoadPath, NoEquilibrium, PathPoint};
pub(crate) use problem::local_displacement;
pub use problem::{lifts_off, open_from_heel, BondLengths, ContactProblem, FaceState, Linearisation};
pub use solution::{CoarseSolve, CoarseTimings, ContactSolution, JointForces, Solution};
pub use uplift::{CrackRule, Uplift};
