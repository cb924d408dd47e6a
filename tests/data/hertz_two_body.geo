// Two-body Hertz: the half-disk of geo/hertz.geo (R = 8, flat top y = 0, arc "Gamma_C")
// above an elastic block [-24, 24] x [-32, -8] whose top "block_top" touches the arc at
// (0, -8). The two surfaces share no point, so gmsh gives them their own nodes.
R = 8;          // radius
h = 0.8;        // mesh size on the top of the disk
hb = 4;         // mesh size at the far block boundary
hc = 0.1;       // mesh size at the contact point, on both bodies
W = 24;         // half-width of the block
D = 24;         // depth of the block

Point(1) = {0, 0, 0, h};
Point(2) = {-R, 0, 0, h};
Point(3) = {0, -R, 0, hc};
Point(4) = {R, 0, 0, h};
Line(1) = {4, 2};
Circle(2) = {2, 1, 3};
Circle(3) = {3, 1, 4};
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};

Point(11) = {-W, -R, 0, hb};
Point(12) = {0, -R, 0, hc};
Point(13) = {W, -R, 0, hb};
Point(14) = {W, -R - D, 0, hb};
Point(15) = {-W, -R - D, 0, hb};
Line(11) = {11, 12};
Line(12) = {12, 13};
Line(13) = {13, 14};
Line(14) = {14, 15};
Line(15) = {15, 11};
Curve Loop(2) = {11, 12, 13, 14, 15};
Plane Surface(2) = {2};

Physical Curve("top") = {1};
Physical Curve("Gamma_C") = {2, 3};
Physical Curve("block_top") = {11, 12};
Physical Curve("block_sides") = {13, 15};
Physical Curve("block_bottom") = {14};
Physical Surface("disk") = {1};
Physical Surface("block") = {2};
