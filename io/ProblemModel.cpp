// The model and materials sections of the problem file: formulation, plane analysis and the
// mixed and nonlinear options; one constitutive matrix per region (io/ProblemReader.hpp). Data
// flow: io (input side).
#include <io/ProblemReader.hpp>
#include <kernels/MixedElasticity.hpp>
#include <solver/Rules.hpp>

#include <cmath>

namespace mixcon::detail {

ModelSpec readModel(const YamlItem &m, ElementType meshElement) {
  m.allowOnly({"formulation", "analysis", "thickness", "geometric_nonlinearity", "compliance",
               "stabilization", "stress_element", "mixed_form", "stress_update", "elastic_law",
               "operators"});
  ModelSpec s;
  if (m.has("formulation"))
    s.formulation = m["formulation"].choice({"displacement", "mixed"}) == "mixed"
                        ? Formulation::Mixed
                        : Formulation::Displacement;
  for (const char *key : {"compliance", "stabilization", "stress_element", "operators"})
    if (m.has(key) && s.formulation != Formulation::Mixed)
      m[key].fail(std::string(key) + " applies to formulation: mixed only");
  if (m.has("compliance"))
    s.mixed.compliance = m["compliance"].choice({"consistent", "lumped"}) == "lumped"
                             ? ComplianceMass::Lumped
                             : ComplianceMass::Consistent;
  if (m.has("stabilization")) {
    s.mixed.stabilization = m["stabilization"].number();
    if (const auto why = rules::stabilizationRange(s.mixed.stabilization))
      m["stabilization"].fail(*why);
  }
  if (m.has("stress_element"))
    s.stressElement = elementType(m["stress_element"]);
  if (m.has("operators")) { // how K12, K12^T and M are applied (kernels/MixedMatrixFree.hpp)
    const std::string v =
        m["operators"].choice({"auto", "assembled", "partial_assembly", "matrix_free"});
    s.mixed.operators = v == "assembled"          ? MixedOperatorForm::Assembled
                        : v == "partial_assembly" ? MixedOperatorForm::PartialAssembly
                        : v == "matrix_free"      ? MixedOperatorForm::MatrixFree
                                                  : MixedOperatorForm::Auto;
  }
  if (m.has("analysis"))
    s.analysis = m["analysis"].choice({"plane_stress", "plane_strain"}) == "plane_strain"
                     ? PlaneAnalysis::PlaneStrain
                     : PlaneAnalysis::PlaneStress;
  if (m.has("thickness"))
    s.thickness = m["thickness"].positive();
  if (m.has("geometric_nonlinearity")) {
    s.geometricNonlinearity = m["geometric_nonlinearity"].boolean();
    if (s.geometricNonlinearity && s.formulation == Formulation::Mixed)
      for (const char *key : {"compliance", "stress_element", "operators"})
        if (m.has(key))
          m[key].fail(std::string(key) + " applies to the linear mixed model's Schur solver; the "
                                         "geometrically nonlinear mixed model uses the "
                                         "consistent M and equal-order interpolation");
  }
  const bool nonlinearMixed = s.geometricNonlinearity && s.formulation == Formulation::Mixed;
  for (const char *key : {"mixed_form", "stress_update"})
    if (m.has(key) && !nonlinearMixed)
      m[key].fail(std::string(key) + " applies to formulation: mixed with "
                                     "geometric_nonlinearity: true only");
  if (nonlinearMixed && !m.has("stabilization"))
    s.mixed.stabilization = 0.0; // the report's model unless asked otherwise
  if (m.has("mixed_form"))
    s.mixedForm = m["mixed_form"].choice({"current", "incremental"}) == "incremental"
                      ? MixedForm::Incremental
                      : MixedForm::Current;
  if (m.has("elastic_law")) {
    if (!s.geometricNonlinearity || s.formulation != Formulation::Displacement)
      m["elastic_law"].fail("elastic_law applies to formulation: displacement with "
                            "geometric_nonlinearity: true only");
    s.elasticLaw = m["elastic_law"].choice({"almansi", "saint_venant_kirchhoff"}) == "almansi"
                       ? ElasticLaw::Almansi
                       : ElasticLaw::SaintVenantKirchhoff;
  }
  if (m.has("stress_update")) {
    if (s.mixedForm != MixedForm::Incremental)
      m["stress_update"].fail("stress_update applies to mixed_form: incremental only");
    s.stressUpdate = m["stress_update"].choice({"projected", "nodal_average"}) == "nodal_average"
                         ? StressUpdate::NodalAverage
                         : StressUpdate::Projected;
  }
  if (s.formulation == Formulation::Mixed) {
    try {
      checkMixedPairing(meshElement, s.stressElement.value_or(meshElement));
    } catch (const InputError &e) {
      m.fail(e.what());
    }
    if (const auto why = rules::lumpedCompliance(s.mixed.compliance, meshElement))
      m.fail(*why);
  }
  return s;
}

MaterialSpec readMaterial(const YamlItem &m, PlaneAnalysis analysis) {
  MaterialSpec s;
  s.line = m.line();
  m.requireMap();
  s.region = m.required("region").string();
  s.type = m.required("type").choice({"isotropic", "orthotropic", "anisotropic"});
  const double deg = m.has("angle") ? m["angle"].number() : 0.0;
  const double theta = deg * M_PI / 180.0;
  if (s.type == "isotropic") {
    m.allowOnly({"region", "type", "E", "nu"});
    s.youngs = m.required("E").positive();
    s.poisson = m.required("nu").number();
    if (!(s.poisson > -1.0 && s.poisson < 0.5))
      m["nu"].fail("Poisson's ratio must lie in (-1, 0.5)");
    s.stiffness = isotropicStiffness(s.youngs, s.poisson, analysis);
  } else if (s.type == "orthotropic") {
    m.allowOnly({"region", "type", "E1", "E2", "E3", "G12", "nu12", "nu13", "nu23", "angle"});
    OrthotropicConstants k{};
    k.e1 = m.required("E1").positive();
    k.e2 = m.required("E2").positive();
    k.g12 = m.required("G12").positive();
    k.nu12 = m.required("nu12").number();
    if (analysis == PlaneAnalysis::PlaneStrain) {
      k.e3 = m.required("E3").positive();
      k.nu13 = m.required("nu13").number();
      k.nu23 = m.required("nu23").number();
    } else { // out-of-plane constants do not enter plane stress
      k.e3 = m.has("E3") ? m["E3"].positive() : k.e2;
      k.nu13 = m.has("nu13") ? m["nu13"].number() : 0.0;
      k.nu23 = m.has("nu23") ? m["nu23"].number() : 0.0;
    }
    s.stiffness = orthotropicStiffness(k, analysis, theta);
  } else {
    m.allowOnly({"region", "type", "C11", "C12", "C16", "C22", "C26", "C66", "angle"});
    PlaneMatrix c{};
    c.m[0][0] = m.required("C11").number();
    c.m[0][1] = c.m[1][0] = m.required("C12").number();
    c.m[0][2] = c.m[2][0] = m.has("C16") ? m["C16"].number() : 0.0;
    c.m[1][1] = m.required("C22").number();
    c.m[1][2] = c.m[2][1] = m.has("C26") ? m["C26"].number() : 0.0;
    c.m[2][2] = m.required("C66").number();
    s.stiffness = rotateStiffness(c, theta);
  }
  if (!isPositiveDefinite(s.stiffness))
    m.fail("the material's constitutive matrix is not positive definite (check the constants)");
  return s;
}

void readMaterials(const YamlItem &top, Problem &p) {
  // Materials: one per region, every region covered.
  const YamlItem mats = top.required("materials");
  if (!mats.node.IsNull()) // an empty list reads as null: then every region lacks a material
    mats.requireSequence();
  for (std::size_t i = 0; i < mats.node.size(); ++i) {
    const YamlItem m = mats.at(i);
    MaterialSpec s = readMaterial(m, p.model.analysis);
    if (p.mesh.regionIndex(s.region) < 0) {
      std::string known;
      for (const auto &r : p.mesh.regionNames)
        known += " " + r;
      m["region"].fail("unknown region '" + s.region + "' (mesh regions:" + known + ")");
    }
    for (const auto &o : p.materials)
      if (o.region == s.region)
        m["region"].fail("region '" + s.region + "' already has a material");
    p.materials.push_back(s);
  }
  for (const auto &r : p.mesh.regionNames) {
    bool found = false;
    for (const auto &m : p.materials)
      found = found || m.region == r;
    if (!found)
      mats.fail("region '" + r + "' has no material");
  }
}

} // namespace mixcon::detail
