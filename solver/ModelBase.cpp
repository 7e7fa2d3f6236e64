// ModelBase: loads, constraints and displacement output shared by both models.
#include <core/Transfer.hpp>
#include <solver/ModelBase.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mixcon {

ModelBase::ModelBase(const Mesh &mesh, const std::vector<int> &elementMaterial,
                     const std::vector<PlaneMatrix> &stiffness, double thickness)
    : mesh_(mesh), dofs_(DofMap::serial(mesh.numNodes(), ModelLayout::kDisplacementUnknowns)) {
  data_.mesh = toDevice<Memory, kModelDim>(mesh);
  data_.thickness = thickness;
  data_.material =
      Kokkos::View<int *, Memory>("mixcon::model::elementMaterial", mesh.numElements());
  data_.stiffness =
      Kokkos::View<PlaneMatrix *, Memory>("mixcon::model::stiffness", stiffness.size());
  auto hm = hostMirror(data_.material);
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    hm(e) = elementMaterial.at(e);
  copyToDevice(data_.material, hm);
  auto hs = hostMirror(data_.stiffness);
  for (std::size_t i = 0; i < stiffness.size(); ++i)
    hs(i) = stiffness[i];
  copyToDevice(data_.stiffness, hs);

  const LocalIndex n = dofs_.numOwned();
  load_ = Kokkos::View<double *, Memory>("mixcon::model::load", n);
  u_ = Kokkos::View<double *, Memory>("mixcon::model::displacement", n);
  isConstrained_ = Kokkos::View<int *, Memory>("mixcon::model::constrained", n);
  prescribed_ = Kokkos::View<double *, Memory>("mixcon::model::prescribed", n);
  stagedNodalForce_.assign(n, 0.0);
  constrainedHost_.assign(n, 0);
  prescribedHost_.assign(n, 0.0);
}

void ModelBase::addEdgeLoad(const std::vector<BoundaryEdge> &edges, double tx, double ty,
                            double pressure) {
  if (edges.empty())
    return;
  const auto batch = uniformEdgeLoads<Memory>(edges, tx, ty, pressure);
  dispatchElement(mesh_.elementType, [&](auto elem) {
    assembleEdgeLoads<decltype(elem)>(Exec(), data_.mesh, batch.edges, batch.load, data_.thickness,
                                      load_);
  });
}

void ModelBase::addNodalForce(LocalIndex node, double fx, double fy) {
  stagedNodalForce_[dofs_.dof(node, 0)] += fx;
  stagedNodalForce_[dofs_.dof(node, 1)] += fy;
}

// 2D-only: the force function takes (x, y) and returns two components.
void ModelBase::addBodyForce(
    const std::function<std::array<double, 2>(double, double, LocalIndex)> &f) {
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    const LocalIndex ne = mesh_.numElements();
    Kokkos::View<double **[2], Memory> xq("mixcon::model::qpCoordinates", ne, Elem::kNumQp);
    quadraturePointCoordinates<Elem>(Exec(), data_.mesh, xq);
    auto hx = copyToHost(xq);
    Kokkos::View<double **[2], Memory> fq("mixcon::model::qpBodyForce", ne, Elem::kNumQp);
    auto hf = hostMirror(fq);
    for (LocalIndex e = 0; e < ne; ++e)
      for (int q = 0; q < Elem::kNumQp; ++q) {
        const auto v = f(hx(e, q, 0), hx(e, q, 1), e);
        hf(e, q, 0) = v[0];
        hf(e, q, 1) = v[1];
      }
    copyToDevice(fq, hf);
    assembleBodyForce<Elem>(Exec(), data_, Kokkos::View<const double **[2], Memory>(fq), load_);
  });
}

void ModelBase::prescribe(LocalIndex node, int comp, double value) {
  const LocalIndex i = dofs_.dof(node, comp);
  constrainedHost_[i] = 1;
  prescribedHost_[i] = value;
}

void ModelBase::updatePrescribed(const std::vector<PrescribedValue> &values) {
  for (const auto &v : values) {
    const LocalIndex i = dofs_.dof(v.node, v.comp);
    if (!constrainedHost_[i])
      throw InputError("node " + std::to_string(mesh_.nodeId(v.node)) + " component " +
                       std::to_string(v.comp) + " is not prescribed; cannot update its value");
    prescribedHost_[i] = v.value;
  }
  auto hp = hostMirror(prescribed_);
  for (std::size_t i = 0; i < prescribedHost_.size(); ++i)
    hp(i) = prescribedHost_[i];
  copyToDevice(prescribed_, hp);
}

