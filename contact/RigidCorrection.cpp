// Rigid-obstacle contact in the linearized system (contact/RigidContact.hpp): the constraints of
// a correction as one ConstraintSet (local (n, t) frames at closed nodes, held normal and stick
// components, Dirichlet steps) solved by solveConstrained, with force-driven obstacles condensed
// on top; the residual the constraints leave free; friction forces as loads.
// Layer: contact (uses solver/).
#include <contact/RigidContact.hpp>
#include <core/Transfer.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/HostAlgebra.hpp>
#include <solver/Krylov.hpp>
#include <solver/LocalFrames.hpp>
#include <solver/ModelBase.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace mixcon {

using namespace fieldops;

const RigidContact::DeviceConstraints &RigidContact::deviceConstraints() const {
  // The entries: every node framed on an obstacle or loaded by a friction force, once each.
  if (!deviceStale_)
    return device_;
  const auto &c = constraints_;
  std::vector<LocalIndex> nodes;
  for (LocalIndex p : node_)
    if (c.framed[p] || c.force[2 * p] != 0.0 || c.force[2 * p + 1] != 0.0)
      nodes.push_back(p);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  const std::size_t m = nodes.size();
  auto &d = device_;
  if (d.node.extent(0) != m) {
    d.node = Kokkos::View<LocalIndex *, DeviceSpace>("mixcon::contact::constrainedNodes", m);
    d.flags = Kokkos::View<int *[4], DeviceSpace>("mixcon::contact::constraintFlags", m);
    d.values = Kokkos::View<double *[6], DeviceSpace>("mixcon::contact::constraintValues", m);
  }
  if (d.entry.extent(0) != static_cast<std::size_t>(numNodes_))
    d.entry = Kokkos::View<int *, DeviceSpace>("mixcon::contact::constraintEntry", numNodes_);
  auto hn = hostMirror(d.node);
  auto hf = hostMirror(d.flags);
  auto hv = hostMirror(d.values);
  for (std::size_t k = 0; k < m; ++k) {
    const LocalIndex p = nodes[k];
    hn(k) = p;
    hf(k, 0) = c.framed[p];
    hf(k, 1) = c.normalFixed[p];
    hf(k, 2) = c.tangentFixed[p];
    hf(k, 3) = c.obstacle[p];
    hv(k, 0) = c.normal[2 * p];
    hv(k, 1) = c.normal[2 * p + 1];
    hv(k, 2) = c.normalStep[p];
    hv(k, 3) = c.tangentStep[p];
    hv(k, 4) = c.force[2 * p];
    hv(k, 5) = c.force[2 * p + 1];
  }
  copyToDevice(d.node, hn);
  copyToDevice(d.flags, hf);
  copyToDevice(d.values, hv);
  Kokkos::deep_copy(d.entry, -1);
  const auto node = d.node;
  const auto entry = d.entry;
  Kokkos::parallel_for(
      "mixcon::contact::constraintEntries", Kokkos::RangePolicy<Exec>(0, m),
      KOKKOS_LAMBDA(LocalIndex k) { entry(node(k)) = k; });
  deviceStale_ = false;
  return device_;
}

double RigidContact::obstacleForce(const ConstVec &y, int stride,
                                   const Kokkos::View<const int *, Memory> &dirichlet, int o, int d,
                                   bool withFriction) const {
  // At each node closed on o, n (n . y), plus t (t . y) in stick, plus the friction force of
  // slip nodes when `withFriction`. Nodes with both components prescribed carry no contact force.
  const DeviceConstraints &c = deviceConstraints();
  const auto node = c.node;
  const auto flags = c.flags;
  const auto values = c.values;
  double f = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::contact::obstacleForce", Kokkos::RangePolicy<Exec>(0, node.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k, double &acc) {
        const LocalIndex i0 = stride * node(k);
        if (!flags(k, 0) || flags(k, 3) != o || (dirichlet(i0) && dirichlet(i0 + 1)))
          return;
        const double n[2] = {values(k, 0), values(k, 1)};
        const double t[2] = {-n[1], n[0]};
        acc += n[d] * (n[0] * y(i0) + n[1] * y(i0 + 1));
        if (flags(k, 2) && !dirichlet(i0) && !dirichlet(i0 + 1))
          acc += t[d] * (t[0] * y(i0) + t[1] * y(i0 + 1));
        if (withFriction)
          acc += values(k, 4 + d);
      },
      f);
  return f;
}

