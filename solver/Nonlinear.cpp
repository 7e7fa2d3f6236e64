// Nonlinear models (host orchestration of the kernels in kernels/Nonlinear.hpp) and the load
// stepper.
#include <contact/RigidContact.hpp>
#include <contact/SurfaceContact.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/Krylov.hpp>
#include <solver/LocalFrames.hpp>
#include <solver/MixedModel.hpp>
#include <solver/MultiPointConstraints.hpp>
#include <solver/Nonlinear.hpp>

#include <kernels/Nonlinear.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace mixcon {

// Named (not anonymous): nvcc rejects device lambdas in functions of an unnamed namespace.
namespace nonlinear_detail {

using Exec = Kokkos::DefaultExecutionSpace;
using Memory = DeviceSpace;
using Vec = Kokkos::View<double *, Memory>;
using ConstVec = Kokkos::View<const double *, Memory>;

double seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The row (or entry) of the i-th unknown of one field of an interleaved vector or matrix: the
/// `width` unknowns from `offset` of every `stride`.
KOKKOS_INLINE_FUNCTION LocalIndex fieldRow(int stride, int offset, int width, LocalIndex i) {
  return stride * (i / width) + offset + i % width;
}

/// Two-norm of the first `width` of every `stride` entries of v, restricted to entries whose
/// flag is `flagged` (flags: nullptr-like empty view means all).
double strideNorm(const ConstVec &v, int stride, int first, int width,
                  const Kokkos::View<const int *, Memory> &flags, int flagged) {
  const LocalIndex n = v.extent(0) / stride;
  const bool useFlags = flags.extent(0) > 0;
  double s = 0.0;
  Kokkos::parallel_reduce(
      "mixcon::nonlinear::norm", Kokkos::RangePolicy<Exec>(0, n),
      KOKKOS_LAMBDA(LocalIndex k, double &acc) {
        for (int c = first; c < first + width; ++c) {
          const LocalIndex i = stride * k + c;
          if (!useFlags || (flags(i) != 0) == (flagged != 0))
            acc += v(i) * v(i);
        }
      },
      s);
  return std::sqrt(s);
}

double relative(double num, double den) {
  if (den > 0.0)
    return num / den;
  return num == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
}

/// y(stride k + c) += alpha x(2 k + c), c = 0, 1.
void addDisplacementVector(const Vec &y, int stride, double alpha, const ConstVec &x) {
  Kokkos::parallel_for(
      "mixcon::nonlinear::addDisplacementVector", Kokkos::RangePolicy<Exec>(0, x.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { y(stride * (i / 2) + i % 2) += alpha * x(i); });
}

/// dst(width k + c) = scale src(stride k + offset + c), k < dst.extent(0) / width (gathers a
/// field out of an interleaved vector, e.g. the stresses out of 5 unknowns per node).
void gather(const ConstVec &src, int stride, int offset, int width, const Vec &dst,
            double scale = 1.0) {
  Kokkos::parallel_for(
      "mixcon::nonlinear::gather", Kokkos::RangePolicy<Exec>(0, dst.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { dst(i) = scale * src(fieldRow(stride, offset, width, i)); });
}

/// dst(stride k + offset + c) = src(width k + c); other entries of dst set to zero when
/// `zeroRest` (the inverse of gather).
template <class T>
void scatter(const Kokkos::View<const T *, Memory> &src, int stride, int offset, int width,
             const Kokkos::View<T *, Memory> &dst, bool zeroRest) {
  if (zeroRest)
    Kokkos::deep_copy(dst, T(0));
  Kokkos::parallel_for(
      "mixcon::nonlinear::scatter", Kokkos::RangePolicy<Exec>(0, src.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { dst(fieldRow(stride, offset, width, i)) = src(i); });
}

/// dst(i) = sign a(r, r), r = stride (i / width) + offset + i % width: diagonal entries of the
/// rows of one field of an interleaved CSR matrix.
void fieldDiagonal(const CsrMatrix<Memory> &a, int stride, int offset, int width, const Vec &dst,
                   double sign) {
  auto ro = a.rowOffsets;
  auto co = a.columns;
  auto va = a.values;
  Kokkos::parallel_for(
      "mixcon::nonlinear::fieldDiagonal", Kokkos::RangePolicy<Exec>(0, dst.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) {
        const LocalIndex r = fieldRow(stride, offset, width, i);
        for (Offset k = ro(r); k < ro(r + 1); ++k)
          if (co(k) == r)
            dst(i) = sign * va(k);
      });
}

/// b <- sign * (the block of a's field rows [rowOffset, rowOffset + rowWidth) and field
/// columns [columnOffset, columnOffset + columnWidth)), with a on expandGraph(graph, stride) and b
/// on expandGraph(graph, rowWidth, columnWidth) of the same graph (both list a row's neighbour
/// nodes in the same order).
void extractFieldBlock(const CsrMatrix<Memory> &a, int stride, int rowOffset, int rowWidth,
                       int columnOffset, int columnWidth, const CsrMatrix<Memory> &b, double sign) {
  auto ra = a.rowOffsets;
  auto va = a.values;
  auto rb = b.rowOffsets;
  auto vb = b.values;
  Kokkos::parallel_for(
      "mixcon::nonlinear::extractFieldBlock", Kokkos::RangePolicy<Exec>(0, b.numRows),
      KOKKOS_LAMBDA(LocalIndex r) {
        const LocalIndex p = r / rowWidth, i = r % rowWidth;
        const Offset first = rb(r);
        const LocalIndex neighbours = static_cast<LocalIndex>((rb(r + 1) - first) / columnWidth);
        const Offset src = ra(stride * p + rowOffset + i);
        for (LocalIndex j = 0; j < neighbours; ++j)
          for (int c = 0; c < columnWidth; ++c)
            vb(first + columnWidth * j + c) = sign * va(src + stride * j + columnOffset + c);
      });
}

/// y(width p + c) = sum_k a(r, k) x(k), r = stride p + offset + c: the rows of one field of an
/// interleaved CSR matrix times x, gathered (a product with [A B] or [C -M] of the mixed
/// Jacobian that reads only those rows).
void multiplyFieldRows(const CsrMatrix<Memory> &a, int stride, int offset, int width,
                       const ConstVec &x, const Vec &y) {
  auto ro = a.rowOffsets;
  auto co = a.columns;
  auto va = a.values;
  Kokkos::parallel_for(
      "mixcon::nonlinear::multiplyFieldRows", Kokkos::RangePolicy<Exec>(0, y.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) {
        const LocalIndex r = fieldRow(stride, offset, width, i);
        double s = 0.0;
        for (Offset k = ro(r); k < ro(r + 1); ++k)
          s += va(k) * x(co(k));
        y(i) = s;
      });
}

/// v(stride p + offset + c) *= s for c < width.
void scaleField(const Vec &v, int stride, int offset, int width, double s) {
  Kokkos::parallel_for(
      "mixcon::nonlinear::scaleField", Kokkos::RangePolicy<Exec>(0, v.extent(0) / stride),
      KOKKOS_LAMBDA(LocalIndex p) {
        for (int c = 0; c < width; ++c)
          v(stride * p + offset + c) *= s;
      });
}

/// inv(p) = the inverse of node p's 3 x 3 diagonal block of m (3 unknowns per node, pattern of
/// expandGraph(graph, 3)): the nodal block-Jacobi preconditioner of the stress block.
void invertNodalBlocks(const CsrMatrix<Memory> &m, const Kokkos::View<double *[9], Memory> &inv) {
  auto ro = m.rowOffsets;
  auto co = m.columns;
  auto va = m.values;
  Kokkos::parallel_for(
      "mixcon::nonlinear::invertNodalBlocks", Kokkos::RangePolicy<Exec>(0, inv.extent(0)),
      KOKKOS_LAMBDA(LocalIndex p) {
        double b[3][3] = {};
        for (int i = 0; i < 3; ++i)
          for (Offset k = ro(3 * p + i); k < ro(3 * p + i + 1); ++k) {
            const LocalIndex c = co(k);
            if (c / 3 == p)
              b[i][c % 3] = va(k);
          }
        const double c00 = b[1][1] * b[2][2] - b[1][2] * b[2][1];
        const double c01 = b[1][2] * b[2][0] - b[1][0] * b[2][2];
        const double c02 = b[1][0] * b[2][1] - b[1][1] * b[2][0];
        const double det = b[0][0] * c00 + b[0][1] * c01 + b[0][2] * c02;
        const double s = 1.0 / det;
        inv(p, 0) = c00 * s;
        inv(p, 1) = (b[0][2] * b[2][1] - b[0][1] * b[2][2]) * s;
        inv(p, 2) = (b[0][1] * b[1][2] - b[0][2] * b[1][1]) * s;
        inv(p, 3) = c01 * s;
        inv(p, 4) = (b[0][0] * b[2][2] - b[0][2] * b[2][0]) * s;
        inv(p, 5) = (b[0][2] * b[1][0] - b[0][0] * b[1][2]) * s;
        inv(p, 6) = c02 * s;
        inv(p, 7) = (b[0][1] * b[2][0] - b[0][0] * b[2][1]) * s;
        inv(p, 8) = (b[0][0] * b[1][1] - b[0][1] * b[1][0]) * s;
      });
}

/// y = blockdiag(inv) x, 3 x 3 blocks per node.
void applyNodalBlocks(const Kokkos::View<const double *[9], Memory> &inv, const ConstVec &x,
                      const Vec &y) {
  Kokkos::parallel_for(
      "mixcon::nonlinear::applyNodalBlocks", Kokkos::RangePolicy<Exec>(0, inv.extent(0)),
      KOKKOS_LAMBDA(LocalIndex p) {
        const double a = x(3 * p), b = x(3 * p + 1), c = x(3 * p + 2);
        for (int i = 0; i < 3; ++i)
          y(3 * p + i) = inv(p, 3 * i) * a + inv(p, 3 * i + 1) * b + inv(p, 3 * i + 2) * c;
      });
}

/// y = x / d, entry by entry (Jacobi).
void divide(const ConstVec &x, const ConstVec &d, const Vec &y) {
  Kokkos::parallel_for(
      "mixcon::nonlinear::divide", Kokkos::RangePolicy<Exec>(0, y.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) { y(i) = x(i) / d(i); });
}

/// out(k, i) = base(k, i) + x(stride k + i): node coordinates moved by the displacement
/// unknowns of x (out may be base).
void movedCoordinates(const Kokkos::View<double *[2], Memory> &base, const ConstVec &x, int stride,
                      const Kokkos::View<double *[2], Memory> &out) {
  Kokkos::parallel_for(
      "mixcon::nonlinear::movedCoordinates", Kokkos::RangePolicy<Exec>(0, out.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k) {
        for (int i = 0; i < 2; ++i)
          out(k, i) = base(k, i) + x(stride * k + i);
      });
}

/// The remaining prescribed change of every constrained unknown: t(stride k + c) =
/// lambda g(2 k + c) - u(2 k + c) where flags(stride k + c) != 0 (c < 2), 0 elsewhere.
void prescribedStep(const Kokkos::View<const int *, Memory> &flags, const ConstVec &g,
                    const ConstVec &u, double lambda, int stride, const Vec &t) {
  Kokkos::parallel_for(
      "mixcon::nonlinear::prescribedStep", Kokkos::RangePolicy<Exec>(0, t.extent(0)),
      KOKKOS_LAMBDA(LocalIndex i) {
        const LocalIndex j = 2 * (i / stride) + i % stride; // displacement dof when i % stride < 2
        t(i) = flags(i) ? lambda * g(j) - u(j) : 0.0;
      });
}

/// Solves the constrained tangent for the correction: rhs = -g on free rows; prescribed rows
/// reach `target` (the remaining prescribed change). A freshly assembled tangent is constrained
/// and handed to the solver; a reused one (modified Newton) keeps its factorization.
LinearSolveStats constrainedSolve(const CsrMatrix<Memory> &tangent, bool fresh,
                                  CsrMatrix<Memory> &work,
                                  const Kokkos::View<const int *, Memory> &flags, const ConstVec &g,
                                  const ConstVec &target, const Vec &rhs, const Vec &diag,
                                  LinearSolver &solver, const Vec &dx, double &setupSeconds) {
  axpby(-1.0, g, 0.0, rhs);
  if (fresh) {
    const auto start = std::chrono::steady_clock::now();
    if (work.numRows == 0)
      work = cloneValues(tangent);
    else
      Kokkos::deep_copy(work.values, tangent.values);
    applyDirichlet(Exec(), work, flags, target, rhs);
    constrainedDiagonal(Exec(), work, flags, diag);
    Exec().fence();
    solver.setup(work);
    setupSeconds += seconds(start);
  } else {
    Kokkos::parallel_for(
        "mixcon::nonlinear::constrainedRhs", Kokkos::RangePolicy<Exec>(0, g.extent(0)),
        KOKKOS_LAMBDA(LocalIndex i) {
          if (flags(i))
            rhs(i) = diag(i) * target(i);
        });
  }
  return solver.solve(rhs, dx);
}

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

} // namespace nonlinear_detail
using namespace nonlinear_detail;

const char *iterationMethodName(IterationMethod m) {
  switch (m) {
  case IterationMethod::ModifiedNewton:
    return "modified_newton";
  case IterationMethod::None:
    return "none";
  case IterationMethod::Newton:
  default:
    return "newton";
  }
}

// ---------------------------------------------------------------------------------------------
// NonlinearModel

void NonlinearModel::addFollowerPressure(const std::vector<BoundaryEdge> &edges, double pressure) {
  for (const auto &e : edges) {
    followerEdges_.push_back(e);
    followerPressure_.push_back(pressure);
  }
}

NonlinearModel::FollowerLoads NonlinearModel::followerLoads() const {
  FollowerLoads f{Kokkos::View<LocalIndex *[2], Memory>("mixcon::nonlinear::followerEdges",
                                                        followerEdges_.size()),
                  Kokkos::View<double *, Memory>("mixcon::nonlinear::followerPressure",
                                                 followerPressure_.size())};
  auto he = Kokkos::create_mirror_view(f.edges);
  auto hp = Kokkos::create_mirror_view(f.pressure);
  for (std::size_t k = 0; k < followerEdges_.size(); ++k) {
    he(k, 0) = followerEdges_[k].element;
    he(k, 1) = followerEdges_[k].edge;
    hp(k) = followerPressure_[k];
  }
  Kokkos::deep_copy(f.edges, he);
  Kokkos::deep_copy(f.pressure, hp);
  return f;
}

void NonlinearModel::setContact(RigidContact *contact) { contact_ = contact; }

double NonlinearModel::finishEvaluate(double lambda, bool tangent, LocalIndex inverted, double fint,
                                      const Kokkos::View<double *, Memory> &g, int stride,
                                      const Kokkos::View<const int *, Memory> &flags,
                                      const Kokkos::View<double *[2], Memory> &coordinates,
                                      const Kokkos::View<const double *, Memory> &x,
                                      std::chrono::steady_clock::time_point start) {
  // Contact detection at the positions coordinates + x, the friction forces of slip nodes (on
  // the body), and the relative residual over the free displacement unknowns.
  double free = 0.0;
  if (contact_) {
    contact_->detect(Kokkos::View<const double *[2], Memory>(coordinates), x, stride);
    subtractFrictionForces(g, stride, contact_->constraints().force);
    free = contactFreeResidualNorm(g, flags, stride);
  } else if (surface_) {
    // Node-to-segment contact: the residual the constrained system balances, T^T G, over the
    // unknowns held neither by Dirichlet conditions nor as contact slaves.
    const auto hf = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), flags);
    std::vector<int> fl(hf.data(), hf.data() + hf.extent(0)), held(2 * mesh_.numNodes(), 0);
    for (LocalIndex p = 0; p < mesh_.numNodes(); ++p)
      for (int i = 0; i < 2; ++i)
        held[2 * p + i] = fl[stride * p + i];
    surface_->setPrescribed(held);
    surface_->detect(Kokkos::View<const double *[2], Memory>(coordinates), x, stride);
    subtractFrictionForces(g, stride, surface_->frictionForces());
    MultiPointConstraints c;
    surfaceConstraints(stride, fl, c);
    std::vector<double> gh = toHost(g);
    condenseVector(c, gh);
    for (LocalIndex sl : c.slaves)
      fl[sl] = 1;
    double sum = 0.0;
    for (std::size_t i = 0; i < gh.size(); ++i)
      if (static_cast<int>(i % stride) < 2 && !fl[i])
        sum += gh[i] * gh[i];
    free = std::sqrt(sum);
  } else {
    free = strideNorm(g, stride, 0, 2, flags, 0);
  }
  double fext = std::abs(lambda) * strideNorm(load_, 1, 0, 1, {}, 0);
  if (contact_)
    for (const auto &d : contact_->drivenComponents())
      fext = std::hypot(fext, contact_->drivenForce(d)); // forces on driven obstacles
  const double r =
      relative(free, std::max({fint, fext, forceFloor(strideNorm(u_, 1, 0, 1, {}, 0))}));
  fresh_ = tangent;
  assemblySeconds_ += seconds(start);
  invertedElement_ = inverted;
  return inverted >= 0 ? std::numeric_limits<double>::infinity() : r;
}

void NonlinearModel::setStiffnessScale(
    const NodeGraph &graph, const Kokkos::View<int ***, Kokkos::LayoutRight, Memory> &map) {
  // RMS diagonal of K^L on the reference configuration, on the model's own pattern: the force a
  // unit displacement of one node produces.
  auto k = expandGraph<Memory>(graph, 2);
  dispatchElement(mesh_.elementType, [&](auto elem) {
    assembleLinearStiffness<decltype(elem)>(Exec(), data_, map, k);
  });
  Vec d("mixcon::nonlinear::stiffnessDiagonal", k.numRows);
  fieldDiagonal(k, 1, 0, 1, d, 1.0);
  stiffnessScale_ = strideNorm(d, 1, 0, 1, {}, 0) / std::sqrt(std::max<double>(1.0, k.numRows));
}

double NonlinearModel::forceFloor(double displacementNorm) const {
  // 1e-8 of the stiffness scale times ||u|| is round-off level for internal forces: the
  // reference left when a motion is (nearly) rigid and no force acts.
  return 1e-8 * stiffnessScale_ * displacementNorm;
}

void NonlinearMixedModel::setContact(RigidContact *contact) { contact_ = contact; }

std::vector<double> NonlinearMixedModel::contactStressHost() const { return toHost(stressOnly()); }

std::string NonlinearModel::invertedElementMessage() const {
  if (invertedElement_ < 0)
    return "no element is inverted";
  return "element " + std::to_string(mesh_.elementId(invertedElement_)) +
         " is inverted (non-positive Jacobian in the deformed configuration)";
}

LinearSolveStats NonlinearModel::solve(double loadFactor) {
  LoadStepper stepper(*this, NonlinearOptions{});
  const IncrementOutcome o = stepper.advance(loadFactor);
  LinearSolveStats s;
  s.converged = o.converged;
  s.iterations = o.linearIterations;
  s.relativeResidual = o.history.empty() ? o.initialResidual : o.history.back().residual;
  s.solveSeconds = o.solveSeconds;
  return s;
}

void NonlinearModel::gaussPointStressHost(std::vector<double> &coordinates,
                                          std::vector<double> &stress,
                                          int &pointsPerElement) const {
  std::vector<double> gradient, current;
  gaussPointFieldsHost(coordinates, stress, pointsPerElement, gradient, current);
}

void NonlinearModel::gaussPointFieldsHost(std::vector<double> &coordinates,
                                          std::vector<double> &stress, int &pointsPerElement,
                                          std::vector<double> &gradient,
                                          std::vector<double> &currentCoordinates) const {
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    const LocalIndex ne = mesh_.numElements();
    Kokkos::View<double **[2], Memory> xq("mixcon::nonlinear::qpCoordinates", ne, Elem::kNumQp);
    Kokkos::View<double **[2], Memory> xc("mixcon::nonlinear::qpCurrent", ne, Elem::kNumQp);
    Kokkos::View<double **[3], Memory> sq("mixcon::nonlinear::qpStress", ne, Elem::kNumQp);
    Kokkos::View<double **[4], Memory> gq("mixcon::nonlinear::qpGradient", ne, Elem::kNumQp);
    quadraturePointCoordinates<Elem>(Exec(), data_.mesh, xq);
    almansiGaussPointStress<Elem>(Exec(), data_, ConstVec(u_), sq, gq, xc, law_);
    if (small_) // linear law on the reference configuration
      gaussPointStress<Elem>(Exec(), data_, ConstVec(u_), sq);
    const auto assign = [](std::vector<double> &out, const auto &view) {
      auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view);
      out.assign(h.data(), h.data() + h.size());
    };
    pointsPerElement = Elem::kNumQp;
    assign(coordinates, xq);
    assign(stress, sq);
    assign(gradient, gq);
    assign(currentCoordinates, xc);
  });
}

