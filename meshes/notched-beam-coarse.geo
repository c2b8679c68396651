// Coarse notched beam for the fracturing three-point bending example and test: the geometry of
// notched-beam.geo (200 mm x 50 mm on [-0.1, 0.1] x [0, 0.05], span 180 mm, supports at
// x = -0.09 and 0.09 on the bottom, central notch 2 mm wide and 10 mm deep), with a loading pad
// 6 mm wide at the top centre (curve "load", |x| <= 3 mm) and the strip |x| <= 10 mm as
// "fracture_zone" (2 mm elements, exploded into joints by the scene); the rest is "bulk"
// (10 mm elements, elastic).
L = 0.2; H = 0.05; S = 0.18; nd = 0.01; nw = 0.002; z = 0.01; pad = 0.003;
lc = 0.01;
lz = 0.002;
Point(1) = {-L/2, 0, 0, lc};
Point(2) = {-S/2, 0, 0, lc};
Point(3) = {-z, 0, 0, lz};
Point(4) = {-nw/2, 0, 0, lz};
Point(5) = {-nw/2, nd, 0, lz};
Point(6) = {nw/2, nd, 0, lz};
Point(7) = {nw/2, 0, 0, lz};
Point(8) = {z, 0, 0, lz};
Point(9) = {S/2, 0, 0, lc};
Point(10) = {L/2, 0, 0, lc};
Point(11) = {L/2, H, 0, lc};
Point(12) = {z, H, 0, lz};
Point(13) = {pad, H, 0, lz};
Point(14) = {0, H, 0, lz};
Point(15) = {-pad, H, 0, lz};
Point(16) = {-z, H, 0, lz};
Point(17) = {-L/2, H, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 8};
Line(8) = {8, 9};
Line(9) = {9, 10};
Line(10) = {10, 11};
Line(11) = {11, 12};
Line(12) = {12, 13};
Line(13) = {13, 14};
Line(14) = {14, 15};
Line(15) = {15, 16};
Line(16) = {16, 17};
Line(17) = {17, 1};
Line(18) = {3, 16};
Line(19) = {8, 12};
Curve Loop(1) = {1, 2, 18, 16, 17};
Plane Surface(1) = {1};
Curve Loop(2) = {3, 4, 5, 6, 7, 19, 12, 13, 14, 15, -18};
Plane Surface(2) = {2};
Curve Loop(3) = {8, 9, 10, 11, -19};
Plane Surface(3) = {3};
Physical Surface("bulk") = {1, 3};
Physical Surface("fracture_zone") = {2};
Physical Curve("bottom") = {1, 2, 3, 7, 8, 9};
Physical Curve("notch") = {4, 5, 6};
Physical Curve("top") = {11, 12, 15, 16};
Physical Curve("load") = {13, 14};
Physical Curve("left") = {17};
Physical Curve("right") = {10};
Physical Point("support_left") = {2};
Physical Point("support_right") = {9};
Physical Point("load_top") = {14};
