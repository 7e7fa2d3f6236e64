// The constant-stress patch test shared by the displacement-model and mixed-model patch tests:
// a distorted Quad4/Quad8 mesh, an orthotropic material at an angle, a linear displacement field
// prescribed on the whole boundary, and the constant stress it implies (the reference).
#pragma once

#include <mesh/Generators.hpp>
#include <solver/ModelBase.hpp>
#include <support/Reference.hpp>

#include <array>

namespace mixcon::test {

struct PatchCase {
  Mesh mesh;
  PlaneMatrix c;
  std::array<double, 3> sigma; ///< C eps of the linear field

  static std::array<double, 2> field(double x, double y) {
    return {1e-3 + 2e-3 * x - 1e-3 * y, -2e-3 + 5e-4 * x + 3e-3 * y};
  }
  /// Prescribes the linear field on the four sides.
  void prescribeBoundary(ModelBase &model) const {
    for (const char *side : {"left", "right", "bottom", "top"})
      for (LocalIndex n : mesh.nodesOf(side)) {
        const auto u = field(mesh.x(n), mesh.y(n));
        model.prescribe(n, 0, u[0]);
        model.prescribe(n, 1, u[1]);
      }
  }
};

inline PatchCase makePatchCase(ElementType type) {
  PatchCase p;
  p.mesh = rectangleMesh(2.0, 1.5, 5, 4, type, -0.3, 0.2);
  distortInterior(p.mesh, 0.4, 0.3, 11);
  validateMesh(p.mesh);
  p.c = orthotropicStiffness({1.6e6, 1.1e5, 1.1e5, 1.0e5, 0.4, 0.4, 0.4},
                             PlaneAnalysis::PlaneStress, 0.35);
  const double eps[3] = {2e-3, 3e-3, -5e-4}; // of field(): xx, yy, engineering xy
  double sig[3];
  applyStiffness(p.c, eps, sig);
  p.sigma = {sig[0], sig[1], sig[2]};
  return p;
}

} // namespace mixcon::test
