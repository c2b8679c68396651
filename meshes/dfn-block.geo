// Discrete fracture network (docs/howto-discrete-fracture-network.md): a 1 x 1 m block on
// [0, 1]^2 with five straight fractures embedded in its surface as lines of mesh edges, all
// in the physical curve "dfn". Fractures that cross must be split at the crossing point
// (here fractures 1 and 2 cross at (0.5, 0.5): four segments meeting there); fractures that
// end inside the block keep their tips inside. Element size 0.02 m along the fractures,
// 0.05 m elsewhere.
lc = 0.05;
lf = 0.02;
Point(1) = {0, 0, 0, lc};
Point(2) = {1, 0, 0, lc};
Point(3) = {1, 1, 0, lc};
Point(4) = {0, 1, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
// fractures 1 and 2 cross at point 10
Point(10) = {0.5, 0.5, 0, lf};
Point(11) = {0.3, 0.3, 0, lf};
Point(12) = {0.7, 0.7, 0, lf};
Point(13) = {0.3, 0.7, 0, lf};
Point(14) = {0.7, 0.3, 0, lf};
Line(11) = {11, 10};
Line(12) = {10, 12};
Line(13) = {13, 10};
Line(14) = {10, 14};
// fracture 3: inclined, isolated
Point(15) = {0.1, 0.8, 0, lf};
Point(16) = {0.35, 0.9, 0, lf};
Line(15) = {15, 16};
// fracture 4: sub-horizontal, isolated
Point(17) = {0.6, 0.12, 0, lf};
Point(18) = {0.9, 0.18, 0, lf};
Line(16) = {17, 18};
// fracture 5: sub-vertical, isolated
Point(19) = {0.85, 0.45, 0, lf};
Point(20) = {0.82, 0.8, 0, lf};
Line(17) = {19, 20};
Curve{11, 12, 13, 14, 15, 16, 17} In Surface{1};
Physical Surface("rock") = {1};
Physical Curve("dfn") = {11, 12, 13, 14, 15, 16, 17};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
