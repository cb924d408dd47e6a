//! Why a contact solve stopped without an answer.

use super::{path, NoEquilibrium, PathPoint};
use crate::solve::NewtonError;

/// Why a contact solve stopped without an answer.
#[derive(Debug, thiserror::Error)]
pub enum ContactError {
    #[error(transparent)]
    Newton(#[from] NewtonError),
    #[error(
        "the crack–uplift iteration did not settle in {iterations} solves: the crack at the heel (now {length:.4} m) \
         still moved by {change:.3e} m; set crack = \"ignore\" in its uplift table to solve without the crack's \
         pressure"
    )]
    Crack { iterations: usize, length: f64, change: f64 },
    #[error(
        "the crack–uplift iteration closed on a crack of {length:.4} m whose opening jumps by {change:.3e} m, more \
         than the face there ({face:.3e} m); refine the mesh along the joint, or set crack = \"ignore\" in its uplift \
         table"
    )]
    CrackJump { length: f64, change: f64, face: f64 },
    #[error(
        "the crack at the heel would grow from {from:.3} m to {to:.3} m in one load step, more than {limit:.3} m: a \
         shorter load step follows it"
    )]
    CrackStep { from: f64, to: f64, limit: f64 },
    #[error(transparent)]
    NoEquilibrium(#[from] Box<NoEquilibrium>),
    #[error(
        "no equilibrium at λ = {load_factor:.4} of the loads that follow the self-weight: only the joint holds the \
         body, and {contact_length:.3} m of its {joint_length:.3} m remain in contact (less than {share} %): the body \
         lifts off (overturns or floats)",
        share = 100.0 * path::LIFT_OFF
    )]
    LiftOff { load_factor: f64, contact_length: f64, joint_length: f64 },
    #[error(
        "the load path stopped at λ = {load_factor:.4} of the loads that follow the self-weight, where the joint \
         neither slides, lifts off nor cracks through (crack {crack}, contact length {contact:.3} m, FS_LE {fs}): no \
         converged state beyond it with load steps down to {min_step:.1e}; the last step's solve: {last}",
        crack = state.crack.map_or("none".to_string(), |c| format!("{c:.3} m")),
        contact = state.contact_length,
        fs = state.sliding_safety_factor.map_or("none".to_string(), |f| format!("{f:.3}")),
        min_step = path::MIN_STEP,
    )]
    PathStalled { load_factor: f64, state: PathPoint, last: Box<ContactError> },
}

impl ContactError {
    /// The Newton steps of the run that failed (0 where no Newton run failed).
    pub fn newton_steps(&self) -> usize {
        match self {
            ContactError::Newton(failed) => failed.steps(),
            _ => 0,
        }
    }
}
