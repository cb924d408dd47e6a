//! Unit tests: the library's pieces one at a time (parallel assembly and estimation, elements,
//! quadrature and transfer, the gmsh interface and remeshing, Newton's method, the joint's
//! resultant, the VTU/PVD writers and the figures).

#[path = "../common/mod.rs"]
mod common;

mod assembly;
mod elements;
mod estimate_threads;
mod gmsh_io;
mod nested;
mod newton;
mod plot;
mod remesh;
mod resultant;
mod transfer;
mod vtu_output;
