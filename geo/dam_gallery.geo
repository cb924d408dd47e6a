// A gravity dam with an inspection gallery, on a rigid rock foundation (plane strain, SI units).
// Scene A's section (height 50 m, base 40 m, crest 5 m) with a 3 m x 4 m gallery near the heel
// (4 <= x <= 7, 3 <= y <= 7). The heel side of the base (0 <= x <= 32) is the contact boundary
// Gamma_C; the downstream toe (32 <= x <= 40) is anchored (Gamma_D).
H = 50;      // dam height [m]
B = 40;      // base width [m]
C = 5;       // crest width [m]
T = 32;      // start of the anchored toe [m]
h = 2.5;     // mesh size in the body [m]
hb = 0.75;   // mesh size at the ends of the contact zone [m]
hg = 0.5;    // mesh size at the gallery corners [m]

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

Point(6) = {4, 3, 0, hg};
Point(7) = {7, 3, 0, hg};
Point(8) = {7, 7, 0, hg};
Point(9) = {4, 7, 0, hg};
Line(6) = {6, 7};   // gallery floor
Line(7) = {7, 8};
Line(8) = {8, 9};   // gallery roof
Line(9) = {9, 6};

Curve Loop(1) = {1, 2, 3, 4, 5};
Curve Loop(2) = {6, 7, 8, 9};
Plane Surface(1) = {1, 2};

Physical Curve("base") = {1};
Physical Curve("toe") = {2};
Physical Curve("downstream") = {3};
Physical Curve("crest") = {4};
Physical Curve("upstream") = {5};
Physical Curve("gallery") = {6, 7, 8, 9};
Physical Surface("concrete") = {1};