// ---------------------------------------------------------------------------------------------
// NonlinearDisplacementModel

NonlinearDisplacementModel::~NonlinearDisplacementModel() = default;

void NonlinearDisplacementModel::setup(const LinearSolverOptions &options, MPI_Comm comm) {
  if (law_ == ElasticLaw::SaintVenantKirchhoff && tangentKind_ == TangentKind::Report)
    throw InputError("the report's tangent (K^L + K^sigma of the Almansi law) is not available "
                     "with the St. Venant-Kirchhoff law; use the exact tangent");
  const auto start = std::chrono::steady_clock::now();
  graph_ = buildNodeGraph(mesh_);
  tangent_ = expandGraph<Memory>(graph_, 2);
  map_ = elementScatterMap<Memory>(mesh_, graph_);
  setStiffnessScale(graph_, map_);
  constrained_ = CsrMatrix<Memory>{};
  commitStaged();
  follower_ = followerLoads();
  const LocalIndex n = dofs_.numOwned();
  g_ = Vec("mixcon::nonlinear::residual", n);
  committed_ = Vec("mixcon::nonlinear::committed", n);
  du_ = Vec("mixcon::nonlinear::correction", n);
  rhs_ = Vec("mixcon::nonlinear::rhs", n);
  target_ = Vec("mixcon::nonlinear::target", n);
  diag_ = Vec("mixcon::nonlinear::diagonal", n);
  Kokkos::deep_copy(committed_, u_);
  linearOptions_ = options;
  // The exact tangent of the Almansi law is not symmetric; the report's K^L + K^sigma is, but a
  // follower pressure's load stiffness is not.
  linearOptions_.symmetric = false;
  solver_ = makeLinearSolver(linearOptions_, dofs_, comm);
  assemblySeconds_ = seconds(start);
}

