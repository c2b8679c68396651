// Disc pressed on a rigid plane (2D Hertz contact), R = 25 mm. The Hertz half-width of the
// test load is a = R/20 = 1.25 mm; the mesh is graded to a/12 within 2.5 a of the bottom pole
// (the contact) and grows to R/15 away from it. Nodes at the poles and the centre.
R = 0.025;
a = R / 20;
lc = R / 15;             // size away from the contacts
lcl = a / 12;            // size at the contacts
Point(1) = {0, 0, 0, lc};
Point(2) = {0, -R, 0, lcl};
Point(3) = {R, 0, 0, lc};
Point(4) = {0, R, 0, lc};
Point(5) = {-R, 0, 0, lc};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Point{1} In Surface{1};
Field[1] = Distance;
Field[1].PointsList = {2};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = lcl;
Field[2].SizeMax = lc;
Field[2].DistMin = 2.5 * a;
Field[2].DistMax = 0.5 * R;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Physical Surface("body") = {1};
Physical Curve("rim") = {1, 2, 3, 4};
Physical Point("bottom") = {2};
Physical Point("top") = {4};
Physical Point("center") = {1};
