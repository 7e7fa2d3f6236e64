// Downstream program built against the installed mixcon: assembles and solves a small clamped
// strip with the public kernel and solver API and checks the tip deflection against beam theory.
#include <mixcon/mesh/Generators.hpp>
#include <mixcon/solver/DisplacementModel.hpp>
#include <mixcon/solver/Environment.hpp>
#include <mixcon_version.hpp>

#include <cmath>
#include <cstdio>

int main(int argc, char **argv) {
  mixcon::Environment env(argc, argv);
  using namespace mixcon;
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
  return (stats.converged && std::abs(u[2 * tip + 1] / beam - 1.0) < 0.02) ? 0 : 1;
}
