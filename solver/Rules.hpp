// Rules between options of the solver layer, each defined once: a pure function that returns the
// reason a combination is refused (std::nullopt where it is allowed). The problem reader (io/)
// calls them and adds the file:line of the offending key; the models call them as guards for host
// codes that set the options through the library API. Data flow: solver (checks of its options).
#pragma once

#include <core/ElementTraits.hpp>
#include <kernels/Material.hpp>
#include <solver/MixedOptions.hpp>

#include <optional>
#include <string>

namespace mixcon {

/// Defined with the displacement model (solver/NonlinearDisplacementModel.hpp); an int enum like
/// this declaration.
enum class TangentKind;

namespace rules {

/// The mixed model's stabilization a must lie in [0, 1) (a = 1 removes the coupling block).
std::optional<std::string> stabilizationRange(double a);

/// A lumped compliance mass needs elements whose row-sum lumping is positive (not Quad8: its
/// positive HRZ lumping fails the constant-stress patch test).
std::optional<std::string> lumpedCompliance(ComplianceMass compliance, ElementType element);

/// The report's tangent (K^L + K^sigma) is the Almansi law's; St. Venant-Kirchhoff iterates with
/// the exact one.
std::optional<std::string> reportTangentLaw(TangentKind tangent, ElasticLaw law);

/// Contact with the mixed model is solved by the direct solver only in this version.
std::optional<std::string> mixedContactSolver(bool mixed, bool contact, LinearSolverType type);

/// An iteration limit of the linear solvers below 1 would "converge" without iterating.
std::optional<std::string> iterationLimit(int maxIterations);

} // namespace rules

} // namespace mixcon
