// 3D solids against closed forms of plane elasticity that hold exactly in 3D (issue 17):
// - Timoshenko's end-loaded cantilever (Timoshenko & Goodier, Theory of Elasticity, sec. 21),
//   exact in 3D with nu = 0: the nodal displacement and stress convergence rates of both models
//   on Hex8 and Hex20 (the tip deflection is beam theory's P L^3 / (3 E I));
// - the plate with a hole extruded (`plate_with_hole` + `extrude`): node for node the 2D plane
//   stress plate at nu = 0.
#include <kernels/Material.hpp>
#include <mesh/Generators.hpp>
#include <solver/DisplacementModel.hpp>
#include <solver/SolidMixedModel.hpp>
#include <support/Convergence.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

using namespace mixcon;

namespace {
/// Timoshenko's cantilever (Timoshenko & Goodier, Theory of Elasticity, sec. 21): x from the
/// loaded end (x = 0) to the clamp (x = L), y from the neutral axis (|y| <= c), the end load P
/// carried by the parabolic shear sigma_xy = -P (c^2 - y^2) / (2 I), sigma_xx = -P x y / I,
/// I = b (2c)^3 / 12. With nu = 0 this plane stress field, with u_z = 0, is an exact solution of
/// 3D elasticity on the prism of width b (no Poisson coupling across z; the faces z = 0, b and
/// y = +-c free), and its displacements, whose centroid at the clamp neither moves nor turns, are
/// the ones below: u_y(0, 0) = P L^3 / (3 E I), beam theory's tip deflection.
struct TimoshenkoCantilever {
  double l = 4.0, c = 0.5, b = 1.0, e = 1000.0, p = 0.1;
  double inertia() const { return b * 8.0 * c * c * c / 12.0; }
  double g() const { return 0.5 * e; } // nu = 0
  /// (u_x, u_y) at (x, y), y from the neutral axis.
  std::array<double, 2> displacement(double x, double y) const {
    const double i = inertia();
    return {-p * x * x * y / (2 * e * i) + p * y * y * y / (6 * i * g()) +
                (p * l * l / (2 * e * i) - p * c * c / (2 * i * g())) * y,
            p * x * x * x / (6 * e * i) - p * l * l * x / (2 * e * i) +
                p * l * l * l / (3 * e * i)};
  }
  double sigmaXx(double x, double y) const { return -p * x * y / inertia(); }
  double sigmaXy(double y) const { return -p * (c * c - y * y) / (2 * inertia()); }
  double tip() const { return p * l * l * l / (3 * e * inertia()); }
  double largestStress() const { return p * l * c / inertia(); }

  /// The largest nodal errors of the displacement model (stresses recovered) or of the mixed one
  /// (SolidMixedModel, a = 0.05; its nodal stresses) on boxMesh(l, 2c, b, 4m, m, m): the
  /// displacements over tip(), the stresses (any entry) over largestStress(). The clamp x = L
  /// takes the exact displacements; the end x = 0 the parabolic shear as consistent nodal
  /// forces (3 x 3 Gauss points on each face with its bilinear or serendipity shape functions:
  /// exact for this quadratic traction).
  std::array<double, 2> errors(ElementType type, int m, bool mixed) const {
    const Mesh mesh = boxMesh(l, 2 * c, b, 4 * m, m, m, type);
    const std::vector<int> material(mesh.numElements(), 0);
    const std::vector<SolidMatrix> stiffness{IsotropicMaterial{e, 0.0}.stiffness()};
    if (mixed) {
      SolidMixedModel model(mesh, material, stiffness, 0.05);
      return solve(mesh, type, m, model);
    }
    LinearDisplacementModel model(mesh, material, stiffness);
    return solve(mesh, type, m, model);
  }

