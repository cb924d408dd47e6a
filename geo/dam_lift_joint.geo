// The dam of Scene A built in two lifts (plane strain, SI units): a horizontal construction
// joint "lift" at y = Y cuts it into a lower block (0 <= y <= Y) and an upper block
// (Y <= y <= H). Both blocks share the curve "lift", so gmsh meshes it conformingly; with a
// [joints.lift] table damfem splits its nodes and the joint may open and slide.
H = 50;      // dam height [m]
B = 40;      // base width [m]
C = 5;       // crest width [m]
Y = 20;      // height of the lift joint [m]
h = 2.5;     // mesh size in the body [m]
hb = 0.75;   // mesh size at the ends of the base and of the lift joint [m]
X = B - (B - C) * Y / H;  // downstream end of the lift joint [m]

Point(1) = {0, 0, 0, hb};
Point(2) = {B, 0, 0, hb};
Point(3) = {X, Y, 0, hb};
Point(4) = {C, H, 0, h};
Point(5) = {0, H, 0, h};
Point(6) = {0, Y, 0, hb};

Line(1) = {1, 2};   // base
Line(2) = {2, 3};   // downstream face, lower block
Line(3) = {3, 4};   // downstream face, upper block
Line(4) = {4, 5};   // crest
Line(5) = {5, 6};   // upstream face, upper block
Line(6) = {6, 1};   // upstream face, lower block
Line(7) = {6, 3};   // lift joint

Curve Loop(1) = {1, 2, -7, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {7, 3, 4, 5};
Plane Surface(2) = {2};

Physical Curve("base") = {1};
Physical Curve("downstream") = {2, 3};
Physical Curve("crest") = {4};
Physical Curve("upstream") = {5, 6};
Physical Curve("lift") = {7};
Physical Surface("lower_block") = {1};
Physical Surface("upper_block") = {2};
