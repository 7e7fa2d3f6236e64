// The displacement model (solver/NonlinearDisplacementModel.hpp). Layer: solver.
#include <core/Transfer.hpp>
#include <solver/Dirichlet.hpp>
#include <solver/FieldOps.hpp>
#include <solver/Krylov.hpp>
#include <solver/NonlinearDisplacementModel.hpp>
#include <solver/Rules.hpp>

#include <kernels/Nonlinear.hpp>

#include <cmath>
#include <stdexcept>

namespace mixcon {

using namespace fieldops;

NonlinearDisplacementModel::~NonlinearDisplacementModel() = default;

void NonlinearDisplacementModel::setup(const LinearSolverOptions &options, MPI_Comm comm) {
  if (const auto why = rules::reportTangentLaw(tangentKind_, law_))
    throw InputError("nonlinear displacement model: " + *why);
  const auto start = std::chrono::steady_clock::now();
  if (dim() == 3 && contact_)
    throw InputError("nonlinear displacement model: contact is 2D only so far (issue 17)");
  graph_ = buildNodeGraph(mesh_);
  tangent_ = expandGraph<Memory>(graph_, dim());
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
  positions_ =
      Kokkos::View<double **, Memory>("mixcon::nonlinear::positions", mesh_.numNodes(), dim());
  Kokkos::deep_copy(positions_, referenceCoordinates());
  solver_->setNearNullSpace(positions_);
  assemblySeconds_ = seconds(start);
}

std::string NonlinearDisplacementModel::solverName() const {
  return solver_ ? solver_->name() : std::string("none");
}

void NonlinearDisplacementModel::setDisplacement(const std::vector<double> &u) { fromHost(u, u_); }

double NonlinearDisplacementModel::evaluate(double lambda, bool tangent) {
  const auto start = std::chrono::steady_clock::now();
  Kokkos::deep_copy(g_, 0.0);
  if (tangent) {
    Kokkos::deep_copy(tangent_.values, 0.0);
    movedCoordinates(referenceCoordinates(), u_, dim(), positions_);
  }
  const CsrMatrix<Memory> none;
  const CsrMatrix<Memory> &a = tangent ? tangent_ : none;
  LocalIndex inverted = -1;
  double fint = 0.0;
  const bool report = tangent && tangentKind_ == TangentKind::Report;
  dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    constexpr int kDim = Elem::kDim;
    const auto &d = elementData<kDim>();
    if (small_) {
      if (linearStiffness_.numRows == 0) {
        linearStiffness_ = cloneValues(tangent_);
        Kokkos::deep_copy(linearStiffness_.values, 0.0);
        assembleLinearStiffness<Elem>(Exec(), d, map_, linearStiffness_);
      }
      multiply(Exec(), linearStiffness_, ConstVec(u_), g_);
      if (tangent)
        Kokkos::deep_copy(tangent_.values, linearStiffness_.values);
    } else {
      inverted = law_ == ElasticLaw::SaintVenantKirchhoff
                     ? assembleNonlinear<kDim, Elem>(
                           Exec(), d.mesh, SvkKernel<Elem, Memory>{d, ConstVec(u_)}, map_, a, g_)
                     : assembleAlmansi<Elem>(Exec(), d, ConstVec(u_), map_, report ? none : a, g_);
    }
    fint = strideNorm(g_, 1, 0, 1, {}, 0);
    subtractLoad(g_, kDim, lambda);
    if (report && !small_)
      assembleReportTangent<Elem>();
    if constexpr (kDim == 2) {
      if (follower_.edges.extent(0) > 0) {
        const auto [pressure, factor] = followerPressureAt(lambda);
        assembleFollowerPressure<kDim, Elem>(Exec(), d.mesh, ConstVec(u_), follower_.edges,
                                             pressure, factor, d.thickness, map_, a,
                                             followerForce(g_));
        addFollowerForce(g_, kDim);
      }
    } else if (follower_.edges.extent(0) > 0) {
      const auto [pressure, factor] = followerPressureAt(lambda);
      assembleFollowerFacePressure<kDim, Elem>(Exec(), d.mesh, ConstVec(u_), follower_.edges,
                                               pressure, factor, map_, a, followerForce(g_));
      addFollowerForce(g_, kDim);
    }
  });
  return finishEvaluate(lambda, tangent, inverted, fint, g_, dim(), isConstrained_,
                        referenceCoordinates(), u_, start);
}