  template <class Model>
  std::array<double, 2> solve(const Mesh &mesh, ElementType type, int m, Model &model) const {
    for (LocalIndex k : mesh.nodesOf("xmax")) {
      const auto u = displacement(l, mesh.y(k) - c);
      model.prescribe(k, 0, u[0]);
      model.prescribe(k, 1, u[1]);
      model.prescribe(k, 2, 0.0);
    }
    // the end x = 0: each face (a cell of the y-z grid) and its nodes found by their coordinates
    std::map<std::pair<long, long>, LocalIndex> at;
    const auto key = [](double y, double z) {
      return std::pair<long, long>{std::lround(y * 1e8), std::lround(z * 1e8)};
    };
    for (LocalIndex k : mesh.nodesOf("xmin"))
      at[key(mesh.y(k), mesh.z(k))] = k;
    const bool quadratic = type == ElementType::Hex20;
    std::vector<std::array<int, 2>> local = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    if (quadratic)
      local.insert(local.end(), {{0, -1}, {1, 0}, {0, 1}, {-1, 0}});
    const auto shape = [&](const std::array<int, 2> &n, double xi, double eta) {
      const double a = n[0], d = n[1];
      if (!quadratic)
        return 0.25 * (1 + a * xi) * (1 + d * eta);
      if (a == 0)
        return 0.5 * (1 - xi * xi) * (1 + d * eta);
      if (d == 0)
        return 0.5 * (1 + a * xi) * (1 - eta * eta);
      return 0.25 * (1 + a * xi) * (1 + d * eta) * (a * xi + d * eta - 1);
    };
    const double gp[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)},
                 gw[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    const double dy = 2 * c / m, dz = b / m;
    std::map<LocalIndex, double> force;
    double total = 0.0;
    for (int iy = 0; iy < m; ++iy)
      for (int iz = 0; iz < m; ++iz) {
        const double ym = (iy + 0.5) * dy, zm = (iz + 0.5) * dz;
        for (const auto &n : local) {
          const LocalIndex k = at.at(key(ym + 0.5 * n[0] * dy, zm + 0.5 * n[1] * dz));
          for (int q = 0; q < 3; ++q)
            for (int r = 0; r < 3; ++r) {
              // traction t_y = -sigma_xy on the face whose outward normal is -x
              const double f = -sigmaXy(ym + 0.5 * gp[q] * dy - c) * shape(n, gp[q], gp[r]) *
                               gw[q] * gw[r] * 0.25 * dy * dz;
              force[k] += f;
              total += f;
            }
        }
      }
    EXPECT_NEAR(total, p, 1e-12 * p); // the parabola carries the end load P
    for (const auto &[k, f] : force)
      model.addNodalForce(k, {0.0, f, 0.0});
    LinearSolverOptions o;
    o.type = LinearSolverType::Direct;
    model.setup(o, MPI_COMM_WORLD);
    EXPECT_TRUE(model.solve(1.0).converged);
    const auto u = model.displacementHost();
    const auto s = model.nodalStressHost();
    double eu = 0.0, es = 0.0;
    for (LocalIndex k = 0; k < mesh.numNodes(); ++k) {
      const double x = mesh.x(k), y = mesh.y(k) - c;
      const auto exact = displacement(x, y);
      eu = std::max({eu, std::abs(u[3 * k] - exact[0]), std::abs(u[3 * k + 1] - exact[1]),
                     std::abs(u[3 * k + 2])});
      for (int v = 0; v < 6; ++v) { // Voigt xx, yy, zz, yz, xz, xy
        const double sv = v == 0 ? sigmaXx(x, y) : v == 5 ? sigmaXy(y) : 0.0;
        es = std::max(es, std::abs(s[6 * k + v] - sv));
      }
    }
    return {eu / tip(), es / largestStress()};
  }
};
} // namespace

