// ModelBase::checkRigidBodyModes: the host-side check that the displacement conditions fix every
// rigid-body mode of every body (a small dense eigenproblem per body). Its own translation unit:
// Eigen stays out of the ones with device code (ctest repo.eigen_host_only).
#include <solver/ModelBase.hpp>
#include <solver/RigidRotation.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace mixcon {

void ModelBase::checkRigidBodyModes(const std::vector<int> &constrained) const {
  // Bodies: the nodes connected through elements (a node in no element is refused by
  // validateMesh).
  const int dim = mesh_.dim();
  const int numModes = dim + rigidRotations(dim); // translations, then rotations
  const LocalIndex nn = mesh_.numNodes();
  const std::vector<LocalIndex> bodyOf = connectedComponents(mesh_);
  // Per body, the rigid-body modes in coordinates p centred on the body and scaled by its size:
  // the translations t_c = e_c and the rotations (2D: r = (-y', x'); 3D: r_k = e_k x p). A
  // prescribed component c at a node is one row of C (its value under each mode). C^T C is
  // singular exactly when a combination of the modes moves no prescribed component.
  struct Body {
    double sum[3] = {0, 0, 0}, lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    LocalIndex count = 0, first = -1;
    bool any[3] = {false, false, false};
    Eigen::MatrixXd gram;
    double size() const { return std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-300}); }
  };
  std::vector<Body> bodies;
  for (LocalIndex n = 0; n < nn; ++n) {
    if (bodyOf[n] == static_cast<LocalIndex>(bodies.size())) { // its first node
      bodies.emplace_back();
      bodies.back().first = n;
      bodies.back().gram = Eigen::MatrixXd::Zero(numModes, numModes);
      if (dim == 2)
        bodies.back().lo[2] = bodies.back().hi[2] = 0.0;
    }
    Body &b = bodies[bodyOf[n]];
    for (int c = 0; c < dim; ++c) {
      const double x = mesh_.coordinate(n, c);
      b.sum[c] += x;
      b.lo[c] = std::min(b.lo[c], x);
      b.hi[c] = std::max(b.hi[c], x);
    }
    ++b.count;
  }
  for (LocalIndex n = 0; n < nn; ++n) {
    Body &b = bodies[bodyOf[n]];
    double p[3] = {0, 0, 0};
    for (int c = 0; c < dim; ++c)
      p[c] = (mesh_.coordinate(n, c) - b.sum[c] / b.count) / b.size();
    for (int c = 0; c < dim; ++c)
      if (constrained.at(dofs_.dof(n, c))) {
        Eigen::VectorXd row = Eigen::VectorXd::Zero(numModes);
        row(c) = 1.0;
        for (int r = 0; r < rigidRotations(dim); ++r)
          row(dim + r) = rigidRotation(dim, r, c, p);
        b.gram += row * row.transpose();
        b.any[c] = true;
      }
  }
  static const char *const kAxis[3] = {"x", "y", "z"};
  for (const Body &b : bodies) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(b.gram);
    const Eigen::VectorXd lambda = eig.eigenvalues(); // ascending
    const double scale = std::max(lambda(numModes - 1), 1.0);
    int free = 0;
    for (int k = 0; k < numModes; ++k)
      free += lambda(k) <= 1e-10 * scale;
    if (free == 0)
      continue;
    std::ostringstream m;
    m << "the displacement conditions leave ";
    if (bodies.size() == 1)
      m << "the body";
    else
      m << "the body that contains node " << mesh_.nodeIds[b.first];
    m << " free to ";
    std::vector<std::string> modes;
    int translations = 0;
    for (int c = 0; c < dim; ++c)
      if (!b.any[c]) {
        modes.push_back(std::string("translate in ") + kAxis[c] + " (no u" + kAxis[c] +
                        " is prescribed on it)");
        ++translations;
      }
    if (free > translations) {
      const double size = b.size();
      const Eigen::VectorXd v = eig.eigenvectors().col(0); // the free combination
      std::ostringstream r;
      if (dim == 2 && free == 1 && std::fabs(v(2)) > 1e-6) {
        // v(0) t_x + v(1) t_y + v(2) r is a rotation about (x0', y0') = (-v(1), v(0)) / v(2)
        // (rounding below 1e-9 of the body's size printed as 0)
        const auto snap = [size](double t) { return std::fabs(t) < 1e-9 * size ? 0.0 : t; };
        r << "rotate about (" << snap(b.sum[0] / b.count - size * v(1) / v(2)) << ", "
          << snap(b.sum[1] / b.count + size * v(0) / v(2)) << ")";
      } else if (dim == 3 && free == 1 && v.tail(3).norm() > 1e-6) {
        Eigen::Vector3d axis = v.tail(3).normalized();
        Eigen::Index largest = 0;
        axis.cwiseAbs().maxCoeff(&largest);
        if (axis(largest) < 0.0) // the axis's sign is arbitrary: print its largest part positive
          axis = -axis;
        const auto snap = [](double t) { return std::fabs(t) < 1e-9 ? 0.0 : t; };
        r << "rotate about an axis along (" << snap(axis(0)) << ", " << snap(axis(1)) << ", "
          << snap(axis(2)) << ")";
      } else if (free == 1) {
        r << "translate along (" << v(0) << ", " << v(1);
        if (dim == 3)
          r << ", " << v(2);
        r << ")";
      } else {
        r << "rotate";
      }
      modes.push_back(r.str());
    }
    for (std::size_t k = 0; k < modes.size(); ++k)
      m << (k == 0 ? "" : k + 1 == modes.size() ? " and to " : ", to ") << modes[k];
    m << ": its stiffness matrix is singular (a rigid-body mode without stiffness). Hold it by "
         "displacement conditions that stop every translation and "
      << (dim == 2 ? "the rotation (e.g. ux and uy at one node and one more component at a node "
                     "away from it)"
                   : "the three rotations (e.g. ux, uy and uz at one node and components at two "
                     "more nodes not on a line with it)");
    throw InputError(m.str());
  }
}

} // namespace mixcon
