// Knee pad (issue 22): a small rubber box fixed on a link, contact face below.
// Frame (the pad frame): origin at the centre of the top face, z up; the pad fills
// [-PadLength/2, PadLength/2] x [-PadWidth/2, PadWidth/2] x [-PadThickness, 0] (m).
// coupling::DeformablePad places this frame on its link (translation, roll-pitch-yaw).
// Physical groups: "top" (attached to the link, Dirichlet), "bottom" (contact),
// "sides", and one volume per material region (here "pad").
// Parameters (override with gmsh -setnumber NAME VALUE, PadDescription::mesh_numbers):
DefineConstant[
  PadLength = {0.08, Name "Length (m)"},
  PadWidth = {0.08, Name "Width (m)"},
  PadThickness = {0.015, Name "Thickness (m)"},
  PadMeshSize = {0.01, Name "Mesh size (m)"},
  PadHex = {0, Name "Hexahedra (1) or tetrahedra (0)"}
];

Point(1) = {-PadLength/2, -PadWidth/2, -PadThickness, PadMeshSize};
Point(2) = { PadLength/2, -PadWidth/2, -PadThickness, PadMeshSize};
Point(3) = { PadLength/2,  PadWidth/2, -PadThickness, PadMeshSize};
Point(4) = {-PadLength/2,  PadWidth/2, -PadThickness, PadMeshSize};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

If (PadHex)
  nx = Ceil(PadLength / PadMeshSize);
  ny = Ceil(PadWidth / PadMeshSize);
  nz = Ceil(PadThickness / PadMeshSize);
  Transfinite Curve{1, 3} = nx + 1;
  Transfinite Curve{2, 4} = ny + 1;
  Transfinite Surface{1};
  Recombine Surface{1};
  out[] = Extrude {0, 0, PadThickness} { Surface{1}; Layers{nz}; Recombine; };
Else
  out[] = Extrude {0, 0, PadThickness} { Surface{1}; };
EndIf

Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
Physical Surface("sides") = {out[2], out[3], out[4], out[5]};
Physical Volume("pad") = {out[1]};
