// Sole graded in 3 layers: "bottom_layer" (touching the ground),
// "middle_layer" and "top_layer" (attached to the foot). Frame and surface
// groups as in sole_box.geo (top face at z = 0, sole below). Layer
// thicknesses are fractions of SoleThickness (BottomFraction + MiddleFraction < 1).
DefineConstant[
  SoleLength = {0.2172, Name "Length (m)"},
  SoleWidth = {0.138, Name "Width (m)"},
  SoleThickness = {0.020, Name "Thickness (m)"},
  BottomFraction = {0.3333, Name "Bottom layer thickness / thickness"},
  MiddleFraction = {0.3333, Name "Middle layer thickness / thickness"},
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

t1 = BottomFraction * SoleThickness;
t2 = MiddleFraction * SoleThickness;
t3 = SoleThickness - t1 - t2;
If (SoleHex)
  nx = Ceil(SoleLength / SoleMeshSize);
  ny = Ceil(SoleWidth / SoleMeshSize);
  Transfinite Curve{1, 3} = nx + 1;
  Transfinite Curve{2, 4} = ny + 1;
  Transfinite Surface{1};
  Recombine Surface{1};
  l1[] = Extrude {0, 0, t1} { Surface{1}; Layers{Ceil(t1 / SoleMeshSize)}; Recombine; };
  l2[] = Extrude {0, 0, t2} { Surface{l1[0]}; Layers{Ceil(t2 / SoleMeshSize)}; Recombine; };
  l3[] = Extrude {0, 0, t3} { Surface{l2[0]}; Layers{Ceil(t3 / SoleMeshSize)}; Recombine; };
Else
  l1[] = Extrude {0, 0, t1} { Surface{1}; };
  l2[] = Extrude {0, 0, t2} { Surface{l1[0]}; };
  l3[] = Extrude {0, 0, t3} { Surface{l2[0]}; };
EndIf

Physical Surface("bottom") = {1};
Physical Surface("top") = {l3[0]};
Physical Surface("sides") = {l1[2], l1[3], l1[4], l1[5], l2[2], l2[3], l2[4], l2[5],
                             l3[2], l3[3], l3[4], l3[5]};
Physical Volume("bottom_layer") = {l1[1]};
Physical Volume("middle_layer") = {l2[1]};
Physical Volume("top_layer") = {l3[1]};
