// Quarter of a thick cylinder (Lame): inner radius 1, outer radius 2 (m), symmetry lines
// x = 0 ("left") and y = 0 ("bottom"). Size 0.008 at the inner surface (where the stress
// gradient is largest) growing to 0.04 at 0.6 from it.
ri = 1;
ro = 2;
lc = 0.04;
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
Field[1] = Distance;
Field[1].CurvesList = {4};
Field[1].Sampling = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = 0.008;
Field[2].SizeMax = lc;
Field[2].DistMin = 0.0;
Field[2].DistMax = 0.6;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Physical Surface("body") = {1};
Physical Curve("bottom") = {1};
Physical Curve("outer") = {2};
Physical Curve("left") = {3};
Physical Curve("inner") = {4};
