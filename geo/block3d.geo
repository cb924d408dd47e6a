// Block3D: a 2 m x 1 m x 1 m block, the first check of damfem's 3D mode (SI units, z up).
// The block fills 0 <= x <= Lx, 0 <= y <= Ly, 0 <= z <= Lz; each of its six faces is a
// physical surface named by its position, so that rollers and loads can be put on any of
// them. The base rectangle (z = 0) is drawn and extruded along z.
Lx = 2;      // length along x [m]
Ly = 1;      // width along y [m]
Lz = 1;      // height along z [m]
h = 0.25;    // mesh size [m]

Point(1) = {0, 0, 0, h};
Point(2) = {Lx, 0, 0, h};
Point(3) = {Lx, Ly, 0, h};
Point(4) = {0, Ly, 0, h};

Line(1) = {1, 2};   // y = 0
Line(2) = {2, 3};   // x = Lx
Line(3) = {3, 4};   // y = Ly
Line(4) = {4, 1};   // x = 0

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};   // bottom, z = 0

// block[0] is the top (z = Lz), block[1] the volume, block[2..5] the faces swept by
// lines 1..4.
block[] = Extrude {0, 0, Lz} { Surface{1}; };

Physical Surface("xmin") = {block[5]};
Physical Surface("xmax") = {block[3]};
Physical Surface("ymin") = {block[2]};
Physical Surface("ymax") = {block[4]};
Physical Surface("bottom") = {1};
Physical Surface("top") = {block[0]};
Physical Volume("block") = {block[1]};