std::string NonlinearDisplacementModel::solverName() const {
  return solver_ ? solver_->name() : std::string("none");
}

void NonlinearDisplacementModel::setDisplacement(const std::vector<double> &u) { fromHost(u, u_); }

double NonlinearDisplacementModel::evaluate(double lambda, bool tangent) {
  const auto start = std::chrono::steady_clock::now();
  Kokkos::deep_copy(g_, 0.0);
  if (tangent)
    Kokkos::deep_copy(tangent_.values, 0.0);
  const CsrMatrix<Memory> none;
  const CsrMatrix<Memory> &a = tangent ? tangent_ : none;
  LocalIndex inverted = -1;
  double fint = 0.0;
  const bool report = tangent && tangentKind_ == TangentKind::Report;
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    if (small_) {
      if (linearStiffness_.numRows == 0) {
        linearStiffness_ = cloneValues(tangent_);
        Kokkos::deep_copy(linearStiffness_.values, 0.0);
        assembleLinearStiffness<Elem>(Exec(), data_, map_, linearStiffness_);
      }
      multiply(Exec(), linearStiffness_, ConstVec(u_), g_);
      if (tangent)
        Kokkos::deep_copy(tangent_.values, linearStiffness_.values);
    } else {
      inverted =
          law_ == ElasticLaw::SaintVenantKirchhoff
              ? assembleNonlinear<2, Elem>(
                    Exec(), data_.mesh, SvkKernel<Elem, Memory>{data_, ConstVec(u_)}, map_, a, g_)
              : assembleAlmansi<Elem>(Exec(), data_, ConstVec(u_), map_, report ? none : a, g_);
    }
    if (report && !small_)
      assembleReportTangent<Elem>();
    fint = strideNorm(g_, 1, 0, 1, {}, 0);
    addDisplacementVector(g_, 2, -lambda, load_);
    if (follower_.edges.extent(0) > 0)
      assembleFollowerPressure<2, Elem>(Exec(), data_.mesh, ConstVec(u_), follower_.edges,
                                        ConstVec(follower_.pressure), lambda, data_.thickness, map_,
                                        a, g_);
  });
  return finishEvaluate(lambda, tangent, inverted, fint, g_, 2, isConstrained_,
                        data_.mesh.coordinates, u_, start);
}

template <class Elem> void NonlinearDisplacementModel::assembleReportTangent() {
  // K^L + K^sigma of Eq. (24)-(25) on the current configuration x = X + u, with tau the Cauchy
  // stress of the Almansi law at the quadrature points.
  ElementData<Memory> current = data_;
  current.mesh.coordinates =
      Kokkos::View<double *[2], Memory>("mixcon::nonlinear::currentCoordinates", mesh_.numNodes());
  movedCoordinates(data_.mesh.coordinates, u_, 2, current.mesh.coordinates);
  const LocalIndex ne = mesh_.numElements();
  Kokkos::View<double **[3], Memory> tau("mixcon::nonlinear::qpCauchy", ne, Elem::kNumQp);
  Kokkos::View<double **[4], Memory> grad("mixcon::nonlinear::qpGradient", ne, Elem::kNumQp);
  Kokkos::View<double **[2], Memory> xq("mixcon::nonlinear::qpCurrent", ne, Elem::kNumQp);
  almansiGaussPointStress<Elem>(Exec(), data_, ConstVec(u_), tau, grad, xq);
  assembleLinearStiffness<Elem>(Exec(), current, map_, tangent_);
  assembleGeometricStiffness<Elem>(
      Exec(), current, GaussPointStressField<Memory>{Kokkos::View<const double **[3], Memory>(tau)},
      map_, tangent_);
}

double NonlinearModel::contactFreeResidualNorm(const Kokkos::View<const double *, Memory> &gv,
                                               const Kokkos::View<const int *, Memory> &fv,
                                               int stride) const {
  // ||G|| over the displacement unknowns held neither by Dirichlet nor by contact conditions;
  // at a node held normally on an obstacle only the tangential component counts (slip).
  const auto g = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), gv);
  const auto flags = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fv);
  const auto &c = contact_->constraints();
  double s = 0.0;
  for (LocalIndex p = 0; p < mesh_.numNodes(); ++p) {
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
  for (const auto &d : contact_->drivenComponents()) {
    const double r =
        contact_->drivenForce(d) - obstacleForce(c, g.data(), stride, flags.data(),
                                                 mesh_.numNodes(), d.obstacle, d.direction, true);
    s += r * r;
  }
  return std::sqrt(s);
}

