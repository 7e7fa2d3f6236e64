// The linear displacement model in 3D (Hex8) against exact solutions and a closed form:
// - patch test (Irons & Razzaque; MacNeal & Harder 1985): on a distorted Hex8 mesh, a linear
//   displacement field prescribed on the boundary is reproduced exactly inside, with the constant
//   stress C eps at every node (a rotated orthotropic solid, all 21 entries of C non-zero), and no
//   reactions at interior nodes; direct and AMG solvers.
// - uniaxial bar: a traction s on one end, symmetry planes on the other three sides: u = s x / E,
//   v = -nu s y / E, w = -nu s z / E and sigma_xx = s (Hooke's law; exact for trilinear elements).
// - cantilever: tip deflection against Timoshenko's beam with shear, P L^3 / (3 E I) +
//   P L / (kappa G A), kappa = 5/6 (Timoshenko & Gere, Mechanics of Materials, sec. 9.11): the
//   error of full-integration Hex8 (which locks in bending) falls with refinement and is within
//   2% on 80 x 8 x 8 elements (13.1%, 4.3%, 1.65% measured on 20 x 2 x 2, 40 x 4 x 4,
//   80 x 8 x 8); Hex20 on 20 x 2 x 2 elements within 1.5% (1.05% measured).
#include <mesh/Generators.hpp>
#include <solver/DisplacementModel.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using namespace mixcon;

