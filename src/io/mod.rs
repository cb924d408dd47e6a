//! Input and output: gmsh meshes, ParaView files.
