// Structured mesh generators: Quad4 / Quad8 for the report's geometries and the closed-form
// validation cases, Hex8, Hex20, Tet4 and Tet10 boxes for the 3D solids (issue 17). Layer: mesh,
// the first stage of the data flow (mesh -> kernels -> ...).
#pragma once

#include <mesh/Mesh.hpp>

#include <string>
#include <vector>

namespace mixcon {

/// Raised by the generators below for arguments that cannot make a mesh. The message names the
/// generator but no file location: a problem reader adds the one of the `generator:` entry (and
/// adds it to these errors only, so that a message carries one location).
class GeneratorError : public InputError {
public:
  using InputError::InputError;
};

/// The 2D generators below take Quad4 or Quad8 and throw GeneratorError for a 3D element type.

/// Rectangle [x0, x0 + lx] x [y0, y0 + ly] with nx x ny elements; grading exponents gx, gy > 1
/// cluster the elements toward x0 and y0 (x = x0 + lx u^gx; 1: uniform).
/// Region "body"; boundaries "left", "right", "bottom", "top"; node sets "bottom_left",
/// "bottom_right", "top_left", "top_right" (the corners), "left_center", "right_center" (the
/// nodes closest to the mid-height of the left and right sides).
Mesh rectangleMesh(double lx, double ly, int nx, int ny, ElementType type, double x0 = 0.0,
                   double y0 = 0.0, double gx = 1.0, double gy = 1.0);

/// Box [x0, x0 + lx] x [y0, y0 + ly] x [z0, z0 + lz] of nx x ny x nz Hex8 or Hex20 elements, or
/// of 6 nx ny nz Tet4 or Tet10 elements (`type` one of these four); grading exponents gx, gy, gz >
/// 1 cluster the elements toward x0, y0, z0 (grid line i at x = x0 + lx (i / nx)^gx; 1: uniform).
/// Hex8: nodes numbered x fastest, then y, then z. Hex20: the nodes are the points of the
/// half-step lattice (2 nx + 1) x (2 ny + 1) x (2 nz + 1) (point (I, J, K) at the grid line I / 2
/// for even I, at the middle of grid lines (I - 1) / 2 and (I + 1) / 2 for odd I: every element
/// edge is straight and its mid-edge node at its middle, also when graded) with at most one odd
/// index (corners and mid-edge nodes, no face or cell centres), numbered in lexicographic order,
/// I fastest, then J, then K; (nx + 1)(ny + 1)(nz + 1) corners plus nx (ny + 1)(nz + 1) +
/// (nx + 1) ny (nz + 1) + (nx + 1)(ny + 1) nz mid-edge nodes. Element nodes in the element's
/// order (core/ElementTraits.hpp: Hex8, the face z- counter-clockwise seen from +z, then the face
/// z+; Hex20, those corners, then the mid-edge nodes in VTK's order). Region "body"; boundaries
/// "xmin", "xmax", "ymin", "ymax", "zmin", "zmax" (element faces, sideNode numbers: 0 z-, 1 z+,
/// 2 y-, 3 x+, 4 y+, 5 x-); node sets "corner_000" ... "corner_111" (the corners; the digits say
/// x, y, z at their minimum 0 or maximum 1), "xmin_center" and "xmax_center" (the node, corner
/// or mid-edge, of face x = x0 or x = x0 + lx closest to the centre of that face).
/// Tet4 / Tet10: each grid cell is split into 6 tetrahedra that share the cell's main diagonal
/// (Hex8 corner 0 to corner 6; the same direction in every cell, so the split is conforming),
/// each with a positive Jacobian; cells in the hexahedra's order, 6 consecutive elements per
/// cell. Tet4 nodes are the Hex8 nodes; Tet10 nodes are every point of the half-step lattice
/// (the cut face diagonals and the cell diagonal carry mid-edge nodes too), numbered I fastest.
/// Boundaries: the triangles on the box faces, as {element, face} in Tet4::sideNode numbering;
/// node sets as for the hexahedra. Throws
/// GeneratorError naming the generator "box" for non-positive sizes, divisions or gradings,
/// another element type, or a mesh whose node or connectivity indices would not fit a
/// LocalIndex.
Mesh boxMesh(double lx, double ly, double lz, int nx, int ny, int nz, ElementType type,
             double x0 = 0.0, double y0 = 0.0, double z0 = 0.0, double gx = 1.0, double gy = 1.0,
             double gz = 1.0);

/// Several bodies in one mesh (one element type), each translated by its offset: nodes and
/// elements concatenated in order; a body's region is named after it (its regions "B.R" when it
/// has several), its boundaries and node sets "B.name". Bodies share no nodes (contact couples
/// them). Throws InputError for mixed element types or repeated names, and for 3D meshes (the
/// offsets and the overlap check are planar: several bodies are 2D only so far, issue 17).
struct MeshBody {
  std::string name;
  Mesh mesh;
  double offset[2] = {0.0, 0.0};
};
Mesh mergeMeshes(const std::vector<MeshBody> &bodies);

/// The 2D mesh `plane` (Quad4 or Quad8, counter-clockwise) extruded along z from 0 to `length`
/// in `layers` layers (grid line k at z = length (k / layers)^grading): Quad4 makes Hex8, Quad8
/// makes Hex20 (the section's nodes at every grid line, its corner nodes also half way between:
/// the vertical mid-edge nodes). Node numbering: the plane's nodes at grid line 0, 1, ..., then
/// the Hex20 half-way nodes layer by layer. Elements layer by layer in the plane's order, with its
/// regions. Boundaries: each 2D boundary becomes the faces its edges sweep (same name), plus
/// "zmin" (z = 0) and "zmax" (z = length); each node set becomes the nodes above its nodes (a
/// line along z). Throws GeneratorError naming "extrude" for a 3D `plane`, non-positive length,
/// layers or grading.
Mesh extrudeMesh(const Mesh &plane, double length, int layers, double grading = 1.0);

/// Octant x, y, z >= 0 of the spherical shell a <= r <= b centred at the origin (a thick-walled
/// sphere's symmetry octant), of Hex8, Hex20, Tet4 or Tet10 elements: three patches of the cubed
/// sphere (the octant's three quarter faces of the cube |x|_inf = 1 projected radially, at equal
/// angles, n x n each) times m radial layers (grid line k at r = a + (b - a) (k / m)^grading:
/// > 1 clusters the layers toward r = a), each patch a box mesh (boxMesh: its Hex20 and Tet10
/// mid-edge nodes mapped too, so edges follow the spheres) with the patches' shared nodes merged.
/// Region "body"; boundaries "inner" (r = a), "outer" (r = b), "xmin", "ymin", "zmin" (the
/// symmetry planes x = 0, y = 0, z = 0); node sets "inner_x", "inner_y", "inner_z", "outer_x",
/// "outer_y", "outer_z" (the nodes on the axes). 3 n^2 m hexahedra (6 times as many tetrahedra).
/// Throws GeneratorError naming "sphere_shell" for b <= a, non-positive arguments or a 2D type.
Mesh sphereShellMesh(double a, double b, int n, int m, ElementType type, double grading = 1.0);

/// Quarter annulus a <= r <= b, 0 <= theta <= pi/2 centred at the origin, nr radial x nt
/// circumferential elements (radial spacing grows geometrically by `ratio` from r = a).
/// Region "body"; boundaries "inner", "outer", "bottom" (y = 0), "left" (x = 0).
Mesh quarterAnnulusMesh(double a, double b, int nr, int nt, ElementType type, double ratio = 1.0);

/// Quarter of a w x h rectangular plate (0 <= x <= w, 0 <= y <= h) with a circular hole of radius
/// a at the origin: two mapped blocks split at the corner ray, nr radial elements, nt elements
/// per block around the hole (radial grading `ratio` from the hole).
/// Region "body"; boundaries "hole", "right" (x = w), "top" (y = h), "bottom" (y = 0),
/// "left" (x = 0).
Mesh plateWithHoleMesh(double a, double w, double h, int nr, int nt, ElementType type,
                       double ratio = 1.0);

/// Quarter disk of radius r centred at the origin (x, y >= 0) as an O-grid: a square core of
/// n x n elements and two curved blocks of n x m elements out to the arc.
/// Region "body"; boundaries "arc", "bottom" (y = 0), "left" (x = 0); node sets "center",
/// "arc_bottom" (r, 0), "arc_left" (0, r). Grading exponents >= 1 cluster elements toward the arc
/// point (0, r) along the arc (angularGrading: parameter u -> u^p) and toward the arc radially
/// (radialGrading: s -> 1 - (1 - s)^q), for contact at (0, r); 1, 1 is uniform.
Mesh quarterDiskMesh(double r, int n, int m, ElementType type, double angularGrading = 1.0,
                     double radialGrading = 1.0);

/// Half disk of radius r centred at the origin (y >= 0) as an O-grid: a core [-r/2, r/2] x
/// [0, r/2] of 2n x n elements and three curved blocks (0-45, 45-135, 135-180 degrees) m
/// elements deep, so 4 n arc segments spaced every 45 / n degrees (a pin in a half model).
/// Region "body"; boundaries "arc", "bottom" (y = 0); node sets "center", "arc_right" (r, 0),
/// "arc_left" (-r, 0). Grading as quarterDiskMesh's: `angularGrading` > 1 clusters the core's x
/// and the top block's arc segments symmetrically toward the top (0, r) (a contact there),
/// `radialGrading` > 1 the curved blocks' layers toward the arc.
Mesh halfDiskMesh(double r, int n, int m, ElementType type, double angularGrading = 1.0,
                  double radialGrading = 1.0);

/// Half of a pin-loaded plate (y >= 0, symmetric about y = 0): a strip -e <= x <= l,
/// 0 <= y <= b with a hole of radius r at the origin. An O-grid of three sectors of 60 degrees
/// around the hole (n elements each along the hole, m radially, geometric growth `ratio` away
/// from the hole) fills [-a, a] x [0, b] with a = b / sqrt(3), so that the hole nodes are evenly
/// spaced every 60 / n degrees; an end block of nEnd columns fills [-e, -a] and a far block of
/// nFar columns [a, l] (both n rows, columns growing by `ratio` away from the hole).
/// Elements: 3 n m + n (nEnd + nFar); with n = 4, m = 6, nEnd = 4, nFar = 9 these are the
/// report's 124 elements and 156 nodes. Region "body"; boundaries "hole", "bottom" (y = 0, the
/// symmetry line), "top" (y = b), "end" (x = -e, the free end beyond the hole), "far"
/// (x = l); node sets "hole_bearing" (-r, 0), "hole_top" (0, r), "far_bottom" (l, 0).
Mesh pinnedPlateMesh(double r, double b, double e, double l, int n, int m, int nEnd, int nFar,
                     ElementType type, double ratio = 1.0);

namespace detail {
/// GeneratorError "mesh generator <gen>: <what> must be positive" unless v > 0 (the generators'
/// shared argument check, mesh/Generators.cpp and mesh/SolidGenerators.cpp).
void requirePositive(const char *what, double v, const std::string &gen);
} // namespace detail

} // namespace mixcon
