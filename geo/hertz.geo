// Half-disk of radius R on a rigid plane: the 2D Hertz case V4 (theory §7).
// Centre at the origin, flat side on top (y = 0), contact near (0, -R).
R = 8;          // radius
h = 0.8;        // mesh size on the top
hc = 0.1;       // mesh size at the contact point

Point(1) = {0, 0, 0, h};
Point(2) = {-R, 0, 0, h};
Point(3) = {0, -R, 0, hc};
Point(4) = {R, 0, 0, h};

Line(1) = {4, 2};            // flat top
Circle(2) = {2, 1, 3};       // left quarter arc
Circle(3) = {3, 1, 4};       // right quarter arc

Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};

Physical Curve("top") = {1};
Physical Curve("Gamma_C") = {2, 3};
Physical Surface("disk") = {1};
