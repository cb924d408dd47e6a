// Scene A with a frictional joint: the gravity dam of scene_a.geo, its whole base on the rock
// as one Coulomb joint (no anchor). Plane strain, SI units.
H = 50;      // dam height [m]
B = 40;      // base width [m]
C = 5;       // crest width [m]
h = 2.5;     // mesh size in the body [m]
hb = 0.75;   // mesh size at the heel and the toe [m]

Point(1) = {0, 0, 0, hb};
Point(2) = {B, 0, 0, hb};
Point(3) = {C, H, 0, h};
Point(4) = {0, H, 0, h};

Line(1) = {1, 2};   // base, the joint
Line(2) = {2, 3};   // downstream face
Line(3) = {3, 4};   // crest
Line(4) = {4, 1};   // upstream face

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

Physical Curve("base") = {1};
Physical Curve("downstream") = {2};
Physical Curve("crest") = {3};
Physical Curve("upstream") = {4};
Physical Surface("concrete") = {1};