void RigidContact::locate(const Kokkos::View<const double *[2], Memory> &coordinates,
                          const Kokkos::View<const double *, Memory> &x, int stride,
                          const Kokkos::View<const int *, Memory> &) {
  detect(coordinates, x, stride);
}

void RigidContact::subtractForces(const Kokkos::View<double *, Memory> &g, int stride) const {
  const DeviceConstraints &c = deviceConstraints();
  const auto node = c.node;
  const auto values = c.values;
  Kokkos::parallel_for(
      "mixcon::contact::subtractFriction", Kokkos::RangePolicy<Exec>(0, node.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k) {
        for (int d = 0; d < 2; ++d)
          g(stride * node(k) + d) = -values(k, 4 + d) + g(stride * node(k) + d);
      });
}

double RigidContact::externalForceNorm(double appliedLoads) const {
  double f = appliedLoads;
  for (const auto &d : driven_)
    f = std::hypot(f, drivenForce(d)); // forces on driven obstacles
  return f;
}

bool RigidContact::constrains() const {
  for (int f : constraints_.framed)
    if (f)
      return true;
  return false;
}

double RigidContact::freeResidualNorm(const Kokkos::View<const double *, Memory> &gv,
                                      const Kokkos::View<const int *, Memory> &fv,
                                      int stride) const {
  // ||G|| over the displacement unknowns held neither by Dirichlet nor by contact conditions;
  // at a node held normally on an obstacle only the tangential component counts (slip).
  const DeviceConstraints &c = deviceConstraints();
  const auto entry = c.entry;
  const auto flags = c.flags;
  const auto values = c.values;
  double s = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::contact::freeResidual", Kokkos::RangePolicy<Exec>(0, numNodes_),
      KOKKOS_LAMBDA(LocalIndex p, double &acc) {
        const LocalIndex i0 = stride * p;
        const int k = entry(p);
        const bool framed = k >= 0 && flags(k, 0);
        if (framed && !fv(i0) && !fv(i0 + 1)) {
          const double gt = -values(k, 1) * gv(i0) + values(k, 0) * gv(i0 + 1);
          if (!flags(k, 2))
            acc += gt * gt;
          return;
        }
        for (int i = 0; i < 2; ++i)
          if (!fv(i0 + i) && !(framed && flags(k, 1)))
            acc += gv(i0 + i) * gv(i0 + i);
      },
      s);
  // The balance of every force-driven obstacle: applied force minus the contact forces.
  for (const auto &d : drivenComponents()) {
    const double r = drivenForce(d) - obstacleForce(gv, stride, fv, d.obstacle, d.direction, true);
    s += r * r;
  }
  return std::sqrt(s);
}

