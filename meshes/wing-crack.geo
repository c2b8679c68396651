// Wing-crack specimen (examples/wing-crack.json): a 50 x 100 mm rock block on
// [0, 0.05] x [0, 0.1] with a pre-existing flaw of length 2c = 16 mm inclined at 45 degrees
// through the centre, embedded in the surface as a line of mesh edges (physical curve
// "flaw"; its two tips are ordinary mesh nodes, shared by both sides until the joints
// around them break). Element size 1.2 mm along the flaw and its tips, growing to 2.5 mm.
W = 0.05;
H = 0.1;
c = 0.008;
lf = 0.0012;
lc = 0.0025;
s = c * Sqrt(0.5);
Point(1) = {0, 0, 0, lc};
Point(2) = {W, 0, 0, lc};
Point(3) = {W, H, 0, lc};
Point(4) = {0, H, 0, lc};
Point(5) = {W / 2 - s, H / 2 - s, 0, lf};
Point(6) = {W / 2 + s, H / 2 + s, 0, lf};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Line(5) = {5, 6};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
// the flaw: a line of mesh edges inside the surface
Curve{5} In Surface{1};
Field[1] = Distance;
Field[1].CurvesList = {5};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = lf;
Field[2].SizeMax = lc;
Field[2].DistMin = 0.003;
Field[2].DistMax = 0.015;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Physical Surface("rock") = {1};
Physical Curve("flaw") = {5};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