LinearSolveStats NonlinearModel::correctWithContact(
    double lambda, int stride, const CsrMatrix<Memory> &tangent, CsrMatrix<Memory> &work,
    const Kokkos::View<const int *, Memory> &fv, const Kokkos::View<const double *, Memory> &g,
    const Kokkos::View<double *, Memory> &rhs, const Kokkos::View<double *, Memory> &target,
    LinearSolver &solver, const Kokkos::View<double *, Memory> &dx) {
  // The system in local (n, t) frames at closed contact nodes: R^T K R dx~ = -R^T G, the normal
  // (and in stick the tangential) components prescribed, then dx = R dx~ (only the displacement
  // pair of a node rotates; `stride` unknowns per node). A contact node that also carries a
  // Dirichlet condition keeps its global frame: its free component then takes the normal
  // condition when the normal is along that axis (symmetry lines).
  const auto &c = contact_->constraints();
  const LocalIndex nn = mesh_.numNodes();
  const auto dflags = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fv);
  std::vector<int> flags(dflags.data(), dflags.data() + dflags.extent(0));
  const auto presc = toHost(prescribed_);
  const auto u = toHost(u_);
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
        throw InputError("node " + std::to_string(mesh_.nodeId(p)) +
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
  const auto &driven = contact_->drivenComponents();
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
  auto hf = Kokkos::create_mirror_view(df);
  auto hfr = Kokkos::create_mirror_view(dfr);
  auto hn = Kokkos::create_mirror_view(dn);
  auto ht = Kokkos::create_mirror_view(target);
  for (std::size_t i = 0; i < flags.size(); ++i) {
    hf(i) = flags[i];
    ht(i) = step[i];
  }
  for (LocalIndex p = 0; p < nn; ++p) {
    hfr(p) = framed[p];
    hn(p, 0) = c.normal[2 * p];
    hn(p, 1) = c.normal[2 * p + 1];
  }
  Kokkos::deep_copy(df, hf);
  Kokkos::deep_copy(dfr, hfr);
  Kokkos::deep_copy(dn, hn);
  Kokkos::deep_copy(target, ht);
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
  solverSetupSeconds_ += seconds(start);
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
    auto hu = Kokkos::create_mirror_view(unit);
    for (LocalIndex i = 0; i < n; ++i)
      hu(i) = unitStep[j][i];
    Kokkos::deep_copy(unit, hu);
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
  const auto base = toHost(product);
  Eigen::MatrixXd a(nd, nd);
  Eigen::VectorXd b(nd);
  for (std::size_t i = 0; i < nd; ++i)
    b(i) = contact_->drivenForce(driven[i]) - obstacleForce(c, base.data(), stride, dflags.data(),
                                                            nn, driven[i].obstacle,
                                                            driven[i].direction, true);
  for (std::size_t j = 0; j < nd; ++j) {
    multiply(Exec(), tangent, ConstVec(response[j]), product);
    const auto y = toHost(product);
    for (std::size_t i = 0; i < nd; ++i)
      a(i, j) = obstacleForce(c, y.data(), stride, dflags.data(), nn, driven[i].obstacle,
                              driven[i].direction, false);
  }
  Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  lu.setThreshold(1e-10);
  if (!lu.isInvertible()) {
    std::ostringstream m;
    m << "force-driven " << contact_->obstacleLabel(driven[0].obstacle)
      << " has no stiffness along a driven direction: its closed nodes cannot carry the force "
         "there (too few contact nodes, or frictionless contact loaded tangentially)";
    throw std::runtime_error(m.str());
  }
  const Eigen::VectorXd dc = lu.solve(b);
  for (std::size_t j = 0; j < nd; ++j)
    axpby(dc(j), response[j], 1.0, dx);
  std::vector<double> motion(2 * contact_->specs().size(), 0.0);
  for (std::size_t j = 0; j < nd; ++j)
    motion[2 * driven[j].obstacle + driven[j].direction] += dc(j);
  for (std::size_t o = 0; o < contact_->specs().size(); ++o)
    if (motion[2 * o] != 0.0 || motion[2 * o + 1] != 0.0)
      contact_->moveObstacle(static_cast<int>(o), &motion[2 * o]);
  return s;
}

ContactIterations *NonlinearModel::contactIterations() const {
  if (contact_)
    return contact_;
  return surface_;
}

bool NonlinearModel::surfaceClosed() const { return surface_ && !surface_->closedPairs().empty(); }

void NonlinearModel::surfaceConstraints(int stride, const std::vector<int> &flags,
                                        MultiPointConstraints &c) const {
  // Per closed contactor p on target nodes i with weights w_i: in its local frame (n, t) the
  // normal displacement is sum_i w_i n . u_i - gap (slave), in stick the tangential one
  // sum_j w_j t . u_j + tangentStep at the anchor (slave), in slip the tangential one free:
  // u_p = n (sum_i w_i n . u_i + step_n) + t (...). A contactor with one component held by a
  // Dirichlet condition (a symmetry line) takes the normal condition on its other component.
  c.clear();
  for (const SurfacePair &q : surface_->closedPairs()) {
    const LocalIndex i0 = stride * q.node;
    const bool fx = flags[i0] != 0, fy = flags[i0 + 1] != 0;
    if (fx && fy)
      continue;
    std::vector<std::pair<LocalIndex, double>> normalRow, tangentRow;
    for (int a = 0; a < q.normalCount; ++a)
      for (int d = 0; d < 2; ++d)
        normalRow.emplace_back(stride * q.normalNodes[a] + d, q.normalWeights[a] * q.normal[d]);
    if (fx || fy) {
      const int fixed = fx ? 0 : 1, other = 1 - fixed;
      const double nf = q.normal[fixed], no = q.normal[other];
      if (std::abs(no) < 0.7)
        throw InputError("node " + std::to_string(mesh_.nodeId(q.node)) +
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

LinearSolveStats NonlinearModel::correctWithSurfaceContact(
    double lambda, int stride, const CsrMatrix<Memory> &tangent,
    const Kokkos::View<const int *, Memory> &fv, const Kokkos::View<const double *, Memory> &g,
    const Kokkos::View<double *, Memory> &rhs, const Kokkos::View<double *, Memory> &target,
    LinearSolver &solver, const Kokkos::View<double *, Memory> &dx) {
  // The contact constraints eliminated (solver/MultiPointConstraints.hpp): (T^T K T + D) y =
  // T^T (-G - K s), the Dirichlet conditions applied to that system as usual, x = T y + s.
  const auto start = std::chrono::steady_clock::now();
  prescribedStep(fv, prescribed_, u_, lambda, stride, target);
  const auto hf = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fv);
  std::vector<int> flags(hf.data(), hf.data() + hf.extent(0));
  MultiPointConstraints c;
  surfaceConstraints(stride, flags, c);
  axpby(-1.0, g, 0.0, rhs);
  surfaceWork_ = eliminateConstraints(tangent, c, std::max(stiffnessScale_, 1e-300), rhs);
  Kokkos::View<int *, Memory> df("mixcon::nonlinear::surfaceFlags", flags.size());
  for (LocalIndex sl : c.slaves)
    flags[sl] = 1;
  auto hdf = Kokkos::create_mirror_view(df);
  for (std::size_t i = 0; i < flags.size(); ++i)
    hdf(i) = flags[i];
  Kokkos::deep_copy(df, hdf);
  applyDirichlet(Exec(), surfaceWork_, Kokkos::View<const int *, Memory>(df), ConstVec(target),
                 rhs);
  Exec().fence();
  solver.setup(surfaceWork_);
  solverSetupSeconds_ += seconds(start);
  LinearSolveStats s = solver.solve(rhs, dx);
  expandConstrained(c, dx);
  return s;
}

bool NonlinearModel::contactFramed() const {
  if (!contact_)
    return false;
  for (int f : contact_->constraints().framed)
    if (f)
      return true;
  return false;
}

void NonlinearModel::subtractFrictionForces(const Kokkos::View<double *, Memory> &g, int stride,
                                            const std::vector<double> &f) {
  Vec fd("mixcon::nonlinear::friction", f.size());
  auto h = Kokkos::create_mirror_view(fd);
  for (std::size_t i = 0; i < f.size(); ++i)
    h(i) = f[i];
  Kokkos::deep_copy(fd, h);
  Vec spread("mixcon::nonlinear::frictionSpread", g.extent(0));
  scatter<double>(fd, stride, 0, 2, spread, true);
  axpby(-1.0, spread, 1.0, g);
}

LinearSolveStats NonlinearDisplacementModel::correct(double lambda, double &increment) {
  const LinearSolveStats s =
      surfaceClosed()   ? correctWithSurfaceContact(lambda, 2, tangent_, isConstrained_, g_, rhs_,
                                                    target_, *solver_, du_)
      : contactFramed() ? correctWithContact(lambda, 2, tangent_, constrained_, isConstrained_, g_,
                                             rhs_, target_, *solver_, du_)
                        : (prescribedStep(isConstrained_, prescribed_, u_, lambda, 2, target_),
                           constrainedSolve(tangent_, fresh_ || contactIterations() != nullptr,
                                            constrained_, isConstrained_, g_, target_, rhs_, diag_,
                                            *solver_, du_, solverSetupSeconds_));
  fresh_ = false;
  axpby(1.0, du_, 1.0, u_);
  increment = relative(strideNorm(du_, 1, 0, 1, {}, 0), strideNorm(u_, 1, 0, 1, {}, 0));
  return s;
}

void NonlinearDisplacementModel::commit() { Kokkos::deep_copy(committed_, u_); }
void NonlinearDisplacementModel::rollback() { Kokkos::deep_copy(u_, committed_); }

namespace {
/// Refuses a saved state of another formulation (0 displacement, 1 and 2 the mixed model's
/// forms Current and Incremental), naming both.
void checkFormulation(const Checkpoint &state, double expected) {
  const auto name = [](double f) -> std::string {
    return f == 0.0   ? "the displacement model"
           : f == 1.0 ? "the mixed model (form current)"
           : f == 2.0 ? "the mixed model (form incremental)"
                      : "an unknown formulation";
  };
  const double saved = state.getScalar("model/formulation");
  if (saved != expected)
    throw std::runtime_error("the saved state is of " + name(saved) + ", this problem uses " +
                             name(expected));
}
} // namespace

void NonlinearDisplacementModel::saveCommitted(Checkpoint &state) const {
  state.putScalar("model/formulation", 0.0);
  state.put("model/displacement", toHost(committed_));
}

void NonlinearDisplacementModel::restoreCommitted(const Checkpoint &state) {
  checkFormulation(state, 0.0);
  fromHost(state.get("model/displacement", committed_.extent(0)), committed_);
  rollback();
}

std::vector<double> NonlinearDisplacementModel::nodalStressHost() const {
  Kokkos::View<double *[3], Memory> s("mixcon::nonlinear::nodalStress", mesh_.numNodes());
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    if (small_)
      recoverNodalStress<Elem>(Exec(), data_.mesh, LinearPointStress<Elem, Memory>{data_, u_}, s);
    else
      recoverNodalStress<Elem>(Exec(), data_.mesh,
                               AlmansiPointStress<Elem, Memory>{data_, u_, law_}, s);
  });
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s);
  return std::vector<double>(h.data(), h.data() + h.size());
}

