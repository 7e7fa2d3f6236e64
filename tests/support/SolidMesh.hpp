// Solid (3D) test meshes and materials shared by the 3D tests: a box mesh of any solid element
// with its interior nodes moved randomly (distortedBox), and a rotated orthotropic solid whose
// Voigt stiffness has all 21 entries non-zero.
#pragma once

#include <core/ElementTraits.hpp>
#include <kernels/Material.hpp>
#include <mesh/Generators.hpp>
#include <mesh/Mesh.hpp>

#include <cmath>
#include <random>
#include <vector>

namespace mixcon::test {

/// A rotated orthotropic solid: every entry of its Voigt stiffness is non-zero.
inline SolidMatrix rotatedOrthotropicSolid() {
  OrthotropicConstants k{1.6e3, 1.1e2, 0.9e2, 1.0e2, 0.4, 0.3, 0.35, 0.8e2, 0.6e2};
  return OrthotropicMaterial{
      k, matmul(rotationAboutZ(0.7), matmul(rotationAboutX(0.4), rotationAboutY(-0.3)))}
      .stiffness();
}

/// Moves the nodes of a solid box mesh of element Elem (distortedBox).
template <class Elem>
void distortSolid(Mesh &mesh, const double (&h)[3], const double (&len)[3], std::mt19937 &rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto onPlane = [&](double x, int i) {
    return std::abs(x) < 1e-12 || std::abs(x - len[i]) < 1e-12;
  };
  constexpr int corners = Elem::kSimplex ? 4 : 8;
  const double amplitude = Elem::kSimplex ? 0.1 : 0.2;
  std::vector<char> corner(mesh.numNodes(), 0), done(mesh.numNodes(), 0);
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    for (int a = 0; a < corners; ++a)
      corner[mesh.node(e, a)] = 1;
  for (LocalIndex p = 0; p < mesh.numNodes(); ++p)
    if (corner[p])
      for (int i = 0; i < 3; ++i) {
        double &x = mesh.coordinates[3 * static_cast<std::size_t>(p) + i];
        if (!onPlane(x, i))
          x += amplitude * u(rng) * h[i];
      }
  if constexpr (Elem::kNumNodes > corners)
    for (LocalIndex e = 0; e < mesh.numElements(); ++e)
      for (int k = 0; k < Elem::kNumNodes - corners; ++k) {
        const LocalIndex m = mesh.node(e, corners + k);
        if (done[m])
          continue;
        done[m] = 1;
        const LocalIndex c0 = mesh.node(e, Elem::edgeCorner(k, 0)),
                         c1 = mesh.node(e, Elem::edgeCorner(k, 1));
        for (int i = 0; i < 3; ++i) {
          double &x = mesh.coordinates[3 * static_cast<std::size_t>(m) + i];
          const bool fixed = onPlane(x, i);
          x = 0.5 * (mesh.coordinate(c0, i) + mesh.coordinate(c1, i));
          if (!fixed && !Elem::kSimplex)
            x += 0.04 * u(rng) * h[i];
        }
      }
}

/// A box mesh with every interior corner node moved randomly by up to 0.2 of a cell (0.1 for
/// tetrahedra, which are thinner); mid-edge nodes then sit at the middle of their moved corners,
/// for Hex20 plus up to 0.04 of a cell (curved edges). Tet10 keeps straight edges: its 4-point
/// rule (degree 2, as Abaqus' C3D10) integrates grad N det J exactly only on straight-sided
/// elements; on curved ones the patch test misses by about 1e-7 relative (measured), which a rule
/// of degree 3 would remove. Boundary nodes move within their face planes only, so the box keeps
/// its shape.
inline Mesh distortedBox(int n, ElementType type) {
  Mesh mesh = boxMesh(1.0, 1.5, 1.2, n, n + 1, n, type);
  std::mt19937 rng(7);
  const double h[3] = {1.0 / n, 1.5 / (n + 1), 1.2 / n}, len[3] = {1.0, 1.5, 1.2};
  dispatchElement(type, [&](auto elem) {
    using Elem = decltype(elem);
    if constexpr (Elem::kDim == 3)
      distortSolid<Elem>(mesh, h, len, rng);
  });
  validateMesh(mesh);
  return mesh;
}

} // namespace mixcon::test
