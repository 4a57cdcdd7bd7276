// stepcontact example: a concrete block (2 m x 1 m) on a rock foundation (4 m x 1 m).
//
// The block's bottom (curve 5) and the foundation's top (curve 3) are different curves with
// different mesh sizes, so the two meshes do not match along the joint: the contact finite
// elements are mortar (segment-to-segment).  Mesh it (gmsh Python package) with
//
//   python -c "from stepcontact.io.meshfile import mesh_geo; mesh_geo('gmsh_block.geo')"
//
// which writes gmsh_block.msh next to this file.  Units: m.

// foundation: structured quads, 10 x 3 cells (0.4 m along the joint)
Point(1) = {0, 0, 0};
Point(2) = {4, 0, 0};
Point(3) = {4, 1, 0};
Point(4) = {0, 1, 0};
Line(1) = {1, 2};          // base
Line(2) = {2, 3};
Line(3) = {3, 4};          // foundation top (S-)
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 11;
Transfinite Curve{2, 4} = 4;
Transfinite Surface{1};
Recombine Surface{1};

// block: unstructured triangles of about 0.25 m
lc = 0.25;
Point(5) = {1, 1, 0, lc};
Point(6) = {3, 1, 0, lc};
Point(7) = {3, 2, 0, lc};
Point(8) = {1, 2, 0, lc};
Line(5) = {5, 6};          // block bottom (S+)
Line(6) = {6, 7};
Line(7) = {7, 8};
Line(8) = {8, 5};          // left face, pushed
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(2) = {2};

Physical Surface("foundation") = {1};
Physical Surface("block") = {2};
Physical Curve("base") = {1};
Physical Curve("foundation_top") = {3};
Physical Curve("block_bottom") = {5};
Physical Curve("push_face") = {8};
Physical Point("block_top_left") = {8};