std::vector<double> NonlinearDisplacementModel::reactionHost(double) const { return toHost(g_); }

// ---------------------------------------------------------------------------------------------
// NonlinearMixedModel

NonlinearMixedModel::NonlinearMixedModel(const Mesh &mesh, const std::vector<int> &elementMaterial,
                                         const std::vector<PlaneMatrix> &stiffness,
                                         double thickness)
    : NonlinearModel(mesh, elementMaterial, stiffness, thickness) {
  checkMixedPairing(mesh.elementType, mesh.elementType);
  reference_ = withCompliance(data_, stiffness);
  for (const auto &c : stiffness)
    for (int i = 0; i < 3; ++i)
      maxModulus_ = std::max(maxModulus_, std::abs(c.m[i][i]));
  current_ = reference_;
  current_.mesh.coordinates =
      Kokkos::View<double *[2], Memory>("mixcon::nonlinear::configuration", mesh.numNodes());
  Kokkos::deep_copy(current_.mesh.coordinates, data_.mesh.coordinates);
  const LocalIndex nn = mesh.numNodes();
  tau_ = Vec("mixcon::nonlinear::cauchyStress", 3 * nn);
  x_ = Vec("mixcon::nonlinear::increment", 5 * nn);
}

NonlinearMixedModel::~NonlinearMixedModel() = default;

void NonlinearMixedModel::setup(const LinearSolverOptions &options, MPI_Comm comm) {
  if ((contact_ || surface_) && options.type != LinearSolverType::Direct)
    throw InputError("contact with the mixed model needs solver: {type: direct} in this version");
  const auto start = std::chrono::steady_clock::now();
  graph_ = buildNodeGraph(mesh_);
  tangent_ = expandGraph<Memory>(graph_, 5);
  map_ = elementScatterMap<Memory>(mesh_, graph_);
  setStiffnessScale(graph_, map_);
  commitStaged();
  follower_ = followerLoads();
  const LocalIndex nn = mesh_.numNodes();
  g_ = Vec("mixcon::nonlinear::residual", 5 * nn);
  committed_ = Vec("mixcon::nonlinear::committed", 2 * nn);
  dx_ = Vec("mixcon::nonlinear::correction", 5 * nn);
  rhs_ = Vec("mixcon::nonlinear::rhs", 5 * nn);
  target_ = Vec("mixcon::nonlinear::target", 5 * nn);
  diag_ = Vec("mixcon::nonlinear::diagonal", 5 * nn);
  work_ = CsrMatrix<Memory>{};
  constrained5_ = Kokkos::View<int *, Memory>("mixcon::nonlinear::constrained5", 5 * nn);
  scatter<int>(isConstrained_, 5, 0, 2, constrained5_, true);
  Kokkos::deep_copy(committed_, u_);
  committedState_ = Vec("mixcon::nonlinear::committedState", 5 * nn);
  Kokkos::deep_copy(committedState_, x_);
  linearOptions_ = options;
  if (options.type == LinearSolverType::Direct) {
    linearOptions_.symmetric = false; // indefinite (Incremental) or nonsymmetric (Current): LU
    solver_ = makeLinearSolver(linearOptions_, DofMap::serial(nn, 5), comm);
  } else {
    // Schur complement on the displacements, BoomerAMG on K^L of the current configuration.
    precMatrix_ = expandGraph<Memory>(graph_, 2);
    precDiag_ = Vec("mixcon::nonlinear::precDiagonal", 2 * nn);
    stressBlock_ = expandGraph<Memory>(graph_, 3);
    stressBlockInverse_ = Kokkos::View<double *[9], Memory>("mixcon::nonlinear::blockInverse", nn);
    LinearSolverOptions amg = options;
    amg.symmetric = true;
    solver_ = makeLinearSolver(amg, dofs_, comm);
  }
  assemblySeconds_ = seconds(start);
}

std::string NonlinearMixedModel::solverName() const {
  std::ostringstream o;
  o << "mixed " << (form_ == MixedForm::Current ? "current-configuration" : "incremental")
    << " form, a = " << stabilization_ << ", ";
  if (linearOptions_.type == LinearSolverType::Direct)
    o << (solver_ ? solver_->name() : std::string("none"));
  else if (mixedOptions_.method == MixedNewtonSolver::Schur)
    o << "flexible GMRES on the Schur complement (inner block-Jacobi CG on the stress block), one "
         "BoomerAMG V-cycle on K^L of the current configuration";
  else
    o << "flexible GMRES(" << mixedOptions_.restart
      << ") on the Jacobian, block-triangular preconditioner: one BoomerAMG V-cycle on K^L of the "
         "current configuration, block-Jacobi CG on the stress block to "
      << mixedOptions_.preconditionerTolerance;
  return o.str();
}

void NonlinearMixedModel::setPrestress(const std::vector<double> &tau) { fromHost(tau, tau_); }

void NonlinearMixedModel::setIncrement(const std::vector<double> &x) {
  fromHost(x, x_);
  updateTotalDisplacement();
}

void NonlinearMixedModel::updateTotalDisplacement() {
  gather(x_, 5, 0, 2, u_);
  if (form_ == MixedForm::Incremental && committed_.extent(0) == u_.extent(0))
    axpby(1.0, committed_, 1.0, u_);
}

double NonlinearMixedModel::evaluate(double lambda, bool tangent) {
  const auto start = std::chrono::steady_clock::now();
  Kokkos::deep_copy(g_, 0.0);
  if (tangent)
    Kokkos::deep_copy(tangent_.values, 0.0);
  const CsrMatrix<Memory> none;
  const CsrMatrix<Memory> &a = tangent ? tangent_ : none;
  LocalIndex inverted = -1;
  double fint = 0.0;
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    const bool current = form_ == MixedForm::Current;
    if (current)
      inverted =
          assembleMixedCurrent<Elem>(Exec(), reference_, ConstVec(x_), stabilization_, map_, a, g_);
    else
      inverted = assembleMixedIncrement<Elem>(Exec(), current_, ConstVec(tau_), ConstVec(x_),
                                              stabilization_, map_, a, g_);
    fint = strideNorm(g_, 5, 0, 2, {}, 0);
    addDisplacementVector(g_, 5, -lambda, load_);
    if (follower_.edges.extent(0) > 0)
      assembleFollowerPressure<5, Elem>(Exec(), current ? reference_.mesh : current_.mesh,
                                        ConstVec(x_), follower_.edges, ConstVec(follower_.pressure),
                                        lambda, data_.thickness, map_, a, g_);
  });
  return finishEvaluate(lambda, tangent, inverted, fint, g_, 5, constrained5_,
                        form_ == MixedForm::Current ? reference_.mesh.coordinates
                                                    : current_.mesh.coordinates,
                        x_, start);
}

