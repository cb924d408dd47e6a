// Quarter of the unit disk: two straight sides and a circular arc.
lc = 0.2;
Point(1) = {0, 0, 0, lc};
Point(2) = {1, 0, 0, lc};
Point(3) = {0, 1, 0, lc};
Line(1) = {1, 2};
Circle(2) = {2, 1, 3};
Line(3) = {3, 1};
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};
Physical Curve("bottom") = {1};
Physical Curve("arc") = {2};
Physical Curve("left") = {3};
Physical Surface("domain") = {1};
