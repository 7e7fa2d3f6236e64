// Rigid-obstacle contact in the linearized system (contact/RigidContact.hpp): the corrections
// of the nonlinear models solved in local (n, t) frames at closed nodes, with force-driven
// obstacles condensed; the residual the constraints leave free; friction forces as loads.
// Layer: contact (uses solver/).
#include <contact/RigidContact.hpp>
#include <core/Transfer.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/Krylov.hpp>
#include <solver/LocalFrames.hpp>
#include <solver/ModelBase.hpp>

#include <Eigen/Dense>

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace mixcon {

using namespace fieldops;

namespace {

/// Component d of the contact force that obstacle o exerts on the body, from a residual-like
/// host vector y (`stride` unknowns per node; the Dirichlet flags `dirichlet` per unknown): at
/// each node closed on o, n (n . y), plus t (t . y) in stick, plus the friction force of slip
/// nodes when `withFriction`. Nodes with both components prescribed carry no contact force.
double obstacleForce(const ContactConstraints &c, const double *y, int stride, const int *dirichlet,
                     LocalIndex numNodes, int o, int d, bool withFriction) {
  double f = 0.0;
  for (LocalIndex p = 0; p < numNodes; ++p) {
    const LocalIndex i0 = stride * p;
    if (!c.framed[p] || c.obstacle[p] != o || (dirichlet[i0] && dirichlet[i0 + 1]))
      continue;
    const double n[2] = {c.normal[2 * p], c.normal[2 * p + 1]};
    const double t[2] = {-n[1], n[0]};
    f += n[d] * (n[0] * y[i0] + n[1] * y[i0 + 1]);
    if (c.tangentFixed[p] && !dirichlet[i0] && !dirichlet[i0 + 1])
      f += t[d] * (t[0] * y[i0] + t[1] * y[i0 + 1]);
    if (withFriction)
      f += c.force[2 * p + d];
  }
  return f;
}

} // namespace

void RigidContact::locate(const Kokkos::View<const double *[2], Memory> &coordinates,
                          const Kokkos::View<const double *, Memory> &x, int stride,
                          const Kokkos::View<const int *, Memory> &) {
  detect(coordinates, x, stride);
}

void RigidContact::subtractForces(const Kokkos::View<double *, Memory> &g, int stride) const {
  subtractNodalForces(g, stride, constraints_.force);
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
  const auto g = copyToHost(gv);
  const auto flags = copyToHost(fv);
  const auto &c = constraints_;
  double s = 0.0;
  for (LocalIndex p = 0; p < numNodes_; ++p) {
    const LocalIndex i0 = stride * p;
    if (c.framed[p] && !flags(i0) && !flags(i0 + 1)) {
      const double n0 = c.normal[2 * p], n1 = c.normal[2 * p + 1];
      const double gt = -n1 * g(i0) + n0 * g(i0 + 1);
      if (!c.tangentFixed[p])
        s += gt * gt;
      continue;
    }
    for (int i = 0; i < 2; ++i)
      if (!flags(i0 + i) && !(c.framed[p] && c.normalFixed[p]))
        s += g(i0 + i) * g(i0 + i);
  }
  // The balance of every force-driven obstacle: applied force minus the contact forces.
  for (const auto &d : drivenComponents()) {
    const double r = drivenForce(d) - obstacleForce(c, g.data(), stride, flags.data(), numNodes_,
                                                    d.obstacle, d.direction, true);
    s += r * r;
  }
  return std::sqrt(s);
}

LinearSolveStats RigidContact::correct(const ContactCorrection &sys,
                                       const Kokkos::View<double *, Memory> &dx) {
  // The system in local (n, t) frames at closed contact nodes: R^T K R dx~ = -R^T G, the normal
  // (and in stick the tangential) components prescribed, then dx = R dx~ (only the displacement
  // pair of a node rotates; `stride` unknowns per node). A contact node that also carries a
  // Dirichlet condition keeps its global frame: its free component then takes the normal
  // condition when the normal is along that axis (symmetry lines).
  const double lambda = sys.lambda;
  const int stride = sys.stride;
  const CsrMatrix<Memory> &tangent = *sys.tangent;
  CsrMatrix<Memory> &work = *sys.work;
  LinearSolver &solver = *sys.solver;
  const auto &fv = sys.flags;
  const auto &g = sys.g;
  const auto &rhs = sys.rhs;
  const auto &target = sys.target;
  const auto &c = constraints_;
  const LocalIndex nn = numNodes_;
  const auto dflags = copyToHost(fv);
  std::vector<int> flags(dflags.data(), dflags.data() + dflags.extent(0));
  const auto presc = ModelBase::toHost(sys.prescribed);
  const auto u = ModelBase::toHost(sys.displacement);
  std::vector<double> step(stride * static_cast<std::size_t>(nn), 0.0);
  std::vector<int> framed(nn, 0);
  for (LocalIndex p = 0; p < nn; ++p)
    for (int i = 0; i < 2; ++i)
      if (flags[stride * p + i])
        step[stride * p + i] = lambda * presc[2 * p + i] - u[2 * p + i];
  for (LocalIndex p = 0; p < nn; ++p) {
    if (!c.framed[p])
      continue;
    const LocalIndex i0 = stride * p;
    const double n[2] = {c.normal[2 * p], c.normal[2 * p + 1]};
    const bool fx = flags[i0] != 0, fy = flags[i0 + 1] != 0;
    if (fx && fy)
      continue; // fully prescribed: the contact condition cannot act
    if (fx || fy) {
      const int fixed = fx ? 0 : 1, other = 1 - fixed;
      if (std::abs(n[other]) < 0.999)
        throw InputError("node " + std::to_string(Mesh::externalId(nodeIds_, p)) +
                         ": contact on a surface not normal to its free direction while the "
                         "other direction is prescribed is not supported");
      flags[i0 + other] = 1;
      step[i0 + other] = (c.normalStep[p] - n[fixed] * step[i0 + fixed]) / n[other];
      continue;
    }
    framed[p] = 1;
    flags[i0] = c.normalFixed[p];
    flags[i0 + 1] = c.tangentFixed[p];
    step[i0] = c.normalStep[p];
    step[i0 + 1] = c.tangentStep[p];
  }
  // Force-driven obstacles: their motion dc along each driven component is an unknown. The
  // prescribed normal (and stick tangential) components of their closed nodes then read
  // step + (n . dc) (and t . dc), so the correction is dx0 + sum_j dx_j dc_j with dx_j the
  // response to a unit motion along component j; dc follows from the balance of the contact
  // forces on each obstacle with its applied force (static condensation of the 2 rigid-body
  // unknowns per obstacle, exact for the linearized problem).
  const auto &driven = drivenComponents();
  const std::size_t nd = driven.size();
  std::vector<std::vector<double>> unitStep(nd, std::vector<double>(step.size(), 0.0));
  for (std::size_t j = 0; j < nd; ++j)
    for (LocalIndex p = 0; p < nn; ++p) {
      if (!c.framed[p] || c.obstacle[p] != driven[j].obstacle)
        continue;
      const LocalIndex i0 = stride * p;
      const double n[2] = {c.normal[2 * p], c.normal[2 * p + 1]};
      const double t[2] = {-n[1], n[0]};
      const int d = driven[j].direction;
      if (framed[p]) {
        unitStep[j][i0] = n[d];
        if (c.tangentFixed[p])
          unitStep[j][i0 + 1] = t[d];
      } else if (!(dflags(i0) && dflags(i0 + 1))) {
        const int other = dflags(i0) ? 1 : 0;
        unitStep[j][i0 + other] = n[d] / n[other];
      }
    }
  const auto start = std::chrono::steady_clock::now();
  Kokkos::View<int *, Memory> df("mixcon::nonlinear::contactFlags", flags.size()),
      dfr("mixcon::nonlinear::framed", nn);
  Kokkos::View<double *[2], Memory> dn("mixcon::nonlinear::frameNormal", nn);
  auto hf = hostMirror(df);
  auto hfr = hostMirror(dfr);
  auto hn = hostMirror(dn);
  auto ht = hostMirror(target);
  for (std::size_t i = 0; i < flags.size(); ++i) {
    hf(i) = flags[i];
    ht(i) = step[i];
  }
  for (LocalIndex p = 0; p < nn; ++p) {
    hfr(p) = framed[p];
    hn(p, 0) = c.normal[2 * p];
    hn(p, 1) = c.normal[2 * p + 1];
  }
  copyToDevice(df, hf);
  copyToDevice(dfr, hfr);
  copyToDevice(dn, hn);
  copyToDevice(target, ht);
  if (work.numRows == 0)
    work = cloneValues(tangent);
  else
    Kokkos::deep_copy(work.values, tangent.values);
  axpby(-1.0, g, 0.0, rhs);
  const auto cfr = Kokkos::View<const int *, Memory>(dfr);
  const auto cn = Kokkos::View<const double *[2], Memory>(dn);
  const auto cf = Kokkos::View<const int *, Memory>(df);
  rotateToLocalFrames(Exec(), work, stride, cfr, cn, rhs);
  CsrMatrix<Memory> rotated;
  if (nd > 0)
    rotated = cloneValues(work);
  applyDirichlet(Exec(), work, cf, ConstVec(target), rhs);
  Exec().fence();
  solver.setup(work);
  *sys.setupSeconds += seconds(start);
  LinearSolveStats s = solver.solve(rhs, dx);
  fromLocalFrames(Exec(), stride, cfr, cn, dx);
  if (nd == 0)
    return s;

  // Responses to unit obstacle motions (same factorization), then the obstacle balance.
  const LocalIndex n = static_cast<LocalIndex>(g.extent(0));
  Vec diag("mixcon::nonlinear::contactDiag", n), zero("mixcon::nonlinear::zero", n),
      lifted("mixcon::nonlinear::lifted", n), unit("mixcon::nonlinear::unitStep", n),
      product("mixcon::nonlinear::product", n);
  constrainedDiagonal(Exec(), work, cf, diag);
  std::vector<Vec> response(nd);
  for (std::size_t j = 0; j < nd; ++j) {
    auto hu = hostMirror(unit);
    for (LocalIndex i = 0; i < n; ++i)
      hu(i) = unitStep[j][i];
    copyToDevice(unit, hu);
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
  const auto base = ModelBase::toHost(product);
  Eigen::MatrixXd a(nd, nd);
  Eigen::VectorXd b(nd);
  for (std::size_t i = 0; i < nd; ++i)
    b(i) = drivenForce(driven[i]) - obstacleForce(c, base.data(), stride, dflags.data(), nn,
                                                  driven[i].obstacle, driven[i].direction, true);
  for (std::size_t j = 0; j < nd; ++j) {
    multiply(Exec(), tangent, ConstVec(response[j]), product);
    const auto y = ModelBase::toHost(product);
    for (std::size_t i = 0; i < nd; ++i)
      a(i, j) = obstacleForce(c, y.data(), stride, dflags.data(), nn, driven[i].obstacle,
                              driven[i].direction, false);
  }
  Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  lu.setThreshold(1e-10);
  if (!lu.isInvertible()) {
    std::ostringstream m;
    m << "force-driven " << obstacleLabel(driven[0].obstacle)
      << " has no stiffness along a driven direction: its closed nodes cannot carry the force "
         "there (too few contact nodes, or frictionless contact loaded tangentially)";
    throw std::runtime_error(m.str());
  }
  const Eigen::VectorXd dc = lu.solve(b);
  for (std::size_t j = 0; j < nd; ++j)
    axpby(dc(j), response[j], 1.0, dx);
  std::vector<double> motion(2 * specs().size(), 0.0);
  for (std::size_t j = 0; j < nd; ++j)
    motion[2 * driven[j].obstacle + driven[j].direction] += dc(j);
  for (std::size_t o = 0; o < specs().size(); ++o)
    if (motion[2 * o] != 0.0 || motion[2 * o + 1] != 0.0)
      moveObstacle(static_cast<int>(o), &motion[2 * o]);
  return s;
}

} // namespace mixcon