namespace {

/// A rotated orthotropic solid: every entry of its Voigt stiffness is non-zero.
SolidMatrix rotatedOrthotropic() {
  OrthotropicConstants k{1.6e3, 1.1e2, 0.9e2, 1.0e2, 0.4, 0.3, 0.35, 0.8e2, 0.6e2};
  return OrthotropicMaterial{
      k, matmul(rotationAboutZ(0.7), matmul(rotationAboutX(0.4), rotationAboutY(-0.3)))}
      .stiffness();
}

/// The linear field of the patch test and its (engineering) strain.
std::array<double, 3> patchField(double x, double y, double z) {
  return {1e-3 * (1.0 + 2.0 * x - 0.5 * y + 0.7 * z), 1e-3 * (-0.5 + 0.3 * x + 1.1 * y - 0.4 * z),
          1e-3 * (0.2 - 0.6 * x + 0.9 * y + 1.3 * z)};
}
Vector<6> patchStrain() {
  // xx, yy, zz, yz, xz, xy of the gradient of patchField.
  return Vector<6>{
      {2e-3, 1.1e-3, 1.3e-3, (-0.4 + 0.9) * 1e-3, (0.7 - 0.6) * 1e-3, (-0.5 + 0.3) * 1e-3}};
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
Mesh distortedBox(int n, ElementType type) {
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

} // namespace

class SolidPatchTest : public ::testing::TestWithParam<std::tuple<ElementType, LinearSolverType>> {
};
INSTANTIATE_TEST_SUITE_P(
    Elements, SolidPatchTest,
    ::testing::Combine(::testing::Values(ElementType::Hex8, ElementType::Hex20, ElementType::Tet4,
                                         ElementType::Tet10),
                       ::testing::Values(LinearSolverType::Direct, LinearSolverType::Amg)),
    [](const auto &info) {
      return elementTypeName(std::get<0>(info.param)) +
             (std::get<1>(info.param) == LinearSolverType::Amg ? "Amg" : "Direct");
    });

TEST_P(SolidPatchTest, ReproducesALinearFieldExactly) {
  const auto [type, solver] = GetParam();
  const Mesh mesh = distortedBox(3, type);
  const SolidMatrix c = rotatedOrthotropic();
  LinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0), {c});
  std::vector<char> onBoundary(mesh.numNodes(), 0);
  for (const char *face : {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"})
    for (LocalIndex p : mesh.nodesOf(face)) {
      onBoundary[p] = 1;
      const auto ue = patchField(mesh.x(p), mesh.y(p), mesh.z(p));
      for (int i = 0; i < 3; ++i)
        model.prescribe(p, i, ue[i]);
    }
  LinearSolverOptions o;
  o.type = solver;
  o.tolerance = 1e-13;
  model.setup(o, MPI_COMM_WORLD);
  ASSERT_TRUE(model.solve(1.0).converged);
  const auto u = model.displacementHost();
  int interior = 0;
  for (LocalIndex p = 0; p < mesh.numNodes(); ++p) {
    const auto ue = patchField(mesh.x(p), mesh.y(p), mesh.z(p));
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(u[3 * p + i], ue[i], 1e-13) << "node " << p << " component " << i;
    interior += !onBoundary[p];
  }
  EXPECT_GE(interior, 8); // free interior nodes to get right
  const Vector<6> sigma = matvec(c, patchStrain());
  const auto s = model.nodalStressHost();
  ASSERT_EQ(s.size(), 6 * static_cast<std::size_t>(mesh.numNodes()));
  for (LocalIndex p = 0; p < mesh.numNodes(); ++p)
    for (int k = 0; k < 6; ++k)
      ASSERT_NEAR(s[6 * p + k], sigma.v[k], 1e-9 * std::abs(sigma.v[0])) << "node " << p;
  std::vector<double> xq, sq;
  int perElement = 0;
  model.gaussPointStressHost(xq, sq, perElement);
  const int qp = dispatchElement(type, [](auto elem) { return decltype(elem)::kNumQp; });
  EXPECT_EQ(perElement, qp);
  ASSERT_EQ(sq.size(), 6u * qp * mesh.numElements());
  for (std::size_t k = 0; k < sq.size(); ++k)
    ASSERT_NEAR(sq[k], sigma.v[k % 6], 1e-9 * std::abs(sigma.v[0]));
  const auto r = model.reactionHost(1.0);
  for (LocalIndex p = 0; p < mesh.numNodes(); ++p)
    if (!onBoundary[p]) {
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(r[3 * p + i], 0.0, 1e-9 * std::abs(sigma.v[0])) << "node " << p;
    }
}

TEST(SolidBar, UniaxialTractionGivesHookesLaw) {
  // 4 x 1 x 1 bar, symmetry planes x = 0, y = 0, z = 0, traction s on x = 4 (distorted inside).
  Mesh mesh = boxMesh(4.0, 1.0, 1.0, 8, 2, 3, ElementType::Hex8, 0.0, 0.0, 0.0, 1.3, 1.0, 1.2);
  const double e = 210.0, nu = 0.3, s = 2.5;
  LinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0),
                                {IsotropicMaterial{e, nu}.stiffness()});
  for (LocalIndex p : mesh.nodesOf("xmin"))
    model.prescribe(p, 0, 0.0);
  for (LocalIndex p : mesh.nodesOf("ymin"))
    model.prescribe(p, 1, 0.0);
  for (LocalIndex p : mesh.nodesOf("zmin"))
    model.prescribe(p, 2, 0.0);
  model.addSideLoad(mesh.boundaries.at("xmax"), {s, 0.0, 0.0}, 0.0);
  LinearSolverOptions o;
  o.type = LinearSolverType::Amg;
  o.tolerance = 1e-12;
  model.setup(o, MPI_COMM_WORLD);
  ASSERT_TRUE(model.solve(1.0).converged);
  const auto u = model.displacementHost();
  const auto sig = model.nodalStressHost();
  for (LocalIndex p = 0; p < mesh.numNodes(); ++p) {
    EXPECT_NEAR(u[3 * p], s * mesh.x(p) / e, 1e-10) << "node " << p;
    EXPECT_NEAR(u[3 * p + 1], -nu * s * mesh.y(p) / e, 1e-10) << "node " << p;
    EXPECT_NEAR(u[3 * p + 2], -nu * s * mesh.z(p) / e, 1e-10) << "node " << p;
    EXPECT_NEAR(sig[6 * p], s, 1e-8 * s);
    for (int k = 1; k < 6; ++k)
      EXPECT_NEAR(sig[6 * p + k], 0.0, 1e-8 * s);
  }
  // The support reaction balances the load: sum of rx over xmin = -s * area.
  const auto r = model.reactionHost(1.0);
  double rx = 0.0;
  for (LocalIndex p : mesh.nodesOf("xmin"))
    rx += r[3 * p];
  EXPECT_NEAR(rx, -s * 1.0, 1e-9 * s);
}

namespace {

/// The cantilever of both tests: L = 10, h = b = 1 (L/h = 10), E = 1000, nu = 0.3, clamped at
/// x = 0, a shear traction q = -0.01 on x = L (P = q b h).
struct Cantilever {
  double l = 10.0, h = 1.0, b = 1.0, e = 1000.0, nu = 0.3, q = -0.01;