template <class Elem> void NonlinearDisplacementModel::assembleReportTangent() {
  // K^L + K^sigma of Eq. (24)-(25) on the current configuration x = X + u, with tau the Cauchy
  // stress of the Almansi law at the quadrature points.
  // View extents spelled from Elem, not from the local kDim: nvcc 13 gave xq the extent of the
  // view before it (kDim * kDim) when both came from local constants, so the host launched a
  // kernel the device code did not have ("invalid resource handle", docs/gpu.md).
  constexpr int kDim = Elem::kDim;
  const LocalIndex ne = mesh_.numElements();
  Kokkos::View<double * * [Voigt<Elem::kDim>::kSize], Memory> tau("mixcon::nonlinear::qpCauchy", ne,
                                                                  Elem::kNumQp);
  Kokkos::View<double * * [Elem::kDim * Elem::kDim], Memory> grad("mixcon::nonlinear::qpGradient",
                                                                  ne, Elem::kNumQp);
  Kokkos::View<double * * [Elem::kDim], Memory> xq("mixcon::nonlinear::qpCurrent", ne,
                                                   Elem::kNumQp);
  almansiGaussPointStress<Elem>(Exec(), elementData<kDim>(), ConstVec(u_), tau, grad, xq);
  if constexpr (kDim == 2) {
    ElementData<Memory> current = data_;
    current.mesh.coordinates = Kokkos::View<double *[kDisp], Memory>(
        "mixcon::nonlinear::currentCoordinates", mesh_.numNodes());
    movedCoordinates(data_.mesh.coordinates, u_, kDisp, current.mesh.coordinates);
    assembleLinearStiffness<Elem>(Exec(), current, map_, tangent_);
    assembleGeometricStiffness<Elem>(
        Exec(), current,
        GaussPointStressField<Memory>{Kokkos::View<const double **[kStress], Memory>(tau)}, map_,
        tangent_);
  } else {
    ElementData<Memory, 3> current = solid_; // positions_: x = X + u (evaluate)
    current.mesh.coordinates = positions_;
    assembleLinearStiffness<Elem>(Exec(), current, map_, tangent_);
    assembleSolidGeometricStiffness<Elem>(
        Exec(), current.mesh, Kokkos::View<const double **[6], Memory>(tau), map_, tangent_);
  }
}

LinearSolveStats NonlinearDisplacementModel::correct(double lambda, double &increment) {
  const LinearSolveStats s =
      contact_ && contact_->constrains()
          ? correctWithContact(lambda, dim(), tangent_, constrained_, isConstrained_, g_, rhs_,
                               target_, *solver_, du_)
          : (prescribedStep(isConstrained_, prescribed_, u_, lambda, dim(), dim(), target_,
                            prescribedBase_),
             constrainedSolve(tangent_, fresh_ || contactIterations() != nullptr, constrained_,
                              isConstrained_, g_, target_, rhs_, diag_, *solver_, du_,
                              solverSetupSeconds_));
  fresh_ = false;
  axpby(1.0, du_, 1.0, u_);
  increment = relativeToHistory(strideNorm(du_, 1, 0, 1, {}, 0), strideNorm(u_, 1, 0, 1, {}, 0),
                                kDisplacementScale);
  return s;
}

void NonlinearDisplacementModel::commit() { Kokkos::deep_copy(committed_, u_); }
void NonlinearDisplacementModel::rollback() { Kokkos::deep_copy(u_, committed_); }

void NonlinearDisplacementModel::saveCommitted(Checkpoint &state) const {
  state.putScalar("model/formulation", 0.0);
  state.put("model/displacement", toHost(committed_));
}

void NonlinearDisplacementModel::restoreCommitted(const Checkpoint &state) {
  detail::checkFormulation(state, 0.0);
  fromHost(state.get("model/displacement", committed_.extent(0)), committed_);
  rollback();
}

std::vector<double> NonlinearDisplacementModel::nodalStressHost() const {
  return dispatchElement(mesh_.elementType, [&](auto elem) {
    using Elem = decltype(elem);
    Kokkos::View<double * [Voigt<Elem::kDim>::kSize], Memory> s("mixcon::nonlinear::nodalStress",
                                                                mesh_.numNodes());
    if constexpr (Elem::kDim == 2) {
      if (small_)
        recoverNodalStress<Elem>(Exec(), data_.mesh, LinearPointStress<Elem, Memory>{data_, u_}, s);
      else
        recoverNodalStress<Elem>(Exec(), data_.mesh,
                                 AlmansiPointStress<Elem, Memory>{data_, u_, law_}, s);
    } else if (small_) {
      solidNodalStressRecovery<Elem>(Exec(), solid_, ConstVec(u_), s);
    } else {
      recoverSolidNodalStress<Elem>(
          Exec(), solid_.mesh, ConstVec(u_),
          SolidCauchyStress<Elem, Memory>{solid_.material, solid_.stiffness, law_}, s);
    }
    return toHostVector(s);
  });
}

std::vector<double> NonlinearDisplacementModel::reactionHost(double) const { return toHost(g_); }

} // namespace mixcon
