// ModelBase: loads, constraints and displacement output shared by both models.
#include <core/Transfer.hpp>
#include <solver/FieldOps.hpp>
#include <solver/ModelBase.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mixcon {

ModelBase::ModelBase(const Mesh &mesh, const std::vector<int> &elementMaterial,
                     const std::vector<PlaneMatrix> &stiffness, double thickness)
    : mesh_(mesh), dofs_(DofMap::serial(mesh.numNodes(), mesh.dim())) {
  initialize(data_, elementMaterial, stiffness, thickness);
}

ModelBase::ModelBase(const Mesh &mesh, const std::vector<int> &elementMaterial,
                     const std::vector<SolidMatrix> &stiffness)
    : mesh_(mesh), dofs_(DofMap::serial(mesh.numNodes(), mesh.dim())) {
  initialize(solid_, elementMaterial, stiffness, 1.0);
}

template <int Dim, class Stiffness>
void ModelBase::initialize(ElementData<Memory, Dim> &data, const std::vector<int> &elementMaterial,
                           const std::vector<Stiffness> &stiffness, double thickness) {
  static_assert(std::is_same_v<Stiffness, typename ElementData<Memory, Dim>::Stiffness>,
                "the material stiffness of the mesh's dimension");
  data.mesh = toDevice<Memory, Dim>(mesh_); // throws when the mesh is not of dimension Dim
  data.thickness = thickness;
  data.material =
      Kokkos::View<int *, Memory>("mixcon::model::elementMaterial", mesh_.numElements());
  data.stiffness = Kokkos::View<Stiffness *, Memory>("mixcon::model::stiffness", stiffness.size());
  auto hm = hostMirror(data.material);
  for (LocalIndex e = 0; e < mesh_.numElements(); ++e)
    hm(e) = elementMaterial.at(e);
  copyToDevice(data.material, hm);
  auto hs = hostMirror(data.stiffness);
  for (std::size_t i = 0; i < stiffness.size(); ++i)
    hs(i) = stiffness[i];
  copyToDevice(data.stiffness, hs);

  const LocalIndex n = dofs_.numOwned();
  load_ = Kokkos::View<double *, Memory>("mixcon::model::load", n);
  u_ = Kokkos::View<double *, Memory>("mixcon::model::displacement", n);
  isConstrained_ = Kokkos::View<int *, Memory>("mixcon::model::constrained", n);
  prescribed_ = Kokkos::View<double *, Memory>("mixcon::model::prescribed", n);
  stagedNodalForce_.assign(n, 0.0);
  constrainedHost_.assign(n, 0);
  prescribedHost_.assign(n, 0.0);
}

void ModelBase::addSideLoad(const std::vector<BoundaryEdge> &sides,
                            const std::array<double, 3> &traction, double pressure) {
  if (sides.empty())
    return;
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    if constexpr (Elem::kDim == 2) {
      const auto batch = uniformEdgeLoads<Memory>(sides, traction[0], traction[1], pressure);
      assembleEdgeLoads<Elem>(Exec(), data_.mesh, batch.edges, batch.load, data_.thickness, load_);
    } else {
      const double t[3] = {traction[0], traction[1], traction[2]};
      const auto batch = uniformFaceLoads<Memory>(sides, t, pressure);
      assembleFaceLoads<Elem>(Exec(), solid_.mesh, batch.faces, batch.load, load_);
    }
  });
}

void ModelBase::addNodalForce(LocalIndex node, const std::array<double, 3> &force) {
  for (int c = 0; c < dim(); ++c)
    stagedNodalForce_[dofs_.dof(node, c)] += force[c];
}

