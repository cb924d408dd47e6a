//! Isotropic linear elasticity in plane strain (material law, element kernels, the boundary
//! value problem and its stresses) and of a solid on tetrahedra ([`solid`]).

pub mod displacement;
pub mod kernels;
pub mod material;
pub mod problem;
pub mod rigid;
pub mod solid;
pub mod stress;

pub use displacement::Displacement;
pub use material::Material;
pub use problem::{nodal, BodyForce, Dirichlet, Discretisation, Neumann, Problem, Refined, Traction, VectorFn};
