// Closed-form stress-accuracy cases shared by the validation tests and the accuracy study
// (bench/mixed_accuracy.cpp): the pressurized Lame cylinder and the Kirsch plate with a hole,
// solved with the displacement model or any mixed-model variant, with nodal-stress errors on the
// loaded / hole surface and in the interior. References: apps/Verification.hpp.
#pragma once

#include <apps/Verification.hpp>
#include <mesh/Generators.hpp>
#include <solver/DisplacementModel.hpp>
#include <solver/MixedModel.hpp>

#include <chrono>
#include <cmath>
#include <memory>
#include <string>

namespace mixcon::test {

struct Method {
  Formulation formulation = Formulation::Mixed;
  ComplianceMass compliance = ComplianceMass::Consistent;
  double a = 0.0;
  std::string name() const {
    if (formulation == Formulation::Displacement)
      return "displacement model (recovered)";
    char buf[80];
    std::snprintf(buf, sizeof buf, "mixed %s M, a = %g",
                  compliance == ComplianceMass::Consistent ? "consistent" : "lumped", a);
    return buf;
  }
};

struct CaseResult {
  double surface = 0.0;  ///< relative RMS error of nodal stresses on the surface of interest
  double interior = 0.0; ///< same, interior nodes
  double peak = 0.0;     ///< Kirsch: sigma_xx(0, a) / S; Lame: sigma_theta(a) / p
  double gauss = 0.0;    ///< relative RMS error of C eps(u) at all quadrature points
  int iterations = 0;
  long unknowns = 0;
  double seconds = 0.0;
};

/// Builds the model for a method; the caller adds loads and constraints, then calls solveCase.
inline std::unique_ptr<ModelBase> makeModel(const Mesh &mesh, const PlaneMatrix &c,
                                            const Method &m) {
  const std::vector<int> mat(mesh.numElements(), 0);
  if (m.formulation == Formulation::Displacement)
    return std::make_unique<LinearDisplacementModel>(mesh, mat, std::vector<PlaneMatrix>{c}, 1.0);
  return std::make_unique<MixedModel>(mesh, mat, std::vector<PlaneMatrix>{c}, 1.0);
}

inline LinearSolveStats solveCase(ModelBase &model, const Method &m, double tolerance = 1e-10) {
  LinearSolverOptions lo;
  lo.tolerance = tolerance;
  lo.maxIterations = 5000;
  if (m.formulation == Formulation::Displacement) {
    static_cast<LinearDisplacementModel &>(model).setup(lo, MPI_COMM_WORLD);
  } else {
    MixedOptions o;
    o.compliance = m.compliance;
    o.stabilization = m.a;
    o.linear = lo;
    static_cast<MixedModel &>(model).setup(o, MPI_COMM_WORLD);
  }
  return model.solve(1.0);
}

/// Solves, timing it, and fills the iteration and unknown counts of a CaseResult.
inline CaseResult solveAndCount(ModelBase &model, const Method &m) {
  const auto start = std::chrono::steady_clock::now();
  const auto st = solveCase(model, m);
  CaseResult r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.iterations = st.iterations;
  r.unknowns =
      static_cast<long>(model.mesh().numNodes()) * (m.formulation == Formulation::Mixed ? 5 : 2);
  return r;
}

/// Relative RMS error of the quadrature-point stresses C eps(u) against an exact Cartesian stress
/// field: what the displacements alone give (for the mixed model, the report's warning).
template <class Exact> double gaussPointError(const ModelBase &model, const Exact &exact) {
  std::vector<double> x, s;
  int q = 0;
  model.gaussPointStressHost(x, s, q);
  double err = 0.0, ref = 0.0;
  for (std::size_t k = 0; k < x.size() / 2; ++k) {
    const std::array<double, 3> e = exact(x[2 * k], x[2 * k + 1]);
    for (int c = 0; c < 3; ++c) {
      err += (s[3 * k + c] - e[c]) * (s[3 * k + c] - e[c]);
      ref += e[c] * e[c];
    }
  }
  return std::sqrt(err / ref);
}

/// Polar components (rr, tt, rt) of a Cartesian stress at angle t.
inline std::array<double, 3> polar(const double *s, double t) {
  const double c = std::cos(t), n = std::sin(t);
  return {s[0] * c * c + s[1] * n * n + 2 * s[2] * n * c,
          s[0] * n * n + s[1] * c * c - 2 * s[2] * n * c,
          (s[1] - s[0]) * n * c + s[2] * (c * c - n * n)};
}

/// Accumulates squared errors and squared references into a relative RMS.
struct Rms {
  double err = 0.0, ref = 0.0;
  void add(const std::array<double, 3> &got, const std::array<double, 3> &exact) {
    for (int k = 0; k < 3; ++k) {
      err += (got[k] - exact[k]) * (got[k] - exact[k]);
      ref += exact[k] * exact[k];
    }
  }
  double value() const { return ref > 0 ? std::sqrt(err / ref) : 0.0; }
};

/// Lame cylinder a = 1, b = 2, inner pressure p = 1, plane stress, E = 1, nu = 0.3 (quarter
/// model, symmetry supports); surface = the loaded inner radius.
inline CaseResult lameCase(ElementType type, int nr, int nt, const Method &m) {
  const LameSolution exact{1.0, 2.0, 1.0, 0.0, 1.0, 0.3, false};
  const Mesh mesh = quarterAnnulusMesh(1.0, 2.0, nr, nt, type);
  auto model = makeModel(mesh, isotropicStiffness(1.0, 0.3, PlaneAnalysis::PlaneStress), m);
  for (LocalIndex n : mesh.nodesOf("left"))
    model->prescribe(n, 0, 0.0);
  for (LocalIndex n : mesh.nodesOf("bottom"))
    model->prescribe(n, 1, 0.0);
  model->addEdgeLoad(mesh.boundaries.at("inner"), 0.0, 0.0, 1.0);
  CaseResult r = solveAndCount(*model, m);
  const auto s = model->nodalStressHost();
  Rms surface, interior;
  for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
    const double rad = std::hypot(mesh.x(n), mesh.y(n)), t = std::atan2(mesh.y(n), mesh.x(n));
    const auto got = polar(&s[3 * n], t);
    const std::array<double, 3> ref{exact.sigmaR(rad), exact.sigmaTheta(rad), 0.0};
    if (rad < 1.0 + 1e-9) {
      surface.add(got, ref);
      if (std::abs(t) < 1e-9)
        r.peak = got[1];
    } else if (rad > 1.25 && rad < 1.75) {
      interior.add(got, ref);
    }
  }
  r.surface = surface.value();
  r.interior = interior.value();
  r.gauss = gaussPointError(*model, [&](double x, double y) {
    const double rad = std::hypot(x, y), t = std::atan2(y, x), c = std::cos(t), n = std::sin(t);
    const double sr = exact.sigmaR(rad), st = exact.sigmaTheta(rad);
    return std::array<double, 3>{sr * c * c + st * n * n, sr * n * n + st * c * c,
                                 (sr - st) * n * c};
  });
  return r;
}

