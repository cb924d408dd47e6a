// Monolith: one 15 m wide monolith of the Scene A gravity dam on a deformable rock block,
// the 3D counterpart of scene_b.geo (SI units, z up, y along the dam's axis, the river
// flowing along +x, water on the side x < 0). The section of Scene A (height 50 m, base
// 40 m, vertical upstream face at x = 0, crest 5 m wide) is drawn in the plane y = 0 with
// the rock's section below it, and both are extruded along y by the width W. The dam-rock
// interface (z = 0, 0 <= x <= B) is one surface shared by the two volumes: it is meshed
// conformingly, bonded, and has no physical surface.
H = 50;      // dam height [m]
B = 40;      // dam base width [m]
C = 5;       // crest width [m]
W = 15;      // monolith width along y [m]
Lu = 40;     // rock extent upstream of the heel [m]
Ld = 40;     // rock extent downstream of the toe [m]
D = 40;      // rock depth [m]
h = 5;       // mesh size at the crest [m]
hb = 2.5;    // mesh size along the dam-rock interface [m]
hr = 10;     // mesh size at the far rock boundary [m]

Point(1) = {0, 0, 0, hb};
Point(2) = {B, 0, 0, hb};
Point(3) = {C, 0, H, h};
Point(4) = {0, 0, H, h};
Point(5) = {-Lu, 0, 0, hr};
Point(6) = {-Lu, 0, -D, hr};
Point(7) = {B + Ld, 0, -D, hr};
Point(8) = {B + Ld, 0, 0, hr};

Line(1) = {1, 2};   // dam-rock interface
Line(2) = {2, 3};   // downstream face
Line(3) = {3, 4};   // crest
Line(4) = {4, 1};   // upstream face
Line(5) = {5, 1};   // reservoir floor
Line(6) = {6, 5};   // upstream rock end
Line(7) = {7, 6};   // rock base
Line(8) = {8, 7};   // downstream rock end
Line(9) = {2, 8};   // downstream ground

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};            // dam section, y = 0
Curve Loop(2) = {5, 1, 9, 8, 7, 6};
Plane Surface(2) = {2};            // rock section, y = 0

// One extrusion of both sections shares the surface swept by line 1 (the interface).
// ext[0]: dam section at y = W, ext[1]: dam volume, ext[2..5]: the surfaces swept by
// lines 1, 2, 3, 4; ext[6]: rock section at y = W, ext[7]: rock volume, ext[8..13]: the
// surfaces swept by lines 5, 1, 9, 8, 7, 6 (ext[9] = ext[2]).
ext[] = Extrude {0, W, 0} { Surface{1, 2}; };

Physical Surface("upstream") = {ext[5]};
Physical Surface("downstream") = {ext[3]};
Physical Surface("crest") = {ext[4]};
Physical Surface("sides") = {1, ext[0]};
Physical Surface("rock_sides") = {2, ext[6]};
Physical Surface("rock_base") = {ext[12]};
Physical Surface("rock_ends") = {ext[13], ext[11]};
Physical Surface("rock_top") = {ext[8], ext[10]};
Physical Volume("concrete") = {ext[1]};
Physical Volume("rock") = {ext[7]};
