// A textbook gravity-dam section for the cracked-base check: a triangle with a vertical upstream
// face, height 50 m and base 40 m, its whole base on a rigid rock foundation as one joint.
// Plane strain, SI units.
H = 50;      // dam height [m]
B = 40;      // base width [m]
h = 2.5;     // mesh size in the body [m]
hb = 0.5;    // mesh size at the heel and the toe [m]

Point(1) = {0, 0, 0, hb};
Point(2) = {B, 0, 0, hb};
Point(3) = {0, H, 0, h};

Line(1) = {1, 2};   // base, the joint
Line(2) = {2, 3};   // downstream face
Line(3) = {3, 1};   // upstream face

Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};

Physical Curve("base") = {1};
Physical Curve("downstream") = {2};
Physical Curve("upstream") = {3};
Physical Surface("concrete") = {1};
