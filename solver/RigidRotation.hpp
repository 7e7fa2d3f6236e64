// The rigid-body rotations of a point set, one formula for every place that builds them: the
// check that the supports fix every rigid-body mode (RigidBodyModes.cpp), BoomerAMG's
// interpolation vectors and the rigid-body coarse space (LinearSolver.cpp, RigidCoarseSpace.cpp).
// Host code. Data flow: solver.
#pragma once

namespace mixcon {

/// Rigid rotations per dimension: 2D one (about z), 3D three (about x, y, z).
constexpr int rigidRotations(int dim) { return dim == 2 ? 1 : 3; }

/// Component c (0 .. dim-1) of rotation r at p, the point relative to the centre of rotation
/// (p[2] = 0 in 2D): e_a x p for the axis a (2D: z), so (-p_y, p_x) in 2D.
inline double rigidRotation(int dim, int r, int c, const double p[3]) {
  const int a = dim == 2 ? 2 : r, u = (a + 1) % 3, v = (a + 2) % 3;
  return c == u ? -p[v] : c == v ? p[u] : 0.0;
}

} // namespace mixcon
