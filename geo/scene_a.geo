// Scene A: gravity dam on a rigid rock foundation (plane strain, SI units).
// Height 50 m, base 40 m, vertical upstream face, crest 5 m wide.
// The base is split: heel side (0 <= x <= 32) is the contact boundary Gamma_C,
// the downstream toe (32 <= x <= 40) is anchored (Gamma_D).
H = 50;      // dam height [m]
B = 40;      // base width [m]
C = 5;       // crest width [m]
T = 32;      // start of the anchored toe [m]
h = 2.5;     // mesh size in the body [m]
hb = 0.75;   // mesh size at the ends of the contact zone [m]

Point(1) = {0, 0, 0, hb};
Point(2) = {T, 0, 0, hb};
Point(3) = {B, 0, 0, hb};
Point(4) = {C, H, 0, h};
Point(5) = {0, H, 0, h};

Line(1) = {1, 2};   // base, contact
Line(2) = {2, 3};   // toe, anchored
Line(3) = {3, 4};   // downstream face
Line(4) = {4, 5};   // crest
Line(5) = {5, 1};   // upstream face

Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};

Physical Curve("base") = {1};
Physical Curve("toe") = {2};
Physical Curve("downstream") = {3};
Physical Curve("crest") = {4};
Physical Curve("upstream") = {5};
Physical Surface("concrete") = {1};