  /// Timoshenko's beam with shear: P L^3 / (3 E I) + P L / (kappa G A), kappa = 5/6.
  double beamTheory() const {
    const double inertia = b * h * h * h / 12.0, area = b * h, g = e / (2.0 * (1.0 + nu));
    const double p = q * area;
    return p * l * l * l / (3.0 * e * inertia) + p * l / (5.0 / 6.0 * g * area);
  }
  /// uy at the end face x = L of an n x (n/10) x (n/10) mesh: the mean over the face's nodes
  /// (quadratic elements: over its corner nodes; the other nodes weigh differently), and the
  /// relative error against beamTheory() printed.
  double tipDeflection(int nx, ElementType type) const {
    const int ny = nx / 10;
    const Mesh mesh = boxMesh(l, h, b, nx, ny, ny, type);
    LinearDisplacementModel model(mesh, std::vector<int>(mesh.numElements(), 0),
                                  {IsotropicMaterial{e, nu}.stiffness()});
    for (LocalIndex k : mesh.nodesOf("xmin"))
      for (int i = 0; i < 3; ++i)
        model.prescribe(k, i, 0.0);
    model.addSideLoad(mesh.boundaries.at("xmax"), {0.0, q, 0.0}, 0.0);
    LinearSolverOptions o;
    o.type = LinearSolverType::Amg;
    o.tolerance = 1e-10;
    model.setup(o, MPI_COMM_WORLD);
    EXPECT_TRUE(model.solve(1.0).converged);
    const auto u = model.displacementHost();
    const auto atEdge = [](double x, double len) {
      return std::abs(std::abs(x - 0.5 * len) - 0.5 * len) < 1e-12;
    };
    double tip = 0.0;
    int count = 0;
    for (LocalIndex k : mesh.nodesOf("xmax"))
      if (type == ElementType::Hex8 || type == ElementType::Tet4 ||
          (atEdge(mesh.y(k), h) && atEdge(mesh.z(k), b))) {
        tip += u[3 * k + 1];
        ++count;
      }
    tip /= count;
    std::printf("  cantilever %d x %d x %d %s: tip %.6g, beam theory %.6g, error %.2f%%\n", nx, ny,
                ny, elementTypeName(type).c_str(), tip, beamTheory(),
                100.0 * std::abs(tip / beamTheory() - 1.0));
    return tip;
  }
};

} // namespace

TEST(SolidCantilever, TipDeflectionConvergesToBeamTheory) {
  const Cantilever c;
  const double reference = c.beamTheory();
  double previous = 1.0;
  for (int nx : {20, 40, 80}) { // 20 x 2 x 2, 40 x 4 x 4, 80 x 8 x 8
    const double tip = c.tipDeflection(nx, ElementType::Hex8);
    const double error = std::abs(tip - reference) / std::abs(reference);
    EXPECT_LT(error, previous) << nx;             // locking recedes with refinement
    EXPECT_LT(tip / reference, 1.0 + 1e-3) << nx; // too stiff, never too soft
    previous = error;
  }
  EXPECT_LT(previous, 0.02); // 80 x 8 x 8: 1.65% measured
}

TEST(SolidCantilever, Hex20IsCloseToBeamTheoryOnACoarseMesh) {
  // The same cantilever with 20-node elements, which do not lock: 20 x 2 x 2 elements.
  const Cantilever c;
  const double error = std::abs(c.tipDeflection(20, ElementType::Hex20) / c.beamTheory() - 1.0);
  // 1.05% measured: more accurate than 80 x 8 x 8 Hex8 (1.65%) with 1/64 of the elements; what
  // remains is mostly the difference between the clamped 3D solid and the beam (the Hex8 errors
  // extrapolate to about 0.8% as h -> 0).
  EXPECT_LT(error, 0.015);
}

TEST(SolidCantilever, Tet10IsCloseToBeamTheory) {
  // The cantilever on the box of 20 x 2 x 2 cells, each split into 6 Tet10.
  const Cantilever c;
  const double error = std::abs(c.tipDeflection(20, ElementType::Tet10) / c.beamTheory() - 1.0);
  // 1.11% measured (480 Tet10, 1,025 nodes), about Hex20's 1.05% on 20 x 2 x 2: what
  // remains is mostly the clamped 3D solid against the beam (see the Hex8 test).
  EXPECT_LT(error, 0.015);
}
