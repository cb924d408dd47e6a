// The dam of Scene A built in two lifts and standing on the rock block of Scene B (plane
// strain, SI units): a horizontal construction joint "lift" at y = Y between the lower block
// (0 <= y <= Y) and the upper block (Y <= y <= H), and the dam-rock interface "base"
// (0 <= x <= B). Each is a curve shared by two surfaces, which gmsh meshes conformingly; with
// a [joints.<curve>] table damfem splits its nodes, and each joint has its own law.
H = 50;      // dam height [m]
B = 40;      // dam base width [m]
C = 5;       // crest width [m]
Y = 20;      // height of the lift joint [m]
L = 55;      // rock extent upstream and downstream of the dam [m]
D = 50;      // rock depth [m]
h = 2.5;     // mesh size in the dam [m]
hr = 8;      // mesh size at the far rock boundary [m]
hb = 0.75;   // mesh size at the ends of the joints [m]
X = B - (B - C) * Y / H;  // downstream end of the lift joint [m]

Point(1) = {0, 0, 0, hb};
Point(2) = {B, 0, 0, hb};
Point(3) = {X, Y, 0, hb};
Point(4) = {C, H, 0, h};
Point(5) = {0, H, 0, h};
Point(6) = {0, Y, 0, hb};
Point(7) = {-L, 0, 0, hr};
Point(8) = {-L, -D, 0, hr};
Point(9) = {B + L, -D, 0, hr};
Point(10) = {B + L, 0, 0, hr};

Line(1) = {1, 2};   // dam-rock interface, the joint "base"
Line(2) = {2, 3};   // downstream face, lower block
Line(3) = {3, 4};   // downstream face, upper block
Line(4) = {4, 5};   // crest
Line(5) = {5, 6};   // upstream face, upper block
Line(6) = {6, 1};   // upstream face, lower block
Line(7) = {6, 3};   // lift joint
Line(8) = {7, 1};   // reservoir floor
Line(9) = {8, 7};   // upstream rock side
Line(10) = {9, 8};  // rock bottom
Line(11) = {10, 9}; // downstream rock side
Line(12) = {2, 10}; // downstream ground

Curve Loop(1) = {1, 2, -7, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {7, 3, 4, 5};
Plane Surface(2) = {2};
Curve Loop(3) = {8, 1, 12, 11, 10, 9};
Plane Surface(3) = {-3};

Physical Curve("base") = {1};
Physical Curve("lift") = {7};
Physical Curve("downstream") = {2, 3};
Physical Curve("crest") = {4};
Physical Curve("upstream") = {5, 6};
Physical Curve("reservoir_floor") = {8};
Physical Curve("rock_sides") = {9, 11};
Physical Curve("rock_bottom") = {10};
Physical Curve("ground") = {12};
Physical Surface("lower_block") = {1};
Physical Surface("upper_block") = {2};
Physical Surface("rock") = {3};
