//! The description of a contact boundary: its curves, the law and Nitsche parameters of each,
//! and the uplift diagrams along them.

use super::bond::Bond;
use super::law::JointLaw;
use super::nitsche::{Nitsche, NitscheParameters};
use super::uplift::Uplift;
use super::ContactSolution;
use crate::elasticity::{Discretisation, Problem};

/// The joint law, the bond and the Nitsche parameters of one curve of Γ_C.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveLaw {
    pub law: JointLaw,
    /// The tensile strength and softening of a cohesive joint; None: no tensile strength.
    pub bond: Option<Bond>,
    pub parameters: NitscheParameters,
}

impl CurveLaw {
    /// This curve with its strength divided by k ([`JointLaw::reduced`], [`Bond::reduced`]).
    pub fn reduced(&self, k: f64) -> CurveLaw {
        CurveLaw { law: self.law.reduced(k), bond: self.bond.map(|b| b.reduced(k)), ..*self }
    }
}

/// An uplift diagram and the curves of Γ_C it acts on (indices into [`ContactJoint::tags`]):
/// one diagram along several curves on one straight line, or a curve's own.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveUplift {
    pub curves: Vec<usize>,
    pub diagram: Uplift,
}

/// A contact boundary: the curves of Γ_C, and the joint law and Nitsche parameters of each.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactJoint {
    /// Physical tags of the curves of Γ_C (on a joint between two bodies, the slave sides).
    pub tags: Vec<i32>,
    /// On joints between two bodies, the physical tag of the master side's curve facing each
    /// curve of `tags`; empty: a rigid foundation.
    pub masters: Vec<i32>,
    /// The law and Nitsche parameters of each curve of `tags`, in the same order.
    pub laws: Vec<CurveLaw>,
    /// The pore-water pressure diagrams in the joint, each on its curves (a curve on at most
    /// one); empty: no uplift.
    pub uplift: Vec<CurveUplift>,
    /// The nodal displacements (dof 2i + a) of the state that the friction law measures slip
    /// from (None: rest); of a joint as solved on a load path, the state before the last.
    pub slip_origin: Option<Vec<f64>>,
}

impl ContactJoint {
    /// A joint on the curves `tags` (facing the curves `masters` on two bodies, or none: a rigid
    /// foundation), every curve with `law` and `parameters`.
    pub fn uniform(tags: Vec<i32>, masters: Vec<i32>, law: JointLaw, parameters: NitscheParameters) -> Self {
        let laws = vec![CurveLaw { law, bond: None, parameters }; tags.len()];
        ContactJoint { tags, masters, laws, uplift: Vec::new(), slip_origin: None }
    }

    /// This joint with the uplift `diagram` along all of its curves.
    pub fn with_uplift(self, diagram: Uplift) -> Self {
        let curves = (0..self.tags.len()).collect();
        ContactJoint { uplift: vec![CurveUplift { curves, diagram }], ..self }
    }

    /// This joint with `bond` on every curve (None: no tensile strength).
    pub fn with_bond(mut self, bond: Option<Bond>) -> Self {
        self.laws.iter_mut().for_each(|c| c.bond = bond);
        self
    }

    /// A frictionless joint on the curves `tags`.
    pub fn frictionless(tags: Vec<i32>, parameters: NitscheParameters) -> Self {
        ContactJoint::uniform(tags, Vec::new(), JointLaw::Frictionless, parameters)
    }

    /// Whether some curve has a tangential traction.
    pub fn has_friction(&self) -> bool {
        self.laws.iter().any(|c| c.law.has_friction())
    }

    /// Whether some curve i with `plane[i]` has a tangential traction (the sliding plane of
    /// [`ContactJoint::reduced`] has a strength to divide).
    pub fn has_friction_on(&self, plane: &[bool]) -> bool {
        self.laws.iter().zip(plane).any(|(c, &on)| on && c.law.has_friction())
    }

    /// Whether some curve i with `plane[i]` has a bond.
    pub fn has_bond_on(&self, plane: &[bool]) -> bool {
        self.laws.iter().zip(plane).any(|(c, &on)| on && c.bond.is_some())
    }

    /// The joint with the strength of the curves i with `plane[i]` divided by k (strength
    /// reduction on a sliding plane; the other curves keep theirs).
    pub fn reduced(&self, k: f64, plane: &[bool]) -> ContactJoint {
        let laws = self.laws.iter().zip(plane).map(|(c, &on)| if on { c.reduced(k) } else { *c }).collect();
        ContactJoint { laws, ..self.clone() }
    }

    /// Every curve: the whole joint as the sliding plane of [`ContactJoint::reduced`].
    pub fn every_curve(&self) -> Vec<bool> {
        vec![true; self.laws.len()]
    }

    /// The contact faces of the joint on the mesh of `problem`.
    pub fn faces(&self, problem: &Problem, disc: &Discretisation) -> Nitsche {
        Nitsche::new(&problem.mesh, &disc.topology, &problem.materials, self)
    }

    /// This joint with the uplift that `solution` was found with (its crack included).
    pub fn as_solved(&self, solution: &ContactSolution) -> ContactJoint {
        let (uplift, slip_origin) =
            (solution.nitsche.uplift.clone(), solution.nitsche.slip_origin().map(<[f64]>::to_vec));
        ContactJoint { uplift, slip_origin, ..self.clone() }
    }
}
