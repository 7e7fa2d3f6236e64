// Host views of a nonlinear model's device vectors and the central finite differences of its
// assembled residual, shared by the tangent tests of the displacement model in 2D
// (tests/unit/test_nonlinear.cpp) and of both models in 3D (tests/unit/test_nonlinear_3d.cpp).
#pragma once

#include <solver/Nonlinear.hpp>

#include <Eigen/Dense>

#include <vector>

namespace mixcon::test {

inline Eigen::VectorXd hostVector(const Kokkos::View<const double *, DeviceSpace> &v) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  return Eigen::Map<const Eigen::VectorXd>(h.data(), h.extent(0));
}

inline std::vector<double> toStd(const Eigen::VectorXd &v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

/// Central finite differences (step 1e-6) of a nonlinear model's assembled residual at the
/// unknowns x, load factor 1, one column per unknown; `set(model, values)` gives the model its
/// unknowns, and the model is left at x.
template <class Model, class Set>
Eigen::MatrixXd finiteDifferenceTangent(Model &model, const Eigen::VectorXd &x, const Set &set) {
  Eigen::MatrixXd fd(x.size(), x.size());
  const double h = 1e-6;
  for (int j = 0; j < x.size(); ++j) {
    Eigen::VectorXd xp = x, xm = x;
    xp(j) += h;
    xm(j) -= h;
    set(model, toStd(xp));
    model.evaluate(1.0, false);
    const Eigen::VectorXd gp = hostVector(model.residual());
    set(model, toStd(xm));
    model.evaluate(1.0, false);
    fd.col(j) = (gp - hostVector(model.residual())) / (2 * h);
  }
  set(model, toStd(x));
  return fd;
}

/// The displacement model's: its unknowns are the displacements.
inline Eigen::MatrixXd finiteDifferenceTangent(NonlinearDisplacementModel &model,
                                               const Eigen::VectorXd &u) {
  return finiteDifferenceTangent(
      model, u,
      [](NonlinearDisplacementModel &m, const std::vector<double> &v) { m.setDisplacement(v); });
}

} // namespace mixcon::test
