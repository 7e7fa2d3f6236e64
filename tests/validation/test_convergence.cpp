// Manufactured-solution convergence: u = (sin(pi x) sin(pi y), sin(2 pi x) sin(pi y)) on the unit
// square, isotropic plane stress, exact Dirichlet data; body force f = -div(C eps(u)) derived by
// hand below. Displacement L2 error must
// fall at rate ~2 (Quad4) and ~3 (Quad8) (Strang & Fix, An Analysis of the FEM, ch. 3: O(h^{p+1})).
#include <mesh/Generators.hpp>
#include <solver/DisplacementModel.hpp>
#include <support/Reference.hpp>

#include <gtest/gtest.h>

using namespace mixcon;

namespace {
constexpr double kPi = 3.14159265358979323846;

// Exact field and its body force f = -div(C eps(u)) for isotropic plane stress.
std::array<double, 2> exactU(double x, double y) {
  return {std::sin(kPi * x) * std::sin(kPi * y), std::sin(2 * kPi * x) * std::sin(kPi * y)};
}

double l2Error(ElementType type, int n) {
  Mesh mesh = rectangleMesh(1.0, 1.0, n, n, type);
  const double e = 1.0, nu = 0.3;
  const PlaneMatrix c = isotropicStiffness(e, nu, PlaneAnalysis::PlaneStress);
  LinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0), {c}, 1.0);
  for (const char *side : {"left", "right", "bottom", "top"})
    for (LocalIndex k : mesh.nodesOf(side)) {
      const auto u = exactU(mesh.x(k), mesh.y(k));
      model.prescribe(k, 0, u[0]);
      model.prescribe(k, 1, u[1]);
    }
  // f1 = -(c11 u1,xx + c66 u1,yy + (c12 + c66) u2,xy), f2 = -(c66 u2,xx + c11 u2,yy + (c12 + c66)
  // u1,xy)
  const double c11 = c.m[0][0], c12 = c.m[0][1], c66 = c.m[2][2], p2 = kPi * kPi;
  model.addBodyForce([=](double x, double y, LocalIndex) {
    const double u1 = std::sin(kPi * x) * std::sin(kPi * y);
    const double u2 = std::sin(2 * kPi * x) * std::sin(kPi * y);
    const double u1xy = p2 * std::cos(kPi * x) * std::cos(kPi * y);
    const double u2xy = 2 * p2 * std::cos(2 * kPi * x) * std::cos(kPi * y);
    return std::array<double, 2>{-(c11 * -p2 * u1 + c66 * -p2 * u1 + (c12 + c66) * u2xy),
                                 -(c66 * -4 * p2 * u2 + c11 * -p2 * u2 + (c12 + c66) * u1xy)};
  });
  LinearSolverOptions o;
  o.type = LinearSolverType::Direct;
  model.setup(o, MPI_COMM_WORLD);
  EXPECT_TRUE(model.solve(1.0).converged);
  const auto u = model.displacementHost();
  double err = 0.0;
  const int npe = mesh.nodesPerElement;
  for (LocalIndex el = 0; el < mesh.numElements(); ++el) {
    const Eigen::MatrixXd xe = test::elementCoordinates(mesh, el);
    for (const auto &g : test::referenceGauss(3)) { // 3x3 is exact enough for both
      Eigen::VectorXd sh;
      Eigen::MatrixXd dn;
      test::referenceShape(npe, g[0], g[1], sh, dn);
      const Eigen::Vector2d x = xe.transpose() * sh;
      double uh[2] = {0, 0};
      for (int a = 0; a < npe; ++a)
        for (int k = 0; k < 2; ++k)
          uh[k] += sh(a) * u[2 * mesh.node(el, a) + k];
      const auto ue = exactU(x(0), x(1));
      const double w = g[2] * (xe.transpose() * dn).determinant();
      err += w * ((uh[0] - ue[0]) * (uh[0] - ue[0]) + (uh[1] - ue[1]) * (uh[1] - ue[1]));
    }
  }
  return std::sqrt(err);
}
} // namespace

/// Errors on n0, 2 n0, 4 n0 elements per side; the rate of the last refinement must be `rate`.
void expectRate(ElementType type, const char *name, int n0, double rate, double tolerance) {
  const double e1 = l2Error(type, n0), e2 = l2Error(type, 2 * n0), e3 = l2Error(type, 4 * n0);
  const double r1 = std::log2(e1 / e2), r2 = std::log2(e2 / e3);
  std::cout << name << " L2 errors " << e1 << " " << e2 << " " << e3 << " rates " << r1 << " " << r2
            << "\n";
  EXPECT_NEAR(r2, rate, tolerance);
  EXPECT_LT(e3, e1);
}

TEST(Convergence, Quad4DisplacementL2RateIsTwo) {
  expectRate(ElementType::Quad4, "Quad4", 8, 2.0, 0.15);
}

TEST(Convergence, Quad8DisplacementL2RateIsThree) {
  expectRate(ElementType::Quad8, "Quad8", 4, 3.0, 0.2);
}
