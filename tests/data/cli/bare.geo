// A 2 x 1 block whose physical curve names give the default roles of a bare .geo:
// Gamma_D clamped, Gamma_N loaded (zero traction by default), Gamma_C bonded; gravity loads it.
Point(1) = {0, 0, 0, 0.25};
Point(2) = {2, 0, 0, 0.25};
Point(3) = {2, 1, 0, 0.25};
Point(4) = {0, 1, 0, 0.25};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("Gamma_D") = {1};
Physical Curve("Gamma_N") = {2, 3};
Physical Curve("Gamma_C") = {4};
Physical Surface("block") = {1};