// The 3D cantilever against Timoshenko's elasticity solution of the end-loaded beam (Timoshenko &
// Goodier, Theory of Elasticity, sec. 21; with nu = 0 an exact 3D solution, see
// TimoshenkoCantilever), whose tip deflection is beam theory's P L^3 / (3 E I): the largest nodal
// displacement and stress errors of both models on Hex8 and Hex20 boxes of 4m x m x m elements
// (L = 4, height 1, width 1), refined twice. Measured with this test's printout (largest nodal
// errors over the tip deflection and over the largest stress P L c / I; rates):
//   displacement model (stresses recovered from the Gauss points):
//   Hex8  m = 2, 4, 8:  displacement 1.86, 1.96   stress 0.80, 0.93   (finest 8.1e-3, 7.5e-2)
//   Hex20 m = 1, 2, 4:  displacement 3.74, 3.67   stress 2.00, 1.99   (finest 9.6e-6, 2.6e-3)
//   mixed model (SolidMixedModel, a = 0.05; the stresses are its nodal unknowns):
//   Hex8  m = 2, 4, 8:  displacement 2.53, 1.97   stress 1.14, 1.05   (finest 4.3e-4, 1.5e-2)
//   Hex20 m = 1, 2, 4:  displacement 3.37, 2.77   stress 1.95, 1.87   (finest 2.0e-5, 4.1e-3)
// Every refinement reduces both errors, the last rates stay above the bounds below, and the mixed
// Hex8's nodal stresses are more than twice as accurate as the displacement Hex8's (4.9x).
TEST(SolidCantilever, NodalStressesOfBothModelsConvergeToTheElasticitySolution) {
  const TimoshenkoCantilever beam;
  struct Case {
    ElementType type;
    int coarse;
    bool mixed;
    double displacementRate, stressRate;
  };
  double displacementHex8 = 0.0, mixedHex8 = 0.0; // finest stress errors
  for (const Case &c :
       {Case{ElementType::Hex8, 2, false, 1.8, 0.85}, Case{ElementType::Hex8, 2, true, 1.8, 0.95},
        Case{ElementType::Hex20, 1, false, 3.4, 1.85},
        Case{ElementType::Hex20, 1, true, 2.5, 1.7}}) {
    const auto finest = test::expectConvergence(
        std::string("cantilever ") + (c.mixed ? "mixed " : "displacement ") +
            elementTypeName(c.type),
        3, [&](int level) { return "m = " + std::to_string(c.coarse << level); },
        [&](int level) { return beam.errors(c.type, c.coarse << level, c.mixed); },
        {c.displacementRate, c.stressRate});
    if (c.type == ElementType::Hex8)
      (c.mixed ? mixedHex8 : displacementHex8) = finest[1];
  }
  EXPECT_LT(mixedHex8, 0.5 * displacementHex8);
}

