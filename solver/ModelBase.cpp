// ModelBase: loads, constraints and displacement output shared by both models.
#include <solver/ModelBase.hpp>

#include <algorithm>

namespace mixcon {

ModelBase::ModelBase(const Mesh &mesh, const std::vector<int> &elementMaterial,
                     const std::vector<PlaneMatrix> &stiffness, double thickness)
    : mesh_(mesh), dofs_(DofMap::serial(mesh.numNodes(), 2)) {
  data_.mesh = toDevice<Memory>(mesh);
  data_.thickness = thickness;
  data_.material =
      Kokkos::View<int *, Memory>("mixcon::model::elementMaterial", mesh.numElements());
  data_.stiffness =
      Kokkos::View<PlaneMatrix *, Memory>("mixcon::model::stiffness", stiffness.size());
  auto hm = Kokkos::create_mirror_view(data_.material);
  for (LocalIndex e = 0; e < mesh.numElements(); ++e)
    hm(e) = elementMaterial.at(e);
  Kokkos::deep_copy(data_.material, hm);
  auto hs = Kokkos::create_mirror_view(data_.stiffness);
  for (std::size_t i = 0; i < stiffness.size(); ++i)
    hs(i) = stiffness[i];
  Kokkos::deep_copy(data_.stiffness, hs);

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

void ModelBase::addBodyForce(
    const std::function<std::array<double, 2>(double, double, LocalIndex)> &f) {
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    const LocalIndex ne = mesh_.numElements();
    Kokkos::View<double **[2], Memory> xq("mixcon::model::qpCoordinates", ne, Elem::kNumQp);
    quadraturePointCoordinates<Elem>(Exec(), data_.mesh, xq);
    auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), xq);
    Kokkos::View<double **[2], Memory> fq("mixcon::model::qpBodyForce", ne, Elem::kNumQp);
    auto hf = Kokkos::create_mirror_view(fq);
    for (LocalIndex e = 0; e < ne; ++e)
      for (int q = 0; q < Elem::kNumQp; ++q) {
        const auto v = f(hx(e, q, 0), hx(e, q, 1), e);
        hf(e, q, 0) = v[0];
        hf(e, q, 1) = v[1];
      }
    Kokkos::deep_copy(fq, hf);
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
  auto hp = Kokkos::create_mirror_view(prescribed_);
  for (std::size_t i = 0; i < prescribedHost_.size(); ++i)
    hp(i) = prescribedHost_[i];
  Kokkos::deep_copy(prescribed_, hp);
}

LocalIndex ModelBase::numConstrained() const {
  return static_cast<LocalIndex>(std::count(constrainedHost_.begin(), constrainedHost_.end(), 1));
}

void ModelBase::commitStaged() {
  // Nodal forces join the reference load and are then cleared, so a second setup() does not add
  // them twice; constraints replace the device flags.
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), load_);
  for (std::size_t i = 0; i < stagedNodalForce_.size(); ++i)
    h(i) += stagedNodalForce_[i];
  Kokkos::deep_copy(load_, h);
  std::fill(stagedNodalForce_.begin(), stagedNodalForce_.end(), 0.0);
  auto hc = Kokkos::create_mirror_view(isConstrained_);
  auto hp = Kokkos::create_mirror_view(prescribed_);
  for (std::size_t i = 0; i < constrainedHost_.size(); ++i) {
    hc(i) = constrainedHost_[i];
    hp(i) = prescribedHost_[i];
  }
  Kokkos::deep_copy(isConstrained_, hc);
  Kokkos::deep_copy(prescribed_, hp);
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
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  return std::vector<double>(h.data(), h.data() + h.extent(0));
}

void ModelBase::fromHost(const std::vector<double> &h, const Kokkos::View<double *, Memory> &v) {
  auto m = Kokkos::create_mirror_view(v);
  for (std::size_t i = 0; i < h.size(); ++i)
    m(i) = h[i];
  Kokkos::deep_copy(v, m);
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
    Kokkos::View<double **[2], Memory> xq("mixcon::model::qpCoordinates", ne, Elem::kNumQp);
    Kokkos::View<double **[3], Memory> sq("mixcon::model::qpStress", ne, Elem::kNumQp);
    quadraturePointCoordinates<Elem>(Exec(), data_.mesh, xq);
    gaussPointStress<Elem>(Exec(), data_, Kokkos::View<const double *, Memory>(u_), sq);
    auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), xq);
    auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sq);
    pointsPerElement = Elem::kNumQp;
    coordinates.resize(static_cast<std::size_t>(ne) * Elem::kNumQp * 2);
    stress.resize(static_cast<std::size_t>(ne) * Elem::kNumQp * 3);
    for (LocalIndex e = 0; e < ne; ++e)
      for (int q = 0; q < Elem::kNumQp; ++q) {
        const std::size_t k = static_cast<std::size_t>(e) * Elem::kNumQp + q;
        for (int c = 0; c < 2; ++c)
          coordinates[2 * k + c] = hx(e, q, c);
        for (int c = 0; c < 3; ++c)
          stress[3 * k + c] = hs(e, q, c);
      }
  });
}

} // namespace mixcon
