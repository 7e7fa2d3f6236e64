// Downstream program built against the installed mixcon: assembles and solves, with the public
// kernel and solver API, a small clamped strip (2D Quad8, tip deflection against beam theory) and
// a 3D Hex8 bar in uniaxial tension (issue 17; exact against Hooke's law).
#include <mixcon/kernels/Material.hpp>
#include <mixcon/mesh/Generators.hpp>
#include <mixcon/solver/DisplacementModel.hpp>
#include <mixcon/solver/Environment.hpp>
#include <mixcon_version.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace {

using namespace mixcon;

/// Cantilever strip 10 x 1 of Quad8, clamped at x = 0, end load P = -1: within 2% of P L^3/(3EI).
bool strip2D() {
  const Mesh mesh = rectangleMesh(10.0, 1.0, 40, 4, ElementType::Quad8, 0.0, -0.5);
  LinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0),
                                {isotropicStiffness(1.0e4, 0.0, PlaneAnalysis::PlaneStress)}, 1.0);
  for (LocalIndex n : mesh.nodesOf("left")) {
    model.prescribe(n, 0, 0.0);
    if (std::abs(mesh.y(n)) < 1e-12)
      model.prescribe(n, 1, 0.0);
  }
  model.addEdgeLoad(mesh.boundaries.at("right"), 0.0, -1.0, 0.0); // total P = -1
  model.setup(LinearSolverOptions{}, MPI_COMM_WORLD);
  const auto stats = model.solve(1.0);
  const auto u = model.displacementHost();
  const LocalIndex tip = mesh.nodeSets.at("top_right").front();
  const double beam = -1000.0 / (3.0 * 1.0e4 / 12.0); // P L^3 / (3 E I), shear adds ~0.5%
  std::printf("mixcon %s downstream: tip %.6f, beam %.6f, %d AMG iterations\n",
              MIXCON_VERSION_STRING, u[2 * tip + 1], beam, stats.iterations);
  return stats.converged && std::abs(u[2 * tip + 1] / beam - 1.0) < 0.02;
}

/// Bar 4 x 1 x 1 of Hex8, symmetry supports on x = 0, y = 0, z = 0 (rollers), traction s on
/// x = 4: the exact solution u = (s x, -nu s y, -nu s z) / E is linear, so the elements
/// reproduce it to the solver's tolerance at every node.
bool bar3D() {
  const double lx = 4.0, e = 210.0, nu = 0.3, s = 2.5;
  const Mesh mesh = boxMesh(lx, 1.0, 1.0, 8, 2, 2, ElementType::Hex8);
  LinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0),
                                {IsotropicMaterial{e, nu}.stiffness()});
  for (LocalIndex n : mesh.nodesOf("xmin"))
    model.prescribe(n, 0, 0.0);
  for (LocalIndex n : mesh.nodesOf("ymin"))
    model.prescribe(n, 1, 0.0);
  for (LocalIndex n : mesh.nodesOf("zmin"))
    model.prescribe(n, 2, 0.0);
  model.addSideLoad(mesh.boundaries.at("xmax"), {s, 0.0, 0.0}, 0.0);
  LinearSolverOptions options;
  options.tolerance = 1e-12;
  model.setup(options, MPI_COMM_WORLD);
  const auto stats = model.solve(1.0);
  const auto u = model.displacementHost();
  const double tipReference = s * lx / e, lateralReference = -nu * s / e; // at y = 1
  double error = 0.0; // max over nodes and components, relative to the tip displacement
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
    const double exact[3] = {s * mesh.x(n) / e, -nu * s * mesh.y(n) / e, -nu * s * mesh.z(n) / e};
    for (int i = 0; i < 3; ++i)
      error = std::max(error, std::abs(u[3 * n + i] - exact[i]) / tipReference);
  }
  const LocalIndex tip = mesh.nodeSets.at("corner_111").front();
  std::printf("mixcon %s downstream 3D: Hex8 bar tip ux %.12f (s L/E %.12f), uy %.12f "
              "(-nu s/E %.12f), max relative error %.2e, %d AMG iterations\n",
              MIXCON_VERSION_STRING, u[3 * tip], tipReference, u[3 * tip + 1], lateralReference,
              error, stats.iterations);
  return stats.converged && error < 1e-8;
}

} // namespace

int main(int argc, char **argv) {
  mixcon::Environment env(argc, argv);
  const bool strip = strip2D();
  const bool bar = bar3D();
  return (strip && bar) ? 0 : 1;
}