LinearSolveStats NonlinearMixedModel::correct(double lambda, double &increment) {
  prescribedStep(constrained5_, prescribed_, u_, lambda, 5, target_);
  const LinearSolveStats s =
      surfaceClosed()   ? correctWithSurfaceContact(lambda, 5, tangent_, constrained5_, g_, rhs_,
                                                    target_, *solver_, dx_)
      : contactFramed() ? correctWithContact(lambda, 5, tangent_, work_, constrained5_, g_, rhs_,
                                             target_, *solver_, dx_)
      : linearOptions_.type == LinearSolverType::Direct
          ? constrainedSolve(tangent_, fresh_ || contactIterations() != nullptr, work_,
                             constrained5_, g_, target_, rhs_, diag_, *solver_, dx_,
                             solverSetupSeconds_)
      : mixedOptions_.method == MixedNewtonSolver::Schur ? solveSchur()
                                                         : solveBlockTriangular();
  fresh_ = false;
  axpby(1.0, dx_, 1.0, x_);
  updateTotalDisplacement();
  const double du = relative(strideNorm(dx_, 5, 0, 2, {}, 0), strideNorm(u_, 1, 0, 1, {}, 0));
  // Stresses below 1e-8 of the largest modulus count as zero (a rigid motion has none).
  const double stressFloor = 1e-8 * maxModulus_ * std::sqrt(static_cast<double>(mesh_.numNodes()));
  const double ds = relative(strideNorm(dx_, 5, 2, 3, {}, 0),
                             std::max(strideNorm(stressOnly(), 1, 0, 1, {}, 0), stressFloor));
  increment = std::max(du, ds);
  return s;
}

void NonlinearMixedModel::setupSchurPreconditioner() {
  // K^L on the current configuration (c1 + increment, or X + total displacement), constrained;
  // one BoomerAMG V-cycle on it preconditions the Schur complement.
  const auto start = std::chrono::steady_clock::now();
  const bool current = form_ == MixedForm::Current;
  ElementData<Memory> d = current ? static_cast<ElementData<Memory>>(reference_)
                                  : static_cast<ElementData<Memory>>(current_);
  const auto base = d.mesh.coordinates;
  d.mesh.coordinates =
      Kokkos::View<double *[2], Memory>("mixcon::nonlinear::precCoordinates", mesh_.numNodes());
  movedCoordinates(base, x_, 5, d.mesh.coordinates);
  Kokkos::deep_copy(precMatrix_.values, 0.0);
  dispatchElement(mesh_.elementType, [&](auto elem) {
    assembleLinearStiffness<decltype(elem)>(Exec(), d, map_, precMatrix_);
  });
  Vec zero("mixcon::nonlinear::zero", precDiag_.extent(0)),
      scratch("mixcon::nonlinear::scratch", precDiag_.extent(0));
  applyDirichlet(Exec(), precMatrix_, Kokkos::View<const int *, Memory>(isConstrained_),
                 ConstVec(zero), scratch);
  constrainedDiagonal(Exec(), precMatrix_, Kokkos::View<const int *, Memory>(isConstrained_),
                      precDiag_);
  // The stress block M = -J_tau,tau and its nodal 3 x 3 inverses for the inner CG.
  extractFieldBlock(tangent_, 5, 2, 3, 2, 3, stressBlock_, -1.0);
  invertNodalBlocks(stressBlock_, stressBlockInverse_);
  Exec().fence();
  solver_->setup(precMatrix_);
  solverSetupSeconds_ += seconds(start);
}

long NonlinearMixedModel::solveStressBlock(const ConstVec &w, const Vec &z, double tolerance) {
  // M z = w with M = -J_tau,tau, extracted from J once per tangent (setupSchurPreconditioner;
  // a product with it reads 9/25 of J), CG preconditioned by the inverses of M's 3 x 3 nodal
  // blocks (the stress components coupled at a node: anisotropic compliances).
  const LinearMap apply = [&](const ConstDeviceVector &a, const DeviceVector &y) {
    multiply(Exec(), stressBlock_, a, y);
  };
  const LinearMap jacobi = [&](const ConstDeviceVector &a, const DeviceVector &y) {
    applyNodalBlocks(stressBlockInverse_, a, y);
  };
  KrylovOptions o;
  o.tolerance = tolerance;
  o.maxIterations = 2000;
  Kokkos::deep_copy(z, 0.0);
  const KrylovStats st = krylovSolve(o, apply, jacobi, w, z, &stressWork_);
  if (!st.converged)
    throw std::runtime_error("nonlinear mixed model: the CG on the stress block did not converge "
                             "(relative residual " +
                             std::to_string(st.relativeResidual) + ")");
  return st.iterations;
}

LinearSolveStats NonlinearMixedModel::solveSchur() {
  // J [du; dtau] = -G with J = [A B; C -M]: dtau = M^-1 (C du + G_S) and
  // (A + B M^-1 C) du = -G_u - B M^-1 G_S, prescribed du applied as P S P + D_c.
  const auto start = std::chrono::steady_clock::now();
  if (fresh_)
    setupSchurPreconditioner();
  const LocalIndex nn = mesh_.numNodes();
  Vec in5("mixcon::nonlinear::in5", 5 * nn), w("mixcon::nonlinear::w", 3 * nn),
      z("mixcon::nonlinear::z", 3 * nn), masked("mixcon::nonlinear::masked", 2 * nn);
  const auto flags = Kokkos::View<const int *, Memory>(isConstrained_);
  // Inner solves two orders tighter than the outer tolerance, so the outer Krylov sees a fixed
  // operator to its own accuracy.
  const double innerTol = std::clamp(1e-2 * linearOptions_.tolerance, 1e-14, 1e-8);
  long inner = 0;
  // y = (A + B M^-1 C) v for a displacement vector v (2 per node).
  const auto schur = [&](const ConstDeviceVector &v, const DeviceVector &y) {
    scatter<double>(v, 5, 0, 2, in5, true);
    multiplyFieldRows(tangent_, 5, 2, 3, ConstVec(in5), w); // tau rows: C v
    inner += solveStressBlock(w, z, innerTol);
    scatter<double>(z, 5, 2, 3, in5, false);
    multiplyFieldRows(tangent_, 5, 0, 2, ConstVec(in5), y); // u rows: A v + B z
  };
  const LinearMap constrainedSchur = [&](const ConstDeviceVector &v, const DeviceVector &y) {
    maskConstrained(Exec(), flags, v, masked);
    schur(ConstVec(masked), y);
    finishConstrained(Exec(), flags, ConstVec(precDiag_), v, y);
  };
  const LinearMap amg = [&](const ConstDeviceVector &r, const DeviceVector &y) {
    solver_->precondition(r, y);
  };
  // Right-hand side: f = -G_u - B M^-1 G_S, then b = P (f - S g) + D_c g.
  Vec mgs("mixcon::nonlinear::mgs", 3 * nn), f("mixcon::nonlinear::schurRhs", 2 * nn),
      gc("mixcon::nonlinear::prescribedStep", 2 * nn), sg("mixcon::nonlinear::schurG", 2 * nn),
      b("mixcon::nonlinear::schurB", 2 * nn), du("mixcon::nonlinear::du", 2 * nn);
  gather(g_, 5, 2, 3, w);
  inner += solveStressBlock(w, mgs, innerTol);
  scatter<double>(mgs, 5, 2, 3, in5, true);
  multiplyFieldRows(tangent_, 5, 0, 2, ConstVec(in5), f); // u rows: B M^-1 G_S
  gather(g_, 5, 0, 2, sg);
  axpby(-1.0, sg, -1.0, f);
  gather(target_, 5, 0, 2, gc);
  schur(ConstVec(gc), sg);
  constrainedRhs(Exec(), flags, ConstVec(precDiag_), ConstVec(f), ConstVec(gc), ConstVec(sg), b);
  KrylovOptions ko;
  ko.method = KrylovMethod::Gmres;
  ko.tolerance = linearOptions_.tolerance;
  ko.maxIterations = linearOptions_.maxIterations;
  const KrylovStats ks = krylovSolve(ko, constrainedSchur, amg, ConstVec(b), du);
  // dtau = M^-1 (C du + G_S).
  scatter<double>(du, 5, 0, 2, in5, true);
  multiplyFieldRows(tangent_, 5, 2, 3, ConstVec(in5), w);
  gather(g_, 5, 2, 3, mgs);
  axpby(1.0, mgs, 1.0, w);
  inner += solveStressBlock(w, z, innerTol);
  scatter<double>(du, 5, 0, 2, dx_, true);
  scatter<double>(z, 5, 2, 3, dx_, false);
  innerIterations_ = inner;
  LinearSolveStats s;
  s.iterations = ks.iterations;
  s.relativeResidual = ks.relativeResidual;
  s.converged = ks.converged;
  s.solveSeconds = seconds(start);
  return s;
}

