// The linear mixed model with its blocks applied assembled, by partial assembly or fully
// matrix-free (MixedOptions::operators, kernels/MixedMatrixFree.hpp) gives the same solution:
// the shipped Lame-cylinder example's problem (quarter annulus, plane strain, internal pressure,
// consistent M, a = 0.05, BoomerAMG on Kd) and a lumped-M Quad4 plate, displacements, stresses
// and reactions to 1e-10 relative; and the problem-file key `model: {operators: ...}`.
#include <io/Problem.hpp>
#include <mesh/Generators.hpp>
#include <solver/MixedModel.hpp>

#include <support/MixedSolution.hpp>
#include <support/Params.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace mixcon;

namespace {

using test::maxRelativeDifference;

struct Solution : test::MixedSolution {
  MixedOperatorForm form;
  std::size_t assembledCouplingEntries;
};

/// examples/lame_cylinder_mixed.yaml (coarser): a = 1, b = 2, p = 100, E = 210000, nu = 0.3.
Solution solveLame(ElementType type, MixedOptions o) {
  const Mesh mesh = quarterAnnulusMesh(1.0, 2.0, 6, 9, type);
  const PlaneMatrix c = isotropicStiffness(210000.0, 0.3, PlaneAnalysis::PlaneStrain);
  MixedModel model(mesh, std::vector<int>(mesh.numElements(), 0), {c}, 1.0);
  for (LocalIndex n : mesh.nodesOf("bottom"))
    model.prescribe(n, 1, 0.0);
  for (LocalIndex n : mesh.nodesOf("left"))
    model.prescribe(n, 0, 0.0);
  model.addEdgeLoad(mesh.boundaries.at("inner"), 0.0, 0.0, 100.0);
  o.linear.tolerance = 1e-13;
  o.linear.maxIterations = 2000;
  o.innerTolerance = 1e-14;
  model.setup(o, MPI_COMM_WORLD);
  Solution r;
  static_cast<test::MixedSolution &>(r) = test::solveMixed(model);
  r.form = model.operatorForm();
  r.assembledCouplingEntries = model.operators().coupling.extent(0);
  return r;
}

} // namespace

class MixedOperatorFormTest : public ::testing::TestWithParam<ElementType> {};
INSTANTIATE_TEST_SUITE_P(Elements, MixedOperatorFormTest, test::bothElements(), test::elementName);

TEST_P(MixedOperatorFormTest, EveryFormGivesTheAssembledSolution) {
  MixedOptions o; // the example's: consistent M, a = 0.05, Krylov + BoomerAMG(Kd)
  o.operators = MixedOperatorForm::Assembled;
  const Solution ref = solveLame(GetParam(), o);
  ASSERT_TRUE(ref.stats.converged);
  EXPECT_GT(ref.assembledCouplingEntries, 0u);
  for (const auto form : {MixedOperatorForm::PartialAssembly, MixedOperatorForm::MatrixFree}) {
    o.operators = form;
    const Solution s = solveLame(GetParam(), o);
    SCOPED_TRACE(form == MixedOperatorForm::PartialAssembly ? "partial assembly" : "matrix-free");
    ASSERT_TRUE(s.stats.converged);
    EXPECT_EQ(s.form, form);
    // Only the lumped blocks stay assembled (the preconditioner is BoomerAMG on Kd).
    EXPECT_EQ(s.assembledCouplingEntries, 0u);
    EXPECT_LT(maxRelativeDifference(s.u, ref.u), 1e-10);
    EXPECT_LT(maxRelativeDifference(s.s, ref.s), 1e-10);
    EXPECT_LT(maxRelativeDifference(s.reaction, ref.reaction), 1e-10);
    EXPECT_NEAR(s.stats.iterations, ref.stats.iterations, 1);
  }
  // Auto resolves to a concrete form.
  o.operators = MixedOperatorForm::Auto;
  const Solution a = solveLame(GetParam(), o);
  EXPECT_EQ(a.form, MixedOperatorForm::Assembled); // 54 elements: below the rule's 1e4

  EXPECT_LT(maxRelativeDifference(a.u, ref.u), 1e-10);
}

