//! Finite elements on affine triangles: quadrature, Lagrange P1/P2 bases, affine maps,
//! degrees of freedom, sparse assembly and transfer of fields between meshes.

pub mod dofs;
pub mod lagrange;
pub mod norms;
pub mod quadrature;
pub mod sparse;
pub mod tabulate;
pub mod transfer;
