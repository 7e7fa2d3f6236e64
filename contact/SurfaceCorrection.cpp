// Node-to-segment contact in the linearized system (contact/SurfaceContact.hpp): the closed pairs
// as multipoint constraints eliminated from the corrections of the nonlinear models (x = T y + s),
// the residual T^T G the constrained system balances, friction forces as loads.
// Layer: contact (uses solver/).
#include <contact/SurfaceContact.hpp>
#include <core/Transfer.hpp>
#include <solver/FieldOps.hpp>
#include <solver/Krylov.hpp>
#include <solver/ModelBase.hpp>

#include <chrono>
#include <cmath>

namespace mixcon {

using namespace fieldops;

void SurfaceContact::locate(const Kokkos::View<const double *[2], Memory> &coordinates,
                            const Kokkos::View<const double *, Memory> &x, int stride,
                            const Kokkos::View<const int *, Memory> &flags) {
  // The displacement unknowns held by Dirichlet conditions at the contactor and target nodes
  // (contactors held there take the normal condition on their free component; a target node
  // held in one direction lies on a symmetry line): O(surface nodes) copied.
  const LocalIndex ns = static_cast<LocalIndex>(surfaceNodes_.size());
  const auto held = surfaceHeld_;
  const auto nodes = deviceSurfaceNodes_;
  Kokkos::parallel_for(
      "mixcon::surface::gatherFlags", Kokkos::RangePolicy<Exec>(0, ns),
      KOKKOS_LAMBDA(LocalIndex k) {
        for (int i = 0; i < 2; ++i)
          held(k, i) = flags(stride * nodes(k) + i);
      });
  const auto h = copyToHost(held);
  for (LocalIndex k = 0; k < ns; ++k)
    for (int i = 0; i < 2; ++i)
      prescribed_[2 * static_cast<std::size_t>(surfaceNodes_[k]) + i] = h(k, i);
  deviceConstraintsFresh_ = false;
  detect(coordinates, x, stride);
}

void SurfaceContact::subtractForces(const Kokkos::View<double *, Memory> &g, int stride) const {
  // The friction forces of slip pairs (only the nodes that carry one) as loads.
  const auto nodes = frictionNodes_;
  const auto f = frictionValues_;
  Kokkos::parallel_for(
      "mixcon::surface::subtractFriction", Kokkos::RangePolicy<Exec>(0, nodes.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k) {
        for (int i = 0; i < 2; ++i)
          g(stride * nodes(k) + i) -= f(k, i);
      });
}

double SurfaceContact::freeResidualNorm(const Kokkos::View<const double *, Memory> &g,
                                        const Kokkos::View<const int *, Memory> &flags,
                                        int stride) const {
  // The residual the constrained system balances, T^T G, over the unknowns held neither by
  // Dirichlet conditions nor as contact slaves: a device reduction.
  ConstraintSet set;
  set.stride = stride;
  set.flags = flags;
  set.multipoint = &deviceConstraints(stride, static_cast<LocalIndex>(g.extent(0)));
  return constrainedFreeNorm(set, g);
}

const DeviceMultiPointConstraints &SurfaceContact::deviceConstraints(int stride,
                                                                     LocalIndex n) const {
  if (!deviceConstraintsFresh_ || deviceConstraintsStride_ != stride ||
      deviceConstraints_.numUnknowns != n) {
    MultiPointConstraints c;
    constraints(stride, c, &conditions_); // the same constraints as conditions, kept with them
    deviceConstraints_ = toDevice(c, n);
    deviceConstraintsFresh_ = true;
    deviceConstraintsStride_ = stride;
  }
  return deviceConstraints_;
}

void SurfaceContact::constraints(int stride, MultiPointConstraints &c,
                                 std::vector<LinearCondition> *conditions) const {
  // Per closed contactor p on target nodes i with weights w_i: in its local frame (n, t) the
  // normal displacement is sum_i w_i n . u_i - gap (slave), in stick the tangential one
  // sum_j w_j t . u_j + tangentStep at the anchor (slave), in slip the tangential one free:
  // u_p = n (sum_i w_i n . u_i + step_n) + t (...). A contactor with one component held by a
  // Dirichlet condition (a symmetry line) takes the normal condition on its other component.
  c.clear();
  if (conditions)
    conditions->clear();
  for (const SurfacePair &q : pairs_) {
    const LocalIndex i0 = stride * q.node;
    const bool fx = prescribed_[2 * static_cast<std::size_t>(q.node)] != 0,
               fy = prescribed_[2 * static_cast<std::size_t>(q.node) + 1] != 0;
    if (fx && fy)
      continue;
    std::vector<std::pair<LocalIndex, double>> normalRow, tangentRow;
    for (int a = 0; a < q.normalCount; ++a)
      for (int d = 0; d < 2; ++d)
        normalRow.emplace_back(stride * q.normalNodes[a] + d, q.normalWeights[a] * q.normal[d]);
    if (conditions) { // n . u_p - normalRow . u = step_n (a held component of p included)
      LinearCondition normal{{{i0, q.normal[0]}, {i0 + 1, q.normal[1]}}, q.normalStep};
      for (const auto &e : normalRow)
        normal.entries.emplace_back(e.first, -e.second);
      conditions->push_back(std::move(normal));
    }
    if (fx || fy) {
      const int fixed = fx ? 0 : 1, other = 1 - fixed;
      const double nf = q.normal[fixed], no = q.normal[other];
      if (std::abs(no) < 0.7)
        throw InputError("node " + std::to_string(Mesh::externalId(nodeIds_, q.node)) +
                         ": node-to-segment contact on a surface not normal to its free direction "
                         "while the other direction is prescribed is not supported");
      auto row = normalRow;
      for (auto &e : row)
        e.second /= no;
      row.emplace_back(i0 + fixed, -nf / no);
      c.addRow(i0 + other, row, q.normalStep / no);
      c.slaves.push_back(i0 + other);
      continue;
    }
    if (q.stick)
      for (int a = 0; a < q.tangentCount; ++a)
        for (int d = 0; d < 2; ++d)
          tangentRow.emplace_back(stride * q.tangentNodes[a] + d,
                                  q.tangentWeights[a] * q.tangent[d]);
    if (conditions && q.stick) { // t . u_p - tangentRow . u = step_t
      LinearCondition tangent{{{i0, q.tangent[0]}, {i0 + 1, q.tangent[1]}}, q.tangentStep};
      for (const auto &e : tangentRow)
        tangent.entries.emplace_back(e.first, -e.second);
      conditions->push_back(std::move(tangent));
    }
    for (int d = 0; d < 2; ++d) {
      std::vector<std::pair<LocalIndex, double>> row;
      for (const auto &e : normalRow)
        row.emplace_back(e.first, q.normal[d] * e.second);
      double offset = q.normal[d] * q.normalStep;
      if (q.stick) {
        for (const auto &e : tangentRow)
          row.emplace_back(e.first, q.tangent[d] * e.second);
        offset += q.tangent[d] * q.tangentStep;
      } else {
        row.emplace_back(i0 + 1, q.tangent[d]); // the free local tangential component
      }
      c.addRow(i0 + d, row, offset);
    }
    c.slaves.push_back(i0);
    if (q.stick)
      c.slaves.push_back(i0 + 1);
  }
}

const ConstraintSet *SurfaceContact::constraintSet(const ContactCorrection &sys) {
  prescribedStep(sys.flags, sys.prescribed, sys.displacement, sys.lambda, sys.stride, kDisp,
                 sys.target, sys.prescribedBase);
  set_ = ConstraintSet{};
  set_.stride = sys.stride;
  set_.flags = sys.flags;
  set_.values = sys.target;
  set_.multipoint = &deviceConstraints(sys.stride, static_cast<LocalIndex>(sys.target.extent(0)));
  set_.slaveDiagonal = std::max(sys.stiffnessScale, 1e-300);
  set_.conditions = &conditions_; // built with the device constraints above
  return &set_;
}

LinearSolveStats SurfaceContact::correct(const ContactCorrection &sys,
                                         const Kokkos::View<double *, Memory> &dx) {
  // The contact constraints eliminated (solver/MultiPointConstraints.hpp): (T^T K T + D) y =
  // T^T (-G - K s), the Dirichlet conditions applied to that system as usual, x = T y + s.
  const auto start = std::chrono::steady_clock::now();
  const ConstraintSet &set = *constraintSet(sys);
  axpby(-1.0, sys.g, 0.0, sys.rhs);
  *sys.setupSeconds += seconds(start);
  return solveConstrained(set, *sys.tangent, work_, elimination_, sys.rhs, *sys.solver, dx,
                          sys.setupSeconds);
}

} // namespace mixcon
