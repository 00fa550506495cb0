// Parallelepiped sole (David et al. 2008, Fig. 1): HRP-2's foot outline.
// Frame: origin at the centre of the top face, z up; the sole fills
// [-SoleLength/2, SoleLength/2] x [-SoleWidth/2, SoleWidth/2] x [-SoleThickness, 0] (m).
// Physical groups: "top" (attached to the foot, Dirichlet), "bottom" (contact),
// "sides", and one volume per material region (here "rubber").
// Parameters (override with gmsh -setnumber NAME VALUE):
DefineConstant[
  SoleLength = {0.2172, Name "Length (m)"},
  SoleWidth = {0.138, Name "Width (m)"},
  SoleThickness = {0.020, Name "Thickness (m)"},
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

If (SoleHex)
  nx = Ceil(SoleLength / SoleMeshSize);
  ny = Ceil(SoleWidth / SoleMeshSize);
  nz = Ceil(SoleThickness / SoleMeshSize);
  Transfinite Curve{1, 3} = nx + 1;
  Transfinite Curve{2, 4} = ny + 1;
  Transfinite Surface{1};
  Recombine Surface{1};
  out[] = Extrude {0, 0, SoleThickness} { Surface{1}; Layers{nz}; Recombine; };
Else
  out[] = Extrude {0, 0, SoleThickness} { Surface{1}; };
EndIf

Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
Physical Surface("sides") = {out[2], out[3], out[4], out[5]};
Physical Volume("rubber") = {out[1]};
