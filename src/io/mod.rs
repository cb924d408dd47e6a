//! Input and output: gmsh meshes, ParaView files.

pub mod atomic;
pub mod gmsh;
pub mod pvd;
pub mod vtu;
