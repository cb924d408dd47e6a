//! End to end: the `damfem` commands on real scenes and real gmsh, the adaptive loop with
//! remeshing, and the tutorial example.

mod adapt;
mod bad_input;
mod battery;
mod bound;
mod cli;
mod cohesive;
mod guard;
mod input;
mod joint;
mod solid;
mod support;
mod tutorial;
mod two_body;
