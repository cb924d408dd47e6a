// Valley: three 15 m wide gravity monoliths side by side (0 <= y <= 3 W) in a terraced
// V-shaped valley (SI units, z up, y along the dam's axis, the river flowing along +x,
// water on the side x < 0). Every monolith has the section of Scene A (vertical upstream
// face at x = 0, crest 5 m wide at z = H, downstream face from (C, H) to (B, 0)): the
// middle monolith (W <= y <= 2 W) stands on the river bed at z = 0 and is 50 m high; the
// two outer ones stand on benches S = 5 m higher, so that their section is the same one cut
// at z = S (base Bs = 36.5 m, height 45 m) and the crest is level. The rock's top follows
// the same terraces for its whole length along x: z = S for y <= W and y >= 2 W, z = 0 in
// between, with vertical 5 m steps at y = W and y = 2 W; the middle monolith is keyed
// into the river bed between them. The ends of the dam (y = 0 and y = 3 W) stand in the air
// (the abutments), above the rock's side faces.
// The volumes are fragmented (OpenCASCADE BooleanFragments), so the joints between the
// monoliths and the dam-rock interfaces are shared surfaces, meshed conformingly, bonded
// and without a physical surface.
SetFactory("OpenCASCADE");

H = 50;      // height of the middle monolith; the crest is at z = H [m]
B = 40;      // base width of the middle monolith [m]
C = 5;       // crest width [m]
W = 15;      // monolith width along y [m]
S = 5;       // height of the outer benches above the river bed [m]
Lu = 40;     // rock extent upstream of the heel [m]
Ld = 40;     // rock extent downstream of the middle monolith's toe [m]
D = 40;      // rock depth below the river bed [m]
h = 5;       // mesh size at the crest [m]
hb = 2.5;    // mesh size along the dam-rock interfaces [m]
hr = 10;     // mesh size at the far rock boundary [m]
Bs = B - (B - C) * S / H;  // base width of an outer monolith [m]
eps = 0.01;  // tolerance of the bounding boxes that pick the surfaces [m]

// The middle monolith's section in the plane y = W, extruded to y = 2 W.
Point(1) = {0, W, 0};
Point(2) = {B, W, 0};
Point(3) = {C, W, H};
Point(4) = {0, W, H};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

// The outer monoliths' section (cut at z = S) in the plane y = 0, extruded to y = W for
// the left monolith; its copy at y = 2 W (made below) is extruded to y = 3 W for the right.
Point(5) = {0, 0, S};
Point(6) = {Bs, 0, S};
Point(7) = {C, 0, H};
Point(8) = {0, 0, H};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 8};
Line(8) = {8, 5};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(2) = {2};

// The rock's section in the plane x = -Lu: the terraced valley, extruded along x.
Point(9) = {-Lu, 0, -D};
Point(10) = {-Lu, 3 * W, -D};
Point(11) = {-Lu, 3 * W, S};
Point(12) = {-Lu, 2 * W, S};
Point(13) = {-Lu, 2 * W, 0};
Point(14) = {-Lu, W, 0};
Point(15) = {-Lu, W, S};
Point(16) = {-Lu, 0, S};
Line(9) = {9, 10};
Line(10) = {10, 11};
Line(11) = {11, 12};
Line(12) = {12, 13};
Line(13) = {13, 14};
Line(14) = {14, 15};
Line(15) = {15, 16};
Line(16) = {16, 9};
Curve Loop(3) = {9, 10, 11, 12, 13, 14, 15, 16};
Plane Surface(3) = {3};

// The right monolith's section: a copy of the outer section moved to y = 2 W.
outer_section[] = Translate {0, 2 * W, 0} { Duplicata { Surface{2}; } };

middle[] = Extrude {0, W, 0} { Surface{1}; };
left[] = Extrude {0, W, 0} { Surface{2}; };
right[] = Extrude {0, W, 0} { Surface{outer_section[0]}; };
rock[] = Extrude {Lu + B + Ld, 0, 0} { Surface{3}; };

// The monoliths touch each other and the rock: fragmenting makes the touching faces shared.
BooleanFragments{ Volume{middle[1], left[1], right[1], rock[1]}; Delete; }{}

dam() = Volume In BoundingBox{-eps, -eps, -eps, B + eps, 3 * W + eps, H + eps};
ground() = Volume In BoundingBox{-Lu - eps, -eps, -D - eps, B + Ld + eps, 3 * W + eps, S + eps};

// Mesh sizes: hr on the rock, h on the dam, hb on the points of the dam-rock interfaces
// (the dam's points at z <= S).
MeshSize{ PointsOf{ Volume{ground()}; } } = hr;
MeshSize{ PointsOf{ Volume{dam()}; } } = h;
MeshSize{ Point In BoundingBox{-eps, -eps, -eps, B + eps, 3 * W + eps, S + eps} } = hb;

// The boundary surfaces: each is picked by its bounding box; rock_top is what remains of
// the model's boundary.
outer() = Abs(CombinedBoundary{ Volume{:}; });
upstream() = Surface In BoundingBox{-eps, -eps, -eps, eps, 3 * W + eps, H + eps};
crest() = Surface In BoundingBox{-eps, -eps, H - eps, C + eps, 3 * W + eps, H + eps};
downstream() = Surface In BoundingBox{C - eps, -eps, -eps, B + eps, 3 * W + eps, H + eps};
abutments() = Surface In BoundingBox{-eps, -eps, S - eps, B + eps, eps, H + eps};
abutments() += Surface In BoundingBox{-eps, 3 * W - eps, S - eps, B + eps, 3 * W + eps, H + eps};
rock_base() = Surface In BoundingBox{-Lu - eps, -eps, -D - eps, B + Ld + eps, 3 * W + eps, -D + eps};
rock_sides() = Surface In BoundingBox{-Lu - eps, -eps, -D - eps, -Lu + eps, 3 * W + eps, S + eps};
rock_sides() += Surface In BoundingBox{B + Ld - eps, -eps, -D - eps, B + Ld + eps, 3 * W + eps, S + eps};
rock_sides() += Surface In BoundingBox{-Lu - eps, -eps, -D - eps, B + Ld + eps, eps, S + eps};
rock_sides() += Surface In BoundingBox{-Lu - eps, 3 * W - eps, -D - eps, B + Ld + eps, 3 * W + eps, S + eps};
rock_top() = outer();
rock_top() -= {upstream(), crest(), downstream(), abutments(), rock_base(), rock_sides()};

Physical Surface("upstream") = {upstream()};
Physical Surface("downstream") = {downstream()};
Physical Surface("crest") = {crest()};
Physical Surface("abutments") = {abutments()};
Physical Surface("rock_base") = {rock_base()};
Physical Surface("rock_sides") = {rock_sides()};
Physical Surface("rock_top") = {rock_top()};
Physical Volume("concrete") = {dam()};
Physical Volume("rock") = {ground()};