LinearSolveStats NonlinearMixedModel::solveBlockTriangular() {
  // Flexible GMRES on the whole Jacobian J = [A B; C -M] (prescribed du as P J P + D_c), right
  // preconditioned by the block lower-triangular P = [S~ 0; C -M~]: S~^-1 one BoomerAMG V-cycle
  // on K^L of the current configuration (as for the Schur complement A + B M^-1 C), M~^-1 a
  // loose block-Jacobi CG on M. With M~ = M, J P^-1 = [S S~^-1, -B M^-1; 0, I] and the
  // iterations are those of the Schur solve; a loose M~ costs a few more outer iterations but
  // no tight inner solve per product. The stress rows are scaled by s = sqrt(rms diag K^L /
  // rms diag M), which balances the two off-diagonal blocks of J P^-1 (s (I - M M~^-1) C S~^-1
  // against B M^-1 / s): with |diag K^L| / |diag M| itself the residual of the loose M~ swamped
  // the iteration (no convergence in 1000 iterations).
  const auto start = std::chrono::steady_clock::now();
  const LocalIndex nn = mesh_.numNodes();
  if (fresh_) {
    setupSchurPreconditioner();
    Vec da("mixcon::nonlinear::diagA", 2 * nn), dm("mixcon::nonlinear::diagM", 3 * nn);
    fieldDiagonal(precMatrix_, 1, 0, 1, da, 1.0); // K^L: A alone is 0 at a = 0 without stress
    fieldDiagonal(tangent_, 5, 2, 3, dm, -1.0);
    const double na = std::sqrt(dot(da, da)), nm = std::sqrt(dot(dm, dm));
    stressRowScale_ = nm > 0.0 ? std::sqrt(na / nm * std::sqrt(3.0 / 2.0)) : 1.0;
    // C = J_tau,u on its own (6/25 of J's entries; the tau rows of J hold 15/25).
    if (couplingBlock_.numRows == 0) {
      couplingBlock_ = expandGraph<Memory>(graph_, 3, 2);
      precDiag5_ = Vec("mixcon::nonlinear::precDiagonal5", 5 * nn);
    }
    scatter<double>(ConstVec(precDiag_), 5, 0, 2, precDiag5_, true);
    extractFieldBlock(tangent_, 5, 2, 3, 0, 2, couplingBlock_, 1.0);
  }
  const double scale = stressRowScale_;
  const auto work = [](const char *label, std::size_t n) {
    return Vec(Kokkos::view_alloc(Kokkos::WithoutInitializing, std::string(label)), n);
  };
  // Work vectors, each fully written before it is read.
  Vec masked = work("mixcon::nonlinear::masked5", 5 * nn),
      r2 = work("mixcon::nonlinear::r2", 2 * nn), y2 = work("mixcon::nonlinear::y2", 2 * nn),
      w = work("mixcon::nonlinear::w", 3 * nn), t = work("mixcon::nonlinear::t", 3 * nn),
      z = work("mixcon::nonlinear::z", 3 * nn);
  const auto flags = Kokkos::View<const int *, Memory>(constrained5_);
  const auto flags2 = Kokkos::View<const int *, Memory>(isConstrained_);
  const auto diag = ConstVec(precDiag5_);
  // y = D (P J P + D_c) v, D scaling the stress rows.
  const LinearMap op = [&](const ConstDeviceVector &v, const DeviceVector &y) {
    maskConstrained(Exec(), flags, v, masked);
    multiply(Exec(), tangent_, ConstVec(masked), y);
    finishConstrained(Exec(), flags, diag, v, y);
    scaleField(y, 5, 2, 3, scale);
  };
  long inner = 0;
  const double precTol = mixedOptions_.preconditionerTolerance;
  // y = P^-1 D^-1 r: y_u = S~^-1 r_u, y_tau = M~^-1 (C P y_u - r_tau / s).
  const LinearMap prec = [&](const ConstDeviceVector &r, const DeviceVector &y) {
    gather(r, 5, 0, 2, r2);
    solver_->precondition(r2, y2);
    scatter<double>(y2, 5, 0, 2, y, true);
    maskConstrained(Exec(), flags2, ConstVec(y2), r2);
    multiply(Exec(), couplingBlock_, ConstVec(r2), w);
    gather(r, 5, 2, 3, t, 1.0 / scale);
    axpby(-1.0, t, 1.0, w);
    inner += solveStressBlock(w, z, precTol);
    scatter<double>(z, 5, 2, 3, y, false);
  };
  // b = D (P (-G - J g) + D_c g), g the remaining prescribed step.
  Vec f = work("mixcon::nonlinear::negativeResidual", 5 * nn),
      jg = work("mixcon::nonlinear::jg", 5 * nn), b = work("mixcon::nonlinear::rhs5", 5 * nn);
  axpby(-1.0, g_, 0.0, f);
  multiply(Exec(), tangent_, ConstVec(target_), jg);
  constrainedRhs(Exec(), flags, diag, ConstVec(f), ConstVec(target_), ConstVec(jg), b);
  scaleField(b, 5, 2, 3, scale);
  KrylovOptions ko;
  ko.method = KrylovMethod::Gmres;
  ko.tolerance = linearOptions_.tolerance;
  ko.maxIterations = linearOptions_.maxIterations;
  ko.restart = mixedOptions_.restart;
  Kokkos::deep_copy(dx_, 0.0);
  const KrylovStats ks = krylovSolve(ko, op, prec, ConstVec(b), dx_, &outerWork_);
  innerIterations_ = inner;
  LinearSolveStats s;
  s.iterations = ks.iterations;
  s.relativeResidual = ks.relativeResidual;
  s.converged = ks.converged;
  s.solveSeconds = seconds(start);
  return s;
}

void NonlinearMixedModel::commit() {
  if (form_ == MixedForm::Current) {
    Kokkos::deep_copy(committedState_, x_);
    return;
  }
  Vec load;
  if (stressUpdate_ == StressUpdate::Projected) {
    load = Vec("mixcon::nonlinear::projectionLoad", tau_.extent(0));
    dispatchElement(mesh_.elementType, [&](auto elem) {
      using Elem = decltype(elem);
      pushForwardProjectionLoad<Elem>(Exec(), current_, ConstVec(tau_), ConstVec(x_), load);
    });
  } else {
    dispatchElement(mesh_.elementType, [&](auto elem) {
      using Elem = decltype(elem);
      pushForwardNodalStress<Elem>(Exec(), current_.mesh, ConstVec(x_), tau_);
    });
  }
  movedCoordinates(current_.mesh.coordinates, x_, 5, current_.mesh.coordinates);
  Vec increment("mixcon::nonlinear::increment", committed_.extent(0));
  gather(x_, 5, 0, 2, increment);
  axpby(1.0, increment, 1.0, committed_);
  Kokkos::deep_copy(x_, 0.0);
  updateTotalDisplacement();
  if (stressUpdate_ == StressUpdate::Projected)
    projectStress(load);
}

void NonlinearMixedModel::projectStress(const Vec &load) {
  // Scalar consistent mass of the new configuration; CG with Jacobi per stress component.
  if (mass_.numRows == 0)
    mass_ = expandGraph<Memory>(graph_, 1);
  Kokkos::deep_copy(mass_.values, 0.0);
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    assembleScalarMass<Elem>(Exec(), current_.mesh, data_.thickness, map_, mass_);
  });
  const LocalIndex nn = mesh_.numNodes();
  Vec diag("mixcon::nonlinear::massDiagonal", nn), b("mixcon::nonlinear::projectionRhs", nn),
      t("mixcon::nonlinear::projected", nn);
  fieldDiagonal(mass_, 1, 0, 1, diag, 1.0);
  const LinearMap apply = [&](const ConstDeviceVector &x, const DeviceVector &y) {
    multiply(Exec(), mass_, x, y);
  };
  const LinearMap jacobi = [&](const ConstDeviceVector &x, const DeviceVector &y) {
    divide(x, diag, y);
  };
  KrylovOptions o;
  o.tolerance = 1e-13;
  o.maxIterations = 500;
  for (int c = 0; c < 3; ++c) {
    gather(load, 3, c, 1, b);
    gather(tau_, 3, c, 1, t); // the previous stress as the initial guess
    const KrylovStats s = krylovSolve(o, apply, jacobi, b, t);
    if (!s.converged)
      throw std::runtime_error("mixed stress update: the mass projection did not converge");
    scatter<double>(t, 3, c, 1, tau_, false);
  }
}

void NonlinearMixedModel::rollback() {
  if (form_ == MixedForm::Current)
    Kokkos::deep_copy(x_, committedState_);
  else
    Kokkos::deep_copy(x_, 0.0);
  updateTotalDisplacement();
}

// Form Current: the committed unknowns (total displacement and nodal Cauchy stress). Form
// Incremental: the total displacement, the stress tau and the configuration c1 carried from
// increment to increment (c1 is saved itself: X + u differs from it by rounding).
void NonlinearMixedModel::saveCommitted(Checkpoint &state) const {
  if (form_ == MixedForm::Current) {
    state.putScalar("model/formulation", 1.0);
    state.put("model/unknowns", toHost(committedState_));
    return;
  }
  state.putScalar("model/formulation", 2.0);
  state.put("model/displacement", toHost(committed_));
  state.put("model/stress", toHost(tau_));
  const auto c =
      Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), current_.mesh.coordinates);
  std::vector<double> rows(2 * c.extent(0)); // node by node, whatever the view's layout
  for (std::size_t i = 0; i < c.extent(0); ++i)
    for (int d = 0; d < 2; ++d)
      rows[2 * i + d] = c(i, d);
  state.put("model/configuration", std::move(rows));
}

