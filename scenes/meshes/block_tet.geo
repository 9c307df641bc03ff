// A unit cube [-0.5, 0.5] x [-0.5, 0.5] x [0, 1] of linear tetrahedra, size 1/8, with its
// faces as physical surfaces. The same block as block_hex.inp (hex8).
// Made with:  gmsh -3 -format msh41 block_tet.geo -o block_tet.msh   (Gmsh 4.15, ASCII)
SetFactory("OpenCASCADE");
Box(1) = {-0.5, -0.5, 0, 1, 1, 1};
Mesh.MeshSizeMin = 0.125;
Mesh.MeshSizeMax = 0.125;
Mesh.ElementOrder = 1;
Mesh.Optimize = 1;
e = 1e-6;
bottom() = Surface In BoundingBox{-1, -1, -e, 1, 1, e};
top() = Surface In BoundingBox{-1, -1, 1 - e, 1, 1, 1 + e};
sides() = Surface{:};
sides() -= bottom();
sides() -= top();
Physical Surface("bottom") = bottom();
Physical Surface("top") = top();
Physical Surface("sides") = sides();
Physical Volume("block") = {1};
