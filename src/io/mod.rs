//! Input and output: gmsh meshes, ParaView files.

pub mod atomic;
pub mod pvd;
pub mod vtu;
