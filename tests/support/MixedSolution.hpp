// What the linear mixed model's tests compare between two solves of the same problem: the
// displacements, nodal stresses and reactions read back from a MixedModel after solve(), and the
// largest difference relative to the reference's largest entry; one solve of the DESIGN-NOTES
// strip. Tests only.
#pragma once
#include <support/Differences.hpp>

#include <mesh/Generators.hpp>
#include <solver/MixedModel.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace mixcon::test {

/// One solve of a set-up MixedModel and its fields on the host.
struct MixedSolution {
  std::vector<double> u, s, reaction; ///< displacements, nodal stresses, reactions
  LinearSolveStats stats;
};

/// Solves `model` (set up) at load factor `load` and reads its fields back.
inline MixedSolution solveMixed(MixedModel &model, double load = 1.0) {
  MixedSolution r;
  r.stats = model.solve(load);
  r.u = model.displacementHost();
  r.s = model.nodalStressHost();
  r.reaction = model.reactionHost(load);
  return r;
}

/// What one solve of the strip reports.
struct StripSolve {
  long unknowns = 0; ///< 5 per node
  LinearSolveStats stats;
  std::string solverName;
  long innerIterations = 0;
};

/// The DESIGN-NOTES strip 4 x 1 (4 ny x ny elements; E = 1, nu = 0.3, plane stress), clamped at
/// x = 0, end shear 1e-3, set up with `o` and solved once.
inline StripSolve solveShearedStrip(ElementType type, int ny, const MixedOptions &o) {
  const Mesh mesh = rectangleMesh(4.0, 1.0, 4 * ny, ny, type);
  MixedModel model(mesh, std::vector<int>(mesh.numElements(), 0),
                   {isotropicStiffness(1.0, 0.3, PlaneAnalysis::PlaneStress)}, 1.0);
  for (LocalIndex n : mesh.nodesOf("left")) {
    model.prescribe(n, 0, 0.0);
    model.prescribe(n, 1, 0.0);
  }
  model.addEdgeLoad(mesh.boundaries.at("right"), 0.0, 1e-3, 0.0);
  model.setup(o, MPI_COMM_WORLD);
  StripSolve r;
  r.unknowns = 5L * mesh.numNodes();
  r.stats = model.solve(1.0);
  r.solverName = model.solverName();
  r.innerIterations = model.innerIterations();
  return r;
}

} // namespace mixcon::test