LocalIndex ModelBase::numConstrained() const {
  return static_cast<LocalIndex>(std::count(constrainedHost_.begin(), constrainedHost_.end(), 1));
}

void ModelBase::checkRigidBodyModes() const {
  // Bodies: the nodes connected through elements (a node in no element is refused by
  // validateMesh).
  const LocalIndex nn = mesh_.numNodes();
  const std::vector<LocalIndex> bodyOf = connectedComponents(mesh_);
  // Per body, the rigid-body modes t_x = (1, 0), t_y = (0, 1), r = (-y', x') in coordinates
  // centred on the body and scaled by its size; a prescribed component c at a node is one row of
  // C (its value under each mode). C^T C is singular exactly when a combination of the modes moves
  // no prescribed component. 2D-only: three rigid modes of a plane body (3D has six).
  struct Body {
    double sum[2] = {0, 0}, lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    LocalIndex count = 0, first = -1;
    bool anyX = false, anyY = false;
    Eigen::Matrix3d gram = Eigen::Matrix3d::Zero();
  };
  std::vector<Body> bodies;
  for (LocalIndex n = 0; n < nn; ++n) {
    if (bodyOf[n] == static_cast<LocalIndex>(bodies.size())) { // its first node
      bodies.emplace_back();
      bodies.back().first = n;
    }
    Body &b = bodies[bodyOf[n]];
    const double xy[2] = {mesh_.x(n), mesh_.y(n)};
    for (int c = 0; c < 2; ++c) {
      b.sum[c] += xy[c];
      b.lo[c] = std::min(b.lo[c], xy[c]);
      b.hi[c] = std::max(b.hi[c], xy[c]);
    }
    ++b.count;
  }
  for (LocalIndex n = 0; n < nn; ++n) {
    Body &b = bodies[bodyOf[n]];
    const double size = std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], 1e-300});
    const double x = (mesh_.x(n) - b.sum[0] / b.count) / size;
    const double y = (mesh_.y(n) - b.sum[1] / b.count) / size;
    for (int c = 0; c < 2; ++c)
      if (constrainedHost_[dofs_.dof(n, c)]) {
        const Eigen::Vector3d row =
            c == 0 ? Eigen::Vector3d(1.0, 0.0, -y) : Eigen::Vector3d(0.0, 1.0, x);
        b.gram += row * row.transpose();
        (c == 0 ? b.anyX : b.anyY) = true;
      }
  }
  for (const Body &b : bodies) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(b.gram);
    const Eigen::Vector3d lambda = eig.eigenvalues(); // ascending
    const double scale = std::max(lambda(2), 1.0);
    int free = 0;
    for (int k = 0; k < 3; ++k)
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
    if (!b.anyX)
      modes.push_back("translate in x (no ux is prescribed on it)");
    if (!b.anyY)
      modes.push_back("translate in y (no uy is prescribed on it)");
    if (free > static_cast<int>(modes.size())) {
      const double size = std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], 1e-300});
      const Eigen::Vector3d v = eig.eigenvectors().col(0); // the free combination
      std::ostringstream r;
      if (free == 1 && std::fabs(v(2)) > 1e-6) {
        // v(0) t_x + v(1) t_y + v(2) r is a rotation about (x0', y0') = (-v(1), v(0)) / v(2)
        // (rounding below 1e-9 of the body's size printed as 0)
        const auto snap = [size](double t) { return std::fabs(t) < 1e-9 * size ? 0.0 : t; };
        r << "rotate about (" << snap(b.sum[0] / b.count - size * v(1) / v(2)) << ", "
          << snap(b.sum[1] / b.count + size * v(0) / v(2)) << ")";
      } else if (free == 1) {
        r << "translate along (" << v(0) << ", " << v(1) << ")";
      } else {
        r << "rotate";
      }
      modes.push_back(r.str());
    }
    for (std::size_t k = 0; k < modes.size(); ++k)
      m << (k == 0 ? "" : k + 1 == modes.size() ? " and to " : ", to ") << modes[k];
    m << ": its stiffness matrix is singular (a rigid-body mode without stiffness). Hold it by "
         "displacement conditions that stop every translation and the rotation (e.g. ux and uy "
         "at one node and one more component at a node away from it)";
    throw InputError(m.str());
  }
}

