// Curve loop with a missing side: its 1D mesh is not closed.
Point(1) = {0, 0, 0, 0.1};
Point(2) = {1, 0, 0, 0.1};
Point(3) = {1, 1, 0, 0.1};
Line(1) = {1, 2};
Line(2) = {2, 3};
Curve Loop(1) = {1, 2};
Plane Surface(1) = {1};