namespace {
/// Adds the body force f(x, e) (x: the quadrature point, Dim coordinates) of every quadrature
/// point to `load`.
template <class Elem, class Memory, class F>
void addBodyForceOf(const ElementData<Memory, Elem::kDim> &data, const F &f,
                    const Kokkos::View<double *, Memory> &load) {
  using Exec = Kokkos::DefaultExecutionSpace;
  constexpr int dim = Elem::kDim;
  const LocalIndex ne = data.material.extent(0);
  Kokkos::View<double * * [Elem::kDim], Memory> xq("mixcon::model::qpCoordinates", ne,
                                                   Elem::kNumQp); // extents from Elem (docs/gpu.md)
  quadraturePointCoordinates<Elem>(Exec(), data.mesh, xq);
  auto hx = copyToHost(xq);
  Kokkos::View<double * * [Elem::kDim], Memory> fq("mixcon::model::qpBodyForce", ne, Elem::kNumQp);
  auto hf = hostMirror(fq);
  for (LocalIndex e = 0; e < ne; ++e)
    for (int q = 0; q < Elem::kNumQp; ++q) {
      double x[dim];
      for (int i = 0; i < dim; ++i)
        x[i] = hx(e, q, i);
      const auto v = f(x, e);
      for (int i = 0; i < dim; ++i)
        hf(e, q, i) = v[i];
    }
  copyToDevice(fq, hf);
  assembleBodyForce<Elem>(Exec(), data, Kokkos::View<const double * * [Elem::kDim], Memory>(fq),
                          load);
}
} // namespace

void ModelBase::addBodyForce(
    const std::function<std::array<double, 2>(double, double, LocalIndex)> &f) {
  dispatchPlaneElement(mesh_.elementType, "addBodyForce (x, y)", [&](auto elem) {
    addBodyForceOf<decltype(elem)>(
        data_, [&](const double(&x)[2], LocalIndex e) { return f(x[0], x[1], e); }, load_);
  });
}

void ModelBase::addBodyForce3D(
    const std::function<std::array<double, 3>(double, double, double, LocalIndex)> &f) {
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    if constexpr (Elem::kDim == 3)
      addBodyForceOf<Elem>(
          solid_, [&](const double(&x)[3], LocalIndex e) { return f(x[0], x[1], x[2], e); }, load_);
    else
      throw std::invalid_argument("addBodyForce3D: the mesh '" + mesh_.source + "' is 2D");
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
  uploadPrescribed();
}

void ModelBase::uploadPrescribed() {
  std::vector<double> base;
  if (staged())
    base = toHost(prescribedBase_);
  auto hp = hostMirror(prescribed_);
  for (std::size_t i = 0; i < prescribedHost_.size(); ++i)
    hp(i) = prescribedHost_[i] - (!base.empty() && constrainedHost_[i] ? base[i] : 0.0);
  copyToDevice(prescribed_, hp);
}

void ModelBase::beginStage() {
  const LocalIndex n = dofs_.numOwned();
  if (!staged()) {
    loadBase_ = Kokkos::View<double *, Memory>("mixcon::model::loadBase", n);
    prescribedBase_ = Kokkos::View<double *, Memory>("mixcon::model::prescribedBase", n);
  }
  // The constrained components have reached their end values; a component constrained now
  // starts where it is.
  Kokkos::deep_copy(prescribedBase_, u_);
  Kokkos::deep_copy(load_, 0.0);
  Kokkos::deep_copy(loadBase_, 0.0);
  std::fill(stagedNodalForce_.begin(), stagedNodalForce_.end(), 0.0);
  stagedBase_.assign(n, 0.0);
}

void ModelBase::addHost(const std::vector<double> &h, const Kokkos::View<double *, Memory> &v) {
  auto m = copyToHost(v);
  for (std::size_t i = 0; i < h.size(); ++i)
    m(i) += h[i];
  copyToDevice(v, m);
}

void ModelBase::loadsToBase() {
  Kokkos::deep_copy(loadBase_, load_);
  addHost(stagedNodalForce_, loadBase_);
  Kokkos::deep_copy(load_, 0.0);
  std::fill(stagedNodalForce_.begin(), stagedNodalForce_.end(), 0.0);
}

void ModelBase::release(LocalIndex node, int comp, double reaction) {
  const LocalIndex i = dofs_.dof(node, comp);
  if (!constrainedHost_[i])
    return; // already free (overlapping releases): its support force is carried once
  constrainedHost_[i] = 0;
  prescribedHost_[i] = 0.0;
  stagedBase_.resize(constrainedHost_.size(), 0.0);
  stagedBase_[i] += reaction;
  stagedNodalForce_[i] -= reaction;
}

