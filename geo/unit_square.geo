// Unit square (0,1)^2 of the verification case V1 (theory §7).
n = 8;   // cells per side

Point(1) = {0, 0, 0, 1.0 / n};
Point(2) = {1, 0, 0, 1.0 / n};
Point(3) = {1, 1, 0, 1.0 / n};
Point(4) = {0, 1, 0, 1.0 / n};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
Physical Surface("domain") = {1};