void NonlinearMixedModel::restoreCommitted(const Checkpoint &state) {
  if (form_ == MixedForm::Current) {
    checkFormulation(state, 1.0);
    fromHost(state.get("model/unknowns", committedState_.extent(0)), committedState_);
  } else {
    checkFormulation(state, 2.0);
    fromHost(state.get("model/displacement", committed_.extent(0)), committed_);
    fromHost(state.get("model/stress", tau_.extent(0)), tau_);
    const auto &rows = state.get("model/configuration", current_.mesh.coordinates.size());
    auto c = Kokkos::create_mirror_view(current_.mesh.coordinates);
    for (std::size_t i = 0; i < c.extent(0); ++i)
      for (int d = 0; d < 2; ++d)
        c(i, d) = rows[2 * i + d];
    Kokkos::deep_copy(current_.mesh.coordinates, c);
  }
  rollback();
}

std::vector<double> NonlinearMixedModel::nodalStressHost() const { return toHost(stressOnly()); }

std::vector<double> NonlinearMixedModel::reactionHost(double) const {
  const auto g = toHost(g_);
  std::vector<double> r(2 * (g.size() / 5));
  for (std::size_t k = 0; k < r.size() / 2; ++k)
    for (int i = 0; i < 2; ++i)
      r[2 * k + i] = g[5 * k + i];
  return r;
}

Kokkos::View<double *, Memory> NonlinearMixedModel::stressOnly() const {
  Vec t("mixcon::nonlinear::nodalStress", tau_.extent(0));
  gather(x_, 5, 2, 3, t);
  axpby(1.0, tau_, 1.0, t);
  return t;
}

std::vector<double> NonlinearMixedModel::interpolatedGaussStressHost() const {
  std::vector<double> out;
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    const LocalIndex ne = mesh_.numElements();
    Kokkos::View<double **[3], Memory> sq("mixcon::nonlinear::qpInterpolated", ne, Elem::kNumQp);
    interpolateNodalStress<Elem>(Exec(), current_.mesh, ConstVec(stressOnly()), sq);
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sq);
    out.assign(h.data(), h.data() + h.size());
  });
  return out;
}

// ---------------------------------------------------------------------------------------------
// LoadStepper

LoadStepper::LoadStepper(NonlinearModel &model, const NonlinearOptions &options, std::ostream *log,
                         Verbosity verbosity)
    : model_(model), options_(options), log_(log),
      detail_(verbosity == Verbosity::Verbose ? log : nullptr) {}

std::string LoadStepper::contactHint() const {
  return model_.contactIterations()
             ? "; with contact, a body held only by obstacles has rigid-body modes "
               "until it touches them: start it touching (gap 0) or hold it by a "
               "displacement condition"
             : "";
}

bool LoadStepper::attempt(double lambda, IncrementOutcome &out, std::string &why) {
  out.history.clear();
  ContactIterations *contact = model_.contactIterations();
  if (contact)
    contact->setLoadFactor(lambda);
  double r0 = model_.evaluate(lambda, true);
  // A force-driven obstacle without support first moves along its force onto the body.
  const bool seated = contact && contact->seatForceDriven() > 0;
  if (seated)
    r0 = model_.evaluate(lambda, true);
  if (contact && (!contactStarted_ || seated)) {
    // Nodes touching an obstacle in the initial state close before the first correction, so a
    // body resting on an obstacle is supported from the start.
    contactStarted_ = true;
    if (contact->closeTouching(1e-12) > 0)
      r0 = model_.evaluate(lambda, true);
  }
  out.initialResidual = r0;
  if (!std::isfinite(r0)) {
    why = model_.invertedElementMessage() + " at the start of the increment";
    return false;
  }
  // A linear body against flat obstacles (or none): the first converged solve is the answer and
  // the residual criterion alone decides (|du|/|u| is then the whole step, not an error).
  const bool linear = model_.linearResponse() && (!contact || contact->linearConstraints());
  for (int it = 1; it <= options_.maxIterations; ++it) {
    double inc = 0.0;
    LinearSolveStats s;
    try {
      s = model_.correct(lambda, inc);
    } catch (const InputError &) {
      throw; // a modelling error, not a failed increment
    } catch (const std::runtime_error &e) {
      why = std::string("the linear solve failed: ") + e.what() + contactHint();
      return false;
    }
    ++out.iterations;
    out.linearIterations += s.iterations;
    out.solveSeconds += s.solveSeconds;
    if (!s.converged) {
      std::ostringstream m;
      m << "the linear solver did not converge (relative residual " << s.relativeResidual
        << " after " << s.iterations << " iterations)";
      why = m.str() + contactHint();
      return false;
    }
    const bool tangent = options_.method == IterationMethod::Newton;
    const double r = model_.evaluate(lambda, tangent);
    out.history.push_back({inc, r, s.iterations});
    if (detail_) {
      char line[200];
      std::snprintf(line, sizeof line,
                    "    load factor %.5g  iteration %d  |du|/|u| %.3e  residual %.3e  linear its "
                    "%d\n",
                    lambda, it, inc, r, s.iterations);
      *detail_ << line << std::flush;
    }
    if (!std::isfinite(r) || !std::isfinite(inc)) {
      why = model_.invertedElement() >= 0 ? model_.invertedElementMessage()
                                          : std::string("the residual is not finite");
      return false;
    }
    if (options_.method == IterationMethod::None)
      return true;
    if ((inc <= options_.tolerance || linear) && r <= options_.residualTolerance)
      return true;
    if (it >= 3 && r > 1e3 * std::max(r0, options_.residualTolerance)) {
      why = "the iteration diverges (residual " + std::to_string(r) + ")";
      return false;
    }
  }
  std::ostringstream m;
  m << "no convergence in " << options_.maxIterations
    << " iterations (|du|/|u| = " << out.history.back().increment
    << ", residual = " << out.history.back().residual << ")";
  why = m.str();
  return false;
}

bool LoadStepper::settleContact(double lambda, IncrementOutcome &out, std::string &why) {
  // The report's nested iterations: after equilibrium, update the contact statuses from the
  // positions and contact forces; while any changed, iterate equilibrium again at this load.
  ContactIterations *contact = model_.contactIterations();
  if (!contact)
    return true;
  std::string previous = contact->signature();
  std::set<std::string> seen{previous};
  bool frozen = false;
  for (int it = 0; it < options_.maxContactIterations; ++it) {
    std::string changesLog;
    const auto stress = model_.contactStressHost();
    const int changes =
        contact->updateStatus(model_.residualVectorHost(), model_.unknownsPerNode(), changesLog,
                              stress.empty() ? nullptr : &stress, frozen);
    ++out.contactIterations;
    if (detail_ && !changesLog.empty())
      *detail_ << changesLog;
    if (changes == 0) {
      std::string where;
      if (!contact->penetrationWithin(1e-6, where)) {
        why = "penetration above 1e-6 of the obstacle size after convergence: " + where;
        return false;
      }
      return true;
    }
    // Only status changes can cycle; friction-force updates alone keep the signature.
    const std::string signature = contact->signature();
    const bool statusChanged = signature != previous;
    previous = signature;
    if (statusChanged && !seen.insert(signature).second) {
      // A status pattern came back: the active set cycles. Resolve it by keeping the current
      // pattern and iterating only the friction forces to mu N, and report it.
      out.contactCycled = true;
      frozen = true;
      if (log_)
        *log_ << "    contact: the active set cycles at load factor " << lambda
              << "; keeping the current pattern\n";
    }
    if (!attempt(lambda, out, why))
      return false;
  }
  why = "the contact statuses did not settle in " + std::to_string(options_.maxContactIterations) +
        " contact iterations";
  return false;
}

IncrementOutcome LoadStepper::advance(double target) {
  IncrementOutcome out;
  double step = target - lambda_;
  while (std::abs(target - lambda_) > 1e-14 * std::max(1.0, std::abs(target))) {
    const double next =
        std::abs(target - lambda_) <= std::abs(step) * (1 + 1e-12) ? target : lambda_ + step;
    std::string why;
    if (attempt(next, out, why) && settleContact(next, out, why)) {
      model_.commit();
      if (model_.contactIterations())
        model_.contactIterations()->commit();
      lambda_ = next;
      ++out.subincrements;
      continue;
    }
    model_.rollback();
    if (model_.contactIterations())
      model_.contactIterations()->rollback();
    if (out.subincrements == 0 && lambda_ == 0.0)
      contactStarted_ = false; // back at the initial state: close the touching nodes again
    if (++out.cuts > options_.maxCuts) {
      std::ostringstream m;
      m << "load factor " << next << ": " << why << "; gave up after " << options_.maxCuts
        << " increment cuts (last increment " << step << ")";
      out.message = m.str();
      return out;
    }
    if (log_)
      *log_ << "    load factor " << next << ": " << why << "; cutting the increment to "
            << step / 2 << "\n";
    step *= 0.5;
  }
  out.converged = true;
  return out;
}

std::vector<double> convergenceOrders(const std::vector<double> &r) {
  std::vector<double> q;
  for (std::size_t k = 2; k < r.size(); ++k)
    if (r[k] > 0 && r[k - 1] > 0 && r[k - 2] > 0 && r[k - 1] != r[k - 2])
      q.push_back(std::log(r[k] / r[k - 1]) / std::log(r[k - 1] / r[k - 2]));
  return q;
}

} // namespace mixcon