// The plate with a hole extruded (issue 17's generators: `generator: {type: plate_with_hole}`
// with `extrude`): a quarter plate w = h = 5 with a hole a = 1 under the tension S = 1 on x = w,
// symmetry on x = 0 and y = 0, extruded to the thickness t = 0.2 (Quad4 -> Hex8 in 1 and 2
// layers, Quad8 -> Hex20). With nu = 0 the 3D solution is the plane stress one with u_z = 0
// (nothing couples z), so every node of the solid must take the 2D model's displacement at its
// (x, y) and its nodal stresses, to the solvers' round-off (the 2D plate itself is validated
// against Kirsch in the 2D suite). The stress at the hole's top, sigma_xx(0, a), is printed
// against Kirsch's 3 S of the infinite plate (about 3.2 S for w = 5a: the finite width).
TEST(SolidExtrudedPlate, IsThePlaneStressPlateNodeForNodeAtNuZero) {
  const double a = 1.0, w = 5.0, t = 0.2, e = 1000.0, sx = 1.0;
  LinearSolverOptions direct;
  direct.type = LinearSolverType::Direct;
  for (const auto &[section, layers] :
       {std::pair{ElementType::Quad4, 1}, std::pair{ElementType::Quad4, 2},
        std::pair{ElementType::Quad8, 1}}) {
    // symmetry on x = 0, y = 0 (and z = 0 in 3D), the tension on x = w; solved
    const auto solve = [&](LinearDisplacementModel &m, const Mesh &mesh) {
      for (int i = 0; i < mesh.dim(); ++i)
        for (LocalIndex k : mesh.nodesOf(i == 0 ? "left" : i == 1 ? "bottom" : "zmin"))
          m.prescribe(k, i, 0.0);
      m.addSideLoad(mesh.boundaries.at("right"), {sx, 0.0, 0.0}, 0.0);
      m.setup(direct, MPI_COMM_WORLD);
      return m.solve(1.0).converged;
    };
    const Mesh plane = plateWithHoleMesh(a, w, w, 6, 6, section, 1.3);
    LinearDisplacementModel flat(plane, std::vector<int>(plane.numElements(), 0),
                                 {isotropicStiffness(e, 0.0, PlaneAnalysis::PlaneStress)}, t);
    ASSERT_TRUE(solve(flat, plane));
    const Mesh solid = extrudeMesh(plane, t, layers);
    validateMesh(solid);
    LinearDisplacementModel model(solid, std::vector<int>(solid.numElements(), 0),
                                  {IsotropicMaterial{e, 0.0}.stiffness()});
    ASSERT_TRUE(solve(model, solid));

    // the 2D node at each solid node's (x, y)
    std::map<std::pair<long, long>, LocalIndex> at;
    for (LocalIndex k = 0; k < plane.numNodes(); ++k)
      at[{std::lround(plane.x(k) * 1e8), std::lround(plane.y(k) * 1e8)}] = k;
    const auto u2 = flat.displacementHost(), u3 = model.displacementHost();
    const auto s2 = flat.nodalStressHost(), s3 = model.nodalStressHost();
    double scaleU = 0.0, du = 0.0, ds = 0.0, top = 0.0;
    int matched = 0;
    for (LocalIndex k = 0; k < solid.numNodes(); ++k) {
      const auto found = at.find({std::lround(solid.x(k) * 1e8), std::lround(solid.y(k) * 1e8)});
      if (found == at.end())
        continue; // none: counted below
      const LocalIndex n = found->second;
      ++matched;
      for (int i = 0; i < 2; ++i) {
        scaleU = std::max(scaleU, std::abs(u2[2 * n + i]));
        du = std::max(du, std::abs(u3[3 * k + i] - u2[2 * n + i]));
      }
      du = std::max(du, std::abs(u3[3 * k + 2]));
      // Voigt: 2D xx, yy, xy; 3D xx, yy, zz, yz, xz, xy
      const double pairs[6][2] = {{s3[6 * k], s2[3 * n]},         {s3[6 * k + 1], s2[3 * n + 1]},
                                  {s3[6 * k + 5], s2[3 * n + 2]}, {s3[6 * k + 2], 0.0},
                                  {s3[6 * k + 3], 0.0},           {s3[6 * k + 4], 0.0}};
      for (const auto &pair : pairs)
        ds = std::max(ds, std::abs(pair[0] - pair[1]));
      if (std::abs(solid.x(k)) < 1e-12 && std::abs(solid.y(k) - a) < 1e-12)
        top = s3[6 * k];
    }
    std::printf("  extruded plate %s, %d layer(s): %d nodes matched, max |u3 - u2| / max |u2| "
                "%.2e, max stress difference / S %.2e, sigma_xx(0, a) = %.4f S (Kirsch: 3)\n",
                elementTypeName(solid.elementType).c_str(), layers, matched, du / scaleU, ds / sx,
                top / sx);
    EXPECT_EQ(matched, solid.numNodes()) << layers; // each above a node of the section
    EXPECT_LT(du, 1e-9 * scaleU) << layers;
    EXPECT_LT(ds, 1e-9 * sx) << layers;
    EXPECT_GT(top, 2.9 * sx); // the concentration is there, near Kirsch's 3 (finite width: more)
    EXPECT_LT(top, 3.6 * sx);
  }
}
