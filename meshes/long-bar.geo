// Long bar 1 m x 0.02 m on [0, 1] x [-0.01, 0.01] for wave arrival times; probes on the axis
// at x = 0.25, 0.5, 0.75 ("probe_25", "probe_50", "probe_75").
L = 1;
H = 0.02;
lc = 0.004;
Point(1) = {0, -H/2, 0, lc};
Point(2) = {L, -H/2, 0, lc};
Point(3) = {L, H/2, 0, lc};
Point(4) = {0, H/2, 0, lc};
Point(5) = {0.25, 0, 0, lc};
Point(6) = {0.5, 0, 0, lc};
Point(7) = {0.75, 0, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Point{5, 6, 7} In Surface{1};
Physical Surface("body") = {1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
Physical Point("probe_25") = {5};
Physical Point("probe_50") = {6};
Physical Point("probe_75") = {7};
