// Scene B with a frictional joint: the gravity dam of Scene A on the rock block of Scene B
// (plane strain, SI units), the whole dam-rock interface (0 <= x <= 40 m) one physical curve
// "joint". scene_b_joint.toml makes it a Coulomb joint with uplift between the two meshed
// bodies; gmsh meshes the interface conformingly and damfem splits its nodes.
H = 50;      // dam height [m]
B = 40;      // dam base width [m]
C = 5;       // crest width [m]
L = 55;      // rock extent upstream and downstream of the dam [m]
D = 50;      // rock depth [m]
h = 2.5;     // mesh size in the dam [m]
hr = 8;      // mesh size at the far rock boundary [m]
hb = 0.75;   // mesh size at the heel and the toe [m]

Point(1) = {0, 0, 0, hb};
Point(3) = {B, 0, 0, hb};
Point(4) = {C, H, 0, h};
Point(5) = {0, H, 0, h};
Point(6) = {-L, 0, 0, hr};
Point(7) = {-L, -D, 0, hr};
Point(8) = {B + L, -D, 0, hr};
Point(9) = {B + L, 0, 0, hr};

Line(1) = {1, 3};   // interface, the joint
Line(3) = {3, 4};   // downstream face
Line(4) = {4, 5};   // crest
Line(5) = {5, 1};   // upstream face
Line(6) = {6, 1};   // reservoir floor
Line(7) = {7, 6};   // upstream rock side
Line(8) = {8, 7};   // rock bottom
Line(9) = {9, 8};   // downstream rock side
Line(10) = {3, 9};  // downstream ground

Curve Loop(1) = {1, 3, 4, 5};
Plane Surface(1) = {1};
Curve Loop(2) = {6, 1, 10, 9, 8, 7};
Plane Surface(2) = {-2};

Physical Curve("joint") = {1};
Physical Curve("downstream") = {3};
Physical Curve("crest") = {4};
Physical Curve("upstream") = {5};
Physical Curve("reservoir_floor") = {6};
Physical Curve("rock_sides") = {7, 9};
Physical Curve("rock_bottom") = {8};
Physical Curve("ground") = {10};
Physical Surface("concrete") = {1};
Physical Surface("rock") = {2};
