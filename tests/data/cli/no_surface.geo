// Only a curve: gmsh meshes it, but there is no triangle to solve on.
Point(1) = {0, 0, 0, 0.1};
Point(2) = {1, 0, 0, 0.1};
Line(1) = {1, 2};
Physical Curve("Gamma_D") = {1};