void ModelBase::commitStage() {
  commitStaged();
  if (!stagedBase_.empty()) {
    addHost(stagedBase_, loadBase_);
    std::fill(stagedBase_.begin(), stagedBase_.end(), 0.0);
  }
  constraintsChanged();
}

void ModelBase::saveLoading(Checkpoint &state) const {
  if (!staged())
    return;
  state.put("loading/load_base", toHost(loadBase_));
  state.put("loading/load", toHost(load_));
  state.put("loading/prescribed_base", toHost(prescribedBase_));
  state.put("loading/prescribed_end", prescribedHost_);
  state.putIntegers("loading/constrained", constrainedHost_);
}

void ModelBase::restoreLoading(const Checkpoint &state) {
  if (!state.has("loading/load"))
    return; // saved before the first stage change: the loads as set up
  const std::size_t n = dofs_.numOwned();
  if (!staged())
    beginStage();
  fromHost(state.get("loading/load_base", n), loadBase_);
  fromHost(state.get("loading/load", n), load_);
  fromHost(state.get("loading/prescribed_base", n), prescribedBase_);
  prescribedHost_ = state.get("loading/prescribed_end", n);
  constrainedHost_ = state.getIntegers<int>("loading/constrained", n);
  std::fill(stagedNodalForce_.begin(), stagedNodalForce_.end(), 0.0);
  std::fill(stagedBase_.begin(), stagedBase_.end(), 0.0);
  uploadConstraints();
  constraintsChanged();
}

void ModelBase::subtractLoad(const Kokkos::View<double *, Memory> &g, int stride,
                             double lambda) const {
  fieldops::addDisplacementVector(g, stride, dim(), -lambda, load_);
  if (staged())
    fieldops::addDisplacementVector(g, stride, dim(), -1.0, loadBase_);
}

double ModelBase::appliedLoadNorm(double lambda) const {
  if (!staged())
    return std::abs(lambda) * fieldops::strideNorm(load_, 1, 0, 1, {}, 0);
  return fieldops::affineNorm(loadBase_, lambda, load_);
}

LocalIndex ModelBase::numConstrained() const {
  return static_cast<LocalIndex>(std::count(constrainedHost_.begin(), constrainedHost_.end(), 1));
}

void ModelBase::commitStaged() {
  // Nodal forces join the reference load and are then cleared, so a second setup() does not add
  // them twice; constraints replace the device flags.
  addHost(stagedNodalForce_, load_);
  std::fill(stagedNodalForce_.begin(), stagedNodalForce_.end(), 0.0);
  uploadConstraints();
}

void ModelBase::uploadConstraints() {
  auto hc = hostMirror(isConstrained_);
  for (std::size_t i = 0; i < constrainedHost_.size(); ++i)
    hc(i) = constrainedHost_[i];
  copyToDevice(isConstrained_, hc);
  uploadPrescribed();
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
  if (staged()) {
    const auto base = toHost(loadBase_);
    for (std::size_t i = 0; i < r.size(); ++i)
      r[i] -= base[i];
  }
  return r;
}

std::vector<double> ModelBase::displacementHost() const { return toHost(u_); }

void ModelBase::gaussPointStressHost(std::vector<double> &coordinates, std::vector<double> &stress,
                                     int &pointsPerElement) const {
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    // The extents spelled from Elem: nvcc 13's front end gives a view's extent the value of
    // another one's when both are local constants of a template (docs/gpu.md).
    using Coordinates = Kokkos::View<double * * [Elem::kDim], Memory>;
    using Stresses = Kokkos::View<double * * [Voigt<Elem::kDim>::kSize], Memory>;
    const auto &data = elementData<Elem::kDim>();
    const LocalIndex ne = mesh_.numElements();
    Coordinates xq("mixcon::model::qpCoordinates", ne, Elem::kNumQp);
    Stresses sq("mixcon::model::qpStress", ne, Elem::kNumQp);
    quadraturePointCoordinates<Elem>(Exec(), data.mesh, xq);
    gaussPointStress<Elem>(Exec(), data, Kokkos::View<const double *, Memory>(u_), sq);
    pointsPerElement = Elem::kNumQp;
    coordinates = toHostVector(xq);
    stress = toHostVector(sq);
  });
}

} // namespace mixcon