const ConstraintSet &RigidContact::buildSet(const ContactCorrection &sys) {
  // The system in local (n, t) frames at closed contact nodes: R^T K R dx~ = -R^T G, the normal
  // (and in stick the tangential) components prescribed, then dx = R dx~ (only the displacement
  // pair of a node rotates; `stride` unknowns per node). A contact node that also carries a
  // Dirichlet condition keeps its global frame: its free component then takes the normal
  // condition when the normal is along that axis (symmetry lines).
  const double lambda = sys.lambda;
  const int stride = sys.stride;
  const auto &fv = sys.flags;
  const auto &target = sys.target;
  const LocalIndex nn = numNodes_;
  // Flags and the prescribed step per unknown, the frames per node, built on the device from the
  // constraint entries (deviceConstraints: O(candidates) uploaded per detection, nothing here).
  const DeviceConstraints &dev = deviceConstraints();
  const auto entry = dev.entry;
  const auto cflags = dev.flags;
  const auto values = dev.values;
  const auto presc = sys.prescribed;
  const auto prescBase = sys.prescribedBase;
  const bool hasBase = prescBase.extent(0) > 0;
  const auto u = sys.displacement;
  if (setFlags_.extent(0) != fv.extent(0))
    setFlags_ = Kokkos::View<int *, Memory>("mixcon::nonlinear::contactFlags", fv.extent(0));
  if (setFramed_.extent(0) != static_cast<std::size_t>(nn)) {
    setFramed_ = Kokkos::View<int *, Memory>("mixcon::nonlinear::framed", nn);
    setNormal_ = Kokkos::View<double *[2], Memory>("mixcon::nonlinear::frameNormal", nn);
  }
  const auto df = setFlags_;
  const auto dfr = setFramed_;
  const auto dn = setNormal_;
  LocalIndex unsupported = nn; // the first node with an unsupported mix of conditions
  Kokkos::parallel_reduce(
      "mixcon::contact::localFrameConditions", Kokkos::RangePolicy<Exec>(0, nn),
      KOKKOS_LAMBDA(LocalIndex p, LocalIndex & bad) {
        const LocalIndex i0 = stride * p;
        for (int i = 0; i < stride; ++i) {
          df(i0 + i) = fv(i0 + i);
          target(i0 + i) = i < 2 && fv(i0 + i) ? (hasBase ? prescBase(2 * p + i) : 0.0) +
                                                     lambda * presc(2 * p + i) - u(2 * p + i)
                                               : 0.0;
        }
        dfr(p) = 0;
        dn(p, 0) = dn(p, 1) = 0.0;
        const int k = entry(p);
        if (k < 0 || !cflags(k, 0))
          return;
        const double n[2] = {values(k, 0), values(k, 1)};
        dn(p, 0) = n[0];
        dn(p, 1) = n[1];
        const bool fx = fv(i0) != 0, fy = fv(i0 + 1) != 0;
        if (fx && fy)
          return; // fully prescribed: the contact condition cannot act
        if (fx || fy) {
          const int fixed = fx ? 0 : 1, other = 1 - fixed;
          if (detail::fabs(n[other]) < 0.999) {
            bad = p < bad ? p : bad;
            return;
          }
          df(i0 + other) = 1;
          target(i0 + other) = (values(k, 2) - n[fixed] * target(i0 + fixed)) / n[other];
          return;
        }
        dfr(p) = 1;
        df(i0) = cflags(k, 1);
        df(i0 + 1) = cflags(k, 2);
        target(i0) = values(k, 2);
        target(i0 + 1) = values(k, 3);
      },
      Kokkos::Min<LocalIndex>(unsupported));
  if (unsupported < nn)
    throw InputError("node " + std::to_string(Mesh::externalId(nodeIds_, unsupported)) +
                     ": contact on a surface not normal to its free direction while the "
                     "other direction is prescribed is not supported");
  set_ = ConstraintSet{};
  set_.stride = stride;
  set_.flags = df;
  set_.values = target;
  set_.framed = dfr;
  set_.normal = dn;
  return set_;
}

const ConstraintSet *RigidContact::constraintSet(const ContactCorrection &sys) {
  return drivenComponents().empty() ? &buildSet(sys) : nullptr;
}