/// Kirsch plate: hole radius 1 in a 4 x 4 quarter plate, S = 1 along x, E = 1, nu = 0.3, plane
/// stress; symmetry on x = 0 and y = 0, the exact Kirsch displacements on x = 4 and y = 4, the hole
/// traction free. n radial elements and n per block around the hole, graded towards the hole.
inline CaseResult kirschCase(ElementType type, int n, const Method &m) {
  const KirschSolution exact{1.0, 1.0, 1.0, 0.3, false};
  const Mesh mesh = plateWithHoleMesh(1.0, 4.0, 4.0, n, n, type, std::pow(1.6, 4.0 / n));
  auto model = makeModel(mesh, isotropicStiffness(1.0, 0.3, PlaneAnalysis::PlaneStress), m);
  for (LocalIndex k : mesh.nodesOf("left"))
    model->prescribe(k, 0, 0.0);
  for (LocalIndex k : mesh.nodesOf("bottom"))
    model->prescribe(k, 1, 0.0);
  for (const char *side : {"right", "top"})
    for (LocalIndex k : mesh.nodesOf(side)) {
      const auto u = exact.displacement(mesh.x(k), mesh.y(k));
      model->prescribe(k, 0, u[0]);
      model->prescribe(k, 1, u[1]);
    }
  CaseResult r = solveAndCount(*model, m);
  const auto s = model->nodalStressHost();
  Rms surface, interior;
  for (LocalIndex k = 0; k < mesh.numNodes(); ++k) {
    const double x = mesh.x(k), y = mesh.y(k), rad = std::hypot(x, y), t = std::atan2(y, x);
    const auto e = exact.stress(x, y);
    const auto got = polar(&s[3 * k], t), ref = polar(e.data(), t);
    if (rad < 1.0 + 1e-9) {
      surface.add(got, ref);
      if (std::abs(x) < 1e-9)
        r.peak = s[3 * k];
    } else if (rad > 1.5 && x < 3.5 && y < 3.5) {
      interior.add(got, ref);
    }
  }
  r.surface = surface.value();
  r.interior = interior.value();
  r.gauss = gaussPointError(*model, [&](double x, double y) { return exact.stress(x, y); });
  return r;
}

} // namespace mixcon::test
