// Two-layer parallelepiped sole: "top_layer" (attached to the foot) over
// "bottom_layer" (touching the ground). Frame and surface groups as in
// sole_box.geo; the interface lies at z = -TopFraction * SoleThickness.
DefineConstant[
  SoleLength = {0.2172, Name "Length (m)"},
  SoleWidth = {0.138, Name "Width (m)"},
  SoleThickness = {0.020, Name "Thickness (m)"},
  TopFraction = {0.5, Name "Top layer thickness / thickness"},
  SoleMeshSize = {0.01, Name "Mesh size (m)"},
  SoleHex = {0, Name "Hexahedra (1) or tetrahedra (0)"}
];

Point(1) = {-SoleLength/2, -SoleWidth/2, -SoleThickness, SoleMeshSize};
Point(2) = { SoleLength/2, -SoleWidth/2, -SoleThickness, SoleMeshSize};
Point(3) = { SoleLength/2,  SoleWidth/2, -SoleThickness, SoleMeshSize};
Point(4) = {-SoleLength/2,  SoleWidth/2, -SoleThickness, SoleMeshSize};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

t_bottom = (1 - TopFraction) * SoleThickness;
t_top = TopFraction * SoleThickness;
If (SoleHex)
  nx = Ceil(SoleLength / SoleMeshSize);
  ny = Ceil(SoleWidth / SoleMeshSize);
  Transfinite Curve{1, 3} = nx + 1;
  Transfinite Curve{2, 4} = ny + 1;
  Transfinite Surface{1};
  Recombine Surface{1};
  lower[] = Extrude {0, 0, t_bottom} { Surface{1}; Layers{Ceil(t_bottom / SoleMeshSize)}; Recombine; };
  upper[] = Extrude {0, 0, t_top} { Surface{lower[0]}; Layers{Ceil(t_top / SoleMeshSize)}; Recombine; };
Else
  lower[] = Extrude {0, 0, t_bottom} { Surface{1}; };
  upper[] = Extrude {0, 0, t_top} { Surface{lower[0]}; };
EndIf

Physical Surface("bottom") = {1};
Physical Surface("top") = {upper[0]};
Physical Surface("sides") = {lower[2], lower[3], lower[4], lower[5], upper[2], upper[3], upper[4], upper[5]};
Physical Volume("bottom_layer") = {lower[1]};
Physical Volume("top_layer") = {upper[1]};