LinearSolveStats RigidContact::correct(const ContactCorrection &sys,
                                       const Kokkos::View<double *, Memory> &dx) {
  const int stride = sys.stride;
  const CsrMatrix<Memory> &tangent = *sys.tangent;
  CsrMatrix<Memory> &work = *sys.work;
  LinearSolver &solver = *sys.solver;
  const auto &fv = sys.flags;
  const auto &g = sys.g;
  const auto &rhs = sys.rhs;
  const auto start = std::chrono::steady_clock::now();
  const ConstraintSet &set = buildSet(sys);
  axpby(-1.0, g, 0.0, rhs);
  *sys.setupSeconds += seconds(start);
  LinearSolveStats s =
      solveConstrained(set, tangent, work, elimination_, rhs, solver, dx, sys.setupSeconds);
  const auto &driven = drivenComponents();
  const std::size_t nd = driven.size();
  if (nd == 0)
    return s;

  // Force-driven obstacles: their motion dc along each driven component is an unknown. The
  // prescribed normal (and stick tangential) components of their closed nodes then read
  // step + (n . dc) (and t . dc), so the correction is dx0 + sum_j dx_j dc_j with dx_j the
  // response to a unit motion along component j; dc follows from the balance of the contact
  // forces on each obstacle with its applied force (static condensation of the 2 rigid-body
  // unknowns per obstacle, exact for the linearized problem). It stays here, outside the
  // constraint set: dc is an unknown coupled to the contact forces, not a constraint on dx.
  // `work` now holds the constrained R^T K R (prescribed rows and columns replaced) that the
  // solver factored; the unit responses need R^T K R itself: rotated afresh (the same values).
  const auto cfr = Kokkos::View<const int *, Memory>(set.framed);
  const auto cn = set.normal;
  const auto cf = set.flags;
  const DeviceConstraints &dev = deviceConstraints();
  const auto cflags = dev.flags;
  const auto values = dev.values;
  const auto dfr = cfr;
  CsrMatrix<Memory> rotated = cloneValues(tangent);
  rotateToLocalFrames(Exec(), rotated, stride, cfr, cn, Vec());

  // Responses to unit obstacle motions (same factorization), then the obstacle balance.
  const LocalIndex n = static_cast<LocalIndex>(g.extent(0));
  Vec diag("mixcon::nonlinear::contactDiag", n), zero("mixcon::nonlinear::zero", n),
      lifted("mixcon::nonlinear::lifted", n), unit("mixcon::nonlinear::unitStep", n),
      product("mixcon::nonlinear::product", n);
  constrainedDiagonal(Exec(), work, cf, diag);
  std::vector<Vec> response(nd);
  for (std::size_t j = 0; j < nd; ++j) {
    // The unit motion of component j at the closed nodes of its obstacle, in their frames.
    Kokkos::deep_copy(unit, 0.0);
    const auto node = dev.node;
    const int o = driven[j].obstacle, d = driven[j].direction;
    Kokkos::parallel_for(
        "mixcon::contact::unitObstacleStep", Kokkos::RangePolicy<Exec>(0, node.extent(0)),
        KOKKOS_LAMBDA(LocalIndex k) {
          const LocalIndex p = node(k), i0 = stride * p;
          if (!cflags(k, 0) || cflags(k, 3) != o)
            return;
          const double nk[2] = {values(k, 0), values(k, 1)};
          const double t[2] = {-nk[1], nk[0]};
          if (dfr(p)) {
            unit(i0) = nk[d];
            if (cflags(k, 2))
              unit(i0 + 1) = t[d];
          } else if (!(fv(i0) && fv(i0 + 1))) {
            const int other = fv(i0) ? 1 : 0;
            unit(i0 + other) = nk[d] / nk[other];
          }
        });
    multiply(Exec(), rotated, ConstVec(unit), product);
    constrainedRhs(Exec(), cf, ConstVec(diag), ConstVec(zero), ConstVec(unit), ConstVec(product),
                   lifted);
    response[j] = Vec("mixcon::nonlinear::unitResponse", n);
    const LinearSolveStats sj = solver.solve(lifted, response[j]);
    s.iterations += sj.iterations;
    s.solveSeconds += sj.solveSeconds;
    s.converged = s.converged && sj.converged;
    fromLocalFrames(Exec(), stride, cfr, cn, response[j]);
  }
  multiply(Exec(), tangent, ConstVec(dx), product);
  axpby(1.0, g, 1.0, product); // G + K dx0: the linearized residual after the base correction
  std::vector<double> a(nd * nd), b(nd), dc;
  for (std::size_t i = 0; i < nd; ++i)
    b[i] = drivenForce(driven[i]) -
           obstacleForce(product, stride, fv, driven[i].obstacle, driven[i].direction, true);
  for (std::size_t j = 0; j < nd; ++j) {
    multiply(Exec(), tangent, ConstVec(response[j]), product);
    for (std::size_t i = 0; i < nd; ++i)
      a[nd * i + j] =
          obstacleForce(product, stride, fv, driven[i].obstacle, driven[i].direction, false);
  }
  if (!solveSmallDense(a, nd, b, dc, 1e-10)) {
    std::ostringstream m;
    m << "force-driven " << obstacleLabel(driven[0].obstacle)
      << " has no stiffness along a driven direction: its closed nodes cannot carry the force "
         "there (too few contact nodes, or frictionless contact loaded tangentially)";
    throw std::runtime_error(m.str());
  }
  for (std::size_t j = 0; j < nd; ++j)
    axpby(dc[j], response[j], 1.0, dx);
  std::vector<double> motion(2 * specs().size(), 0.0);
  for (std::size_t j = 0; j < nd; ++j)
    motion[2 * driven[j].obstacle + driven[j].direction] += dc[j];
  for (std::size_t o = 0; o < specs().size(); ++o)
    if (motion[2 * o] != 0.0 || motion[2 * o + 1] != 0.0)
      moveObstacle(static_cast<int>(o), &motion[2 * o]);
  return s;
}

} // namespace mixcon
