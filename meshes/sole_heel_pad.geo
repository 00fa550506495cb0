// Sole with a heel pad insert: a "rubber" parallelepiped sole with a softer
// "heel_pad" block let into its bottom under the heel (x < 0 end). Frame and
// surface groups as in sole_box.geo (top face at z = 0, sole below; physical
// surfaces top / bottom / sides). Tetrahedra only (OpenCASCADE fragments).
SetFactory("OpenCASCADE");
DefineConstant[
  SoleLength = {0.2172, Name "Length (m)"},
  SoleWidth = {0.138, Name "Width (m)"},
  SoleThickness = {0.020, Name "Thickness (m)"},
  PadLength = {0.06, Name "Heel pad length along x (m)"},
  PadWidth = {0.08, Name "Heel pad width along y (m)"},
  PadDepth = {0.5, Name "Heel pad depth / thickness"},
  PadInset = {0.02, Name "Heel pad distance from the heel end (m)"},
  SoleMeshSize = {0.01, Name "Mesh size (m)"},
  SoleHex = {0, Name "Ignored: tetrahedra only"}
];
Box(1) = {-SoleLength/2, -SoleWidth/2, -SoleThickness, SoleLength, SoleWidth, SoleThickness};
Box(2) = {-SoleLength/2 + PadInset, -PadWidth/2, -SoleThickness, PadLength, PadWidth,
          PadDepth * SoleThickness};
v() = BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; };
eps = 1e-6;
bottom() = Surface In BoundingBox{-SoleLength/2 - eps, -SoleWidth/2 - eps, -SoleThickness - eps,
                                  SoleLength/2 + eps, SoleWidth/2 + eps, -SoleThickness + eps};
top() = Surface In BoundingBox{-SoleLength/2 - eps, -SoleWidth/2 - eps, -eps,
                               SoleLength/2 + eps, SoleWidth/2 + eps, eps};
sides() = Abs(CombinedBoundary{ Volume{v()}; });
sides() -= bottom();
sides() -= top();
pad() = Volume In BoundingBox{-SoleLength/2 + PadInset - eps, -PadWidth/2 - eps,
                              -SoleThickness - eps, -SoleLength/2 + PadInset + PadLength + eps,
                              PadWidth/2 + eps, -SoleThickness + PadDepth * SoleThickness + eps};
rubber() = v();
rubber() -= pad();
Physical Surface("bottom") = {bottom()};
Physical Surface("top") = {top()};
Physical Surface("sides") = {sides()};
Physical Volume("rubber") = {rubber()};
Physical Volume("heel_pad") = {pad()};
Mesh.CharacteristicLengthMax = SoleMeshSize;
