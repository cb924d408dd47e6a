//! Input and output: gmsh meshes, ParaView files, convergence plots.

pub mod atomic;
pub mod gmsh;
pub mod input;
pub mod plot;
pub mod pvd;
pub mod vtu;