/// Lumped M with the lumped-Schur preconditioner (Quad4): the operator is the assembled S_a,L;
/// the element-by-element K12^T recovers the same stresses.
TEST(MixedOperatorForm, LumpedComplianceStressRecoveryAgrees) {
  MixedOptions o;
  o.compliance = ComplianceMass::Lumped;
  o.operators = MixedOperatorForm::Assembled;
  const Solution ref = solveLame(ElementType::Quad4, o);
  ASSERT_TRUE(ref.stats.converged) << ref.stats.iterations << " " << ref.stats.relativeResidual;
  for (const auto form : {MixedOperatorForm::PartialAssembly, MixedOperatorForm::MatrixFree}) {
    o.operators = form;
    const Solution s = solveLame(ElementType::Quad4, o);
    EXPECT_GT(s.assembledCouplingEntries, 0u); // S_a,L needs the assembled coupling
    EXPECT_LT(maxRelativeDifference(s.u, ref.u), 1e-10);
    EXPECT_LT(maxRelativeDifference(s.s, ref.s), 1e-10);
    EXPECT_LT(maxRelativeDifference(s.reaction, ref.reaction), 1e-10);
  }
}

namespace {
const char *kMixed = R"(mesh:
  generator: {type: rectangle, size: [10, 1], divisions: [20, 2], element: quad8}
model: {formulation: mixed, analysis: plane_stress, thickness: 0.5, operators: VALUE}
materials:
  - {region: body, type: isotropic, E: 1.0e5, nu: 0.3}
boundary_conditions:
  - {boundary: left, ux: 0, uy: 0}
loads:
  - {boundary: right, traction: [0, -1.0]}
steps: {increments: 1}
solver: {type: amg}
output: {directory: somewhere}
)";

/// `yaml` with its first `from` replaced by `to`.
std::string replaced(const std::string &yaml, const std::string &from, const std::string &to) {
  std::string y = yaml;
  y.replace(y.find(from), from.size(), to);
  return y;
}

std::string withValue(const std::string &yaml, const std::string &value) {
  return replaced(yaml, "VALUE", value);
}
} // namespace

TEST(MixedOperatorForm, ProblemFileKey) {
  const std::pair<const char *, MixedOperatorForm> cases[] = {
      {"auto", MixedOperatorForm::Auto},
      {"assembled", MixedOperatorForm::Assembled},
      {"partial_assembly", MixedOperatorForm::PartialAssembly},
      {"matrix_free", MixedOperatorForm::MatrixFree}};
  for (const auto &[value, form] : cases)
    EXPECT_EQ(parseProblem(withValue(kMixed, value), "case.yaml", "").model.mixed.operators, form)
        << value;
  // Not given: Auto.
  const std::string none = replaced(kMixed, ", operators: VALUE", "");
  EXPECT_EQ(parseProblem(none, "case.yaml", "").model.mixed.operators, MixedOperatorForm::Auto);
  // A bad value names file:line and the choices; the key is refused off the linear mixed model.
  const std::pair<std::string, std::string> bad[] = {
      {withValue(kMixed, "sparse"), "case.yaml:3:"},
      {withValue(kMixed, "partial_assembly, geometric_nonlinearity: true"), "case.yaml:3:"}};
  for (const auto &[yaml, where] : bad) {
    try {
      parseProblem(yaml, "case.yaml", "");
      ADD_FAILURE() << "accepted: " << yaml;
    } catch (const InputError &e) {
      EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("operators"), std::string::npos) << e.what();
    }
  }
  const std::string displacement =
      replaced(withValue(kMixed, "matrix_free"), "formulation: mixed", "formulation: displacement");
  EXPECT_THROW(parseProblem(displacement, "case.yaml", ""), InputError);
}

/// The measured rule of `operators: auto` (docs/performance.md): partial assembly for Quad8 from
/// 1e4 elements, the assembled operators otherwise; an explicit form is kept.
TEST(MixedOperatorForm, AutoRule) {
  using F = MixedOperatorForm;
  EXPECT_EQ(resolveOperatorForm(F::Auto, ElementType::Quad8, 9999), F::Assembled);
  EXPECT_EQ(resolveOperatorForm(F::Auto, ElementType::Quad8, 10000), F::PartialAssembly);
  EXPECT_EQ(resolveOperatorForm(F::Auto, ElementType::Quad4, 1000000), F::Assembled);
  for (const F f : {F::Assembled, F::PartialAssembly, F::MatrixFree})
    EXPECT_EQ(resolveOperatorForm(f, ElementType::Quad8, 20000), f);
}
