// A quarter of a unit sphere (radius 1, centre at the origin, x >= 0, y >= 0) of linear
// tetrahedra, refined towards its south pole (0, 0, -1) where it strikes the plane: element
// size 0.01 within 0.15 of the pole, growing to 0.08 from 0.6 away. The centre is a mesh
// node (the probe of the approach). Physical groups: surfaces "skin", "symmetry_x" (the
// plane x = 0) and "symmetry_y" (y = 0), volume "ball".
// Made with:  gmsh -3 -format msh41 -bin sphere.geo -o sphere.msh   (Gmsh 4.15)
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 0, 1, -Pi/2, Pi/2, Pi/2};
Point(101) = {0, 0, -1, 0.01};
e = 1e-6;
symx() = Surface In BoundingBox{-e, -2, -2, e, 2, 2};
symy() = Surface In BoundingBox{-2, -e, -2, 2, e, 2};
skin() = Surface{:};
skin() -= symx();
skin() -= symy();

Field[1] = Distance;
Field[1].PointsList = {101};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = 0.01;
Field[2].SizeMax = 0.08;
Field[2].DistMin = 0.15;
Field[2].DistMax = 0.6;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.ElementOrder = 1;
Mesh.Optimize = 1;

Physical Surface("skin") = skin();
Physical Surface("symmetry_x") = symx();
Physical Surface("symmetry_y") = symy();
Physical Volume("ball") = {1};
