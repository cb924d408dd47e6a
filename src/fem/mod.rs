//! Finite elements on affine triangles and tetrahedra: quadrature, Lagrange P1/P2 bases,
//! degrees of freedom, sparse assembly and transfer of fields between meshes.

pub mod dofs;
pub mod lagrange;
pub mod norms;
pub mod quadrature;
pub mod sparse;
pub mod tabulate;
pub mod tetrahedron;
pub mod transfer;
