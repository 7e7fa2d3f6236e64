// Host views of a nonlinear model's device vectors and the central finite differences of its
// assembled residual, shared by the tangent tests of the displacement model in 2D
// (tests/unit/test_nonlinear.cpp) and 3D (tests/unit/test_nonlinear_3d.cpp).
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

/// Central finite differences (step 1e-6) of the displacement model's assembled residual at u,
/// load factor 1, one column per unknown; the model is left at u.
inline Eigen::MatrixXd finiteDifferenceTangent(NonlinearDisplacementModel &model,
                                               const Eigen::VectorXd &u) {
  Eigen::MatrixXd fd(u.size(), u.size());
  const double h = 1e-6;
  for (int j = 0; j < u.size(); ++j) {
    Eigen::VectorXd up = u, um = u;
    up(j) += h;
    um(j) -= h;
    model.setDisplacement(toStd(up));
    model.evaluate(1.0, false);
    const Eigen::VectorXd gp = hostVector(model.residual());
    model.setDisplacement(toStd(um));
    model.evaluate(1.0, false);
    fd.col(j) = (gp - hostVector(model.residual())) / (2 * h);
  }
  model.setDisplacement(toStd(u));
  return fd;
}

} // namespace mixcon::test
