// Coarse square block for the fracturing uniaxial compression example and test: 50 mm wide and
// 50 mm high on [0, 0.05] x [0, 0.05], element size 4 mm (the whole block is exploded into
// joints by the scene).
W = 0.05;
H = 0.05;
lc = 0.004;
Point(1) = {0, 0, 0, lc};
Point(2) = {W, 0, 0, lc};
Point(3) = {W, H, 0, lc};
Point(4) = {0, H, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("body") = {1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
