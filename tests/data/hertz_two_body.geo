// Two-body Hertz (docs/method.md §7, V4 on a deformable foundation): a half-disk of radius
// R = 8 (centre at the origin, flat top y = 0, arc "arc" below) touching at (0, -R) the top
// "block_top" of an elastic block [-L, L] x [-R - D, -R]. The two bodies share no curve and no
// point: each is meshed on its own, so the meshes of the arc and of the block's top do not
// match, and the initial gap is the vertical distance between them.
R = 8;          // radius
L = 32;         // half-width of the block
D = 32;         // depth of the block
h = 0.8;        // mesh size on the disk's top
hb = 6;         // mesh size at the block's far corners
hc = 0.02;      // mesh size at the contact point, on both bodies

// the half-disk
Point(1) = {0, 0, 0, h};
Point(2) = {-R, 0, 0, h};
Point(3) = {0, -R, 0, hc};
Point(4) = {R, 0, 0, h};
Line(1) = {4, 2};
Circle(2) = {2, 1, 3};
Circle(3) = {3, 1, 4};
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};

// the block, its top split at the contact point and at x = -R/2, R/2, where the size
// grows as on the arc
Point(11) = {-L, -R, 0, hb};
Point(16) = {-R / 2, -R, 0, h / 2};
Point(12) = {0, -R, 0, hc};
Point(17) = {R / 2, -R, 0, h / 2};
Point(13) = {L, -R, 0, hb};
Point(14) = {L, -R - D, 0, hb};
Point(15) = {-L, -R - D, 0, hb};
Line(11) = {11, 16};
Line(16) = {16, 12};
Line(12) = {12, 17};
Line(17) = {17, 13};
Line(13) = {13, 14};
Line(14) = {14, 15};
Line(15) = {15, 11};
Curve Loop(2) = {11, 16, 12, 17, 13, 14, 15};
Plane Surface(2) = {2};

Physical Curve("top") = {1};
Physical Curve("arc") = {2, 3};
Physical Curve("block_top") = {11, 16, 12, 17};
Physical Curve("block_bottom") = {14};
Physical Curve("block_sides") = {13, 15};
Physical Surface("disk") = {1};
Physical Surface("block") = {2};
