// The option rules of the solver layer (solver/Rules.hpp): one message per rule, shared by the
// problem reader and the models' guards.
#include <kernels/MixedElasticity.hpp>
#include <solver/NonlinearDisplacementModel.hpp>
#include <solver/Rules.hpp>

namespace mixcon::rules {

std::optional<std::string> stabilizationRange(double a) {
  if (a >= 0.0 && a < 1.0)
    return std::nullopt;
  return "stabilization must lie in [0, 1) (0: the report's model)";
}

std::optional<std::string> lumpedCompliance(ComplianceMass compliance, ElementType element) {
  if (compliance != ComplianceMass::Lumped || massLumping(element) == MassLumping::RowSum)
    return std::nullopt;
  return "compliance: lumped is not available for quad8 elements (their positive HRZ lumping "
         "fails the constant-stress patch test); use compliance: consistent";
}

std::optional<std::string> reportTangentLaw(TangentKind tangent, ElasticLaw law) {
  if (tangent != TangentKind::Report || law != ElasticLaw::SaintVenantKirchhoff)
    return std::nullopt;
  return "tangent: report is the Almansi law's K^L + K^sigma; with elastic_law: "
         "saint_venant_kirchhoff use the exact tangent";
}

std::optional<std::string> mixedContactSolver(bool mixed, bool contact, LinearSolverType type) {
  if (!mixed || !contact || type == LinearSolverType::Direct)
    return std::nullopt;
  return "contact with the mixed model needs type: direct in this version";
}

std::optional<std::string> iterationLimit(int maxIterations) {
  if (maxIterations >= 1)
    return std::nullopt;
  return "must be at least 1";
}

} // namespace mixcon::rules
