// Stress accuracy of the mixed model versus the stabilization a and the compliance mass (lumped
// vs consistent), against the displacement model's recovered stresses, on two closed-form cases:
// the pressurized Lame cylinder (error on the loaded surface r = a) and the Kirsch plate (error on
// the hole, stress concentration 3). Prints markdown tables with convergence rates under uniform
// refinement (docs/mixed-model.md). Not a timing benchmark.
// Usage: mixcon_mixed_accuracy [levels]   (default 4 refinement levels)
#include <solver/Environment.hpp>
#include <support/AccuracyCases.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

using namespace mixcon;
using namespace mixcon::test;

namespace {

std::vector<Method> methods(ElementType type) {
  std::vector<Method> m{{Formulation::Displacement, ComplianceMass::Consistent, 0.0}};
  for (double a : {0.0, 0.01, 0.05, 0.2})
    m.push_back({Formulation::Mixed, ComplianceMass::Consistent, a});
  if (massLumping(type) == MassLumping::RowSum)
    for (double a : {0.0, 0.01, 0.05, 0.2})
      m.push_back({Formulation::Mixed, ComplianceMass::Lumped, a});
  return m;
}

template <class Run> void table(const char *title, ElementType type, int levels, Run run) {
  std::printf("\n### %s, %s\n\n", title, type == ElementType::Quad8 ? "Quad8" : "Quad4");
  std::printf("| method | surface error per level | rate | interior error (finest) | rate | "
              "peak (finest) | C eps(u) at Gauss points, error (finest) | iterations per level "
              "|\n|---|---|---|---|---|---|---|---|\n");
  for (const Method &m : methods(type)) {
    std::vector<CaseResult> r;
    for (int l = 0; l < levels; ++l)
      r.push_back(run(l, m));
    std::printf("| %s | ", m.name().c_str());
    for (int l = 0; l < levels; ++l)
      std::printf("%.2e%s", r[l].surface, l + 1 < levels ? ", " : "");
    const auto rate = [&](double CaseResult::*f) {
      return std::log2(r[levels - 2].*f / r[levels - 1].*f);
    };
    std::printf(" | %.2f | %.2e | %.2f | %.4f | %.2e | ", rate(&CaseResult::surface),
                r[levels - 1].interior, rate(&CaseResult::interior), r[levels - 1].peak,
                r[levels - 1].gauss);
    for (int l = 0; l < levels; ++l)
      std::printf("%d%s", r[l].iterations, l + 1 < levels ? ", " : "");
    std::printf(" |\n");
    std::fflush(stdout);
  }
}

} // namespace

int main(int argc, char **argv) {
  Environment env(argc, argv);
  const int levels = argc > 1 ? std::atoi(argv[1]) : 4;
  std::printf("Nodal-stress accuracy (relative RMS over the surface nodes; rate = log2 of the "
              "error ratio over the last refinement). %s\n",
              Environment::describe().c_str());
  for (ElementType type : {ElementType::Quad4, ElementType::Quad8}) {
    const int base = type == ElementType::Quad4 ? 8 : 4;
    table("Lame cylinder, error at the loaded surface r = a (peak: sigma_theta(a)/p, exact "
          "1.6667)",
          type, levels, [&](int l, const Method &m) {
            return lameCase(type, base << l, (3 * base / 2) << l, m);
          });
    table("Kirsch plate, error on the hole (peak: sigma_xx(0, a)/S, exact 3)", type, levels,
          [&](int l, const Method &m) { return kirschCase(type, (base / 2) << l, m); });
  }
  return 0;
}
