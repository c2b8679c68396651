// Quarter of a thick cylinder (Lame): inner radius 1, outer radius 2 (m), symmetry lines
// x = 0 ("left") and y = 0 ("bottom").
ri = 1;
ro = 2;
lc = 0.035;
Point(1) = {0, 0, 0, lc};
Point(2) = {ri, 0, 0, lc};
Point(3) = {ro, 0, 0, lc};
Point(4) = {0, ro, 0, lc};
Point(5) = {0, ri, 0, lc};
Line(1) = {2, 3};
Circle(2) = {3, 1, 4};
Line(3) = {4, 5};
Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("body") = {1};
Physical Curve("bottom") = {1};
Physical Curve("outer") = {2};
Physical Curve("left") = {3};
Physical Curve("inner") = {4};
