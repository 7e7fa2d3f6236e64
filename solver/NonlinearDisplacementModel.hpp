// The displacement model of the report (Eq. (24)-(28)) as a NonlinearModel: Cauchy stress from
// the Almansi strain (or St. Venant-Kirchhoff), integrals over the current configuration, exact
// or the report's symmetric tangent. Layer: solver.
#pragma once

#include <solver/NonlinearModel.hpp>

#include <memory>
#include <string>
#include <vector>

namespace mixcon {

/// The displacement model (Eq. (24)-(28)): Cauchy stress from the Almansi strain of the total
/// displacement, integrals over the current configuration, exact (nonsymmetric) tangent or the
/// report's symmetric K^L + K^sigma.
class NonlinearDisplacementModel final : public NonlinearModel {
public:
  using NonlinearModel::NonlinearModel;
  ~NonlinearDisplacementModel() override;

  void setup(const LinearSolverOptions &options, MPI_Comm comm) override;
  double evaluate(double lambda, bool tangent) override;
  LinearSolveStats correct(double lambda, double &increment) override;
  void commit() override;
  void rollback() override;
  void saveCommitted(Checkpoint &state) const override;
  void restoreCommitted(const Checkpoint &state) override;

  std::string solverName() const override;
  std::vector<double> nodalStressHost() const override; ///< the law's, recovered at nodes
  std::vector<double> reactionHost(double loadFactor) const override;
  /// The last assembled tangent (unconstrained) and residual, for tests.
  const CsrMatrix<Memory> &tangent() const { return tangent_; }
  Kokkos::View<const double *, Memory> residual() const { return g_; }
  void setDisplacement(const std::vector<double> &u);
  void setTangent(TangentKind t) { tangentKind_ = t; }
  /// Elastic law (default Almansi; St. Venant-Kirchhoff needs the exact tangent).
  void setElasticLaw(ElasticLaw law) { law_ = law; }
  std::vector<double> residualVectorHost() const override { return toHost(g_); }
  std::vector<double> residualVectorHost(const std::vector<LocalIndex> &nodes) const override {
    return toHostAt(g_, dim(), nodes);
  }
  int unknownsPerNode() const override { return dim(); }

private:
  template <class Elem> void assembleReportTangent();
  TangentKind tangentKind_ = TangentKind::Exact;
  CsrMatrix<Memory> linearStiffness_; ///< K^L on the reference configuration (small_)
  NodeGraph graph_;
  Kokkos::View<int ***, Kokkos::LayoutRight, Memory> map_;
  CsrMatrix<Memory> tangent_, constrained_;
  Kokkos::View<double *, Memory> g_, committed_, du_, rhs_, target_, diag_;
  std::unique_ptr<LinearSolver> solver_;
};

} // namespace mixcon