void ModelBase::commitStaged() {
  // Nodal forces join the reference load and are then cleared, so a second setup() does not add
  // them twice; constraints replace the device flags.
  auto h = copyToHost(load_);
  for (std::size_t i = 0; i < stagedNodalForce_.size(); ++i)
    h(i) += stagedNodalForce_[i];
  copyToDevice(load_, h);
  std::fill(stagedNodalForce_.begin(), stagedNodalForce_.end(), 0.0);
  auto hc = hostMirror(isConstrained_);
  auto hp = hostMirror(prescribed_);
  for (std::size_t i = 0; i < constrainedHost_.size(); ++i) {
    hc(i) = constrainedHost_[i];
    hp(i) = prescribedHost_[i];
  }
  copyToDevice(isConstrained_, hc);
  copyToDevice(prescribed_, hp);
}

Kokkos::View<double *, DeviceSpace> scaledCopy(const Kokkos::View<const double *, DeviceSpace> &v,
                                               double lambda) {
  Kokkos::View<double *, DeviceSpace> b("mixcon::model::scaled", v.extent(0));
  Kokkos::parallel_for(
      "mixcon::model::scale", Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, b.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { b(i) = lambda * v(i); });
  return b;
}

std::vector<double> ModelBase::toHost(const Kokkos::View<const double *, Memory> &v) {
  auto h = copyToHost(v);
  return std::vector<double>(h.data(), h.data() + h.extent(0));
}

void ModelBase::fromHost(const std::vector<double> &h, const Kokkos::View<double *, Memory> &v) {
  auto m = hostMirror(v);
  for (std::size_t i = 0; i < h.size(); ++i)
    m(i) = h[i];
  copyToDevice(v, m);
}

std::vector<double> ModelBase::toHostAt(const Kokkos::View<const double *, Memory> &v, int perNode,
                                        const std::vector<LocalIndex> &nodes) {
  const std::size_t m = nodes.size();
  Kokkos::View<LocalIndex *, Memory> at("mixcon::model::gatherNodes", m);
  Kokkos::View<double *, Memory> packed("mixcon::model::gathered", perNode * m);
  copyToDevice(at, nodes);
  Kokkos::parallel_for(
      "mixcon::model::gatherAtNodes", Kokkos::RangePolicy<Exec>(0, m), KOKKOS_LAMBDA(LocalIndex k) {
        for (int c = 0; c < perNode; ++c)
          packed(perNode * k + c) = v(perNode * at(k) + c);
      });
  const auto h = copyToHost(packed);
  std::vector<double> out(v.extent(0), 0.0);
  for (std::size_t k = 0; k < m; ++k)
    for (int c = 0; c < perNode; ++c)
      out[perNode * static_cast<std::size_t>(nodes[k]) + c] = h(perNode * k + c);
  return out;
}

std::vector<double>
ModelBase::reactionFrom(const Kokkos::View<const double *, Memory> &internalForce,
                        double loadFactor) const {
  auto r = toHost(internalForce);
  const auto load = toHost(load_);
  for (std::size_t i = 0; i < r.size(); ++i)
    r[i] -= loadFactor * load[i];
  return r;
}

std::vector<double> ModelBase::displacementHost() const { return toHost(u_); }

void ModelBase::gaussPointStressHost(std::vector<double> &coordinates, std::vector<double> &stress,
                                     int &pointsPerElement) const {
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    const LocalIndex ne = mesh_.numElements();
    constexpr int kDim = ModelLayout::kDim, kStress = ModelLayout::kNumStresses;
    Kokkos::View<double **[kDim], Memory> xq("mixcon::model::qpCoordinates", ne, Elem::kNumQp);
    Kokkos::View<double **[kStress], Memory> sq("mixcon::model::qpStress", ne, Elem::kNumQp);
    quadraturePointCoordinates<Elem>(Exec(), data_.mesh, xq);
    gaussPointStress<Elem>(Exec(), data_, Kokkos::View<const double *, Memory>(u_), sq);
    auto hx = copyToHost(xq);
    auto hs = copyToHost(sq);
    pointsPerElement = Elem::kNumQp;
    coordinates.resize(static_cast<std::size_t>(ne) * Elem::kNumQp * kDim);
    stress.resize(static_cast<std::size_t>(ne) * Elem::kNumQp * kStress);
    for (LocalIndex e = 0; e < ne; ++e)
      for (int q = 0; q < Elem::kNumQp; ++q) {
        const std::size_t k = static_cast<std::size_t>(e) * Elem::kNumQp + q;
        for (int c = 0; c < kDim; ++c)
          coordinates[kDim * k + c] = hx(e, q, c);
        for (int c = 0; c < kStress; ++c)
          stress[kStress * k + c] = hs(e, q, c);
      }
  });
}

} // namespace mixcon
