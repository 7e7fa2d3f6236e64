// The model and materials sections of the problem file: formulation, plane analysis and the
// mixed and nonlinear options; one constitutive matrix per region (io/ProblemReader.hpp). Data
// flow: io (input side).
#include <io/ProblemReader.hpp>
#include <kernels/MixedElasticity.hpp>
#include <solver/Rules.hpp>

#include <cmath>

namespace mixcon::detail {

void refuseLinearMixedKeys(const YamlItem &m, const std::string &why) {
  for (const char *key : {"compliance", "stress_element", "operators"})
    if (m.has(key))
      m[key].fail(key + why);
}

ModelSpec readModel(const YamlItem &m, ElementType meshElement) {
  m.allowOnly({"formulation", "analysis", "thickness", "geometric_nonlinearity", "compliance",
               "stabilization", "stress_element", "mixed_form", "stress_update", "elastic_law",
               "operators"});
  ModelSpec s;
  if (m.has("formulation"))
    s.formulation = m["formulation"].choice({"displacement", "mixed"}) == "mixed"
                        ? Formulation::Mixed
                        : Formulation::Displacement;
  if (spatialDimension(meshElement) == 3) {
    // 3D runs so far: the displacement model, linear or geometrically nonlinear, and the mixed
    // model (hexahedra and tetrahedra) with its stabilization, linear or geometrically nonlinear
    // in either form (issue 17).
    if (s.formulation == Formulation::Mixed) {
      for (const char *key : {"compliance", "stress_element", "operators"})
        if (m.has(key))
          m[key].fail(std::string(key) + " applies to the 2D mixed model's iterative solvers; "
                                         "the 3D mixed model uses the consistent M, equal-order "
                                         "stresses and the direct solver");
    }
    for (const char *key : {"analysis", "thickness"})
      if (m.has(key))
        m[key].fail(std::string(key) + " applies to 2D meshes (plane stress or strain of a "
                                       "slice); this mesh is 3D");
  }
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
      refuseLinearMixedKeys(m, " applies to the linear mixed model's Schur solver; the "
                               "geometrically nonlinear mixed model uses the consistent M and "
                               "equal-order interpolation");
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
  if (s.formulation == Formulation::Mixed && spatialDimension(meshElement) == 2) {
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

namespace {

/// The orientation of a 3D material's axes: `axes: [[a1], [a2]]` (material axis 1, and a vector in
/// the 1-2 plane: axis 2 is its part normal to a1, axis 3 = a1 x a2), or `angles: [a, b, c]`
/// (degrees: R = Rz(a) Ry(b) Rx(c), rotations about the global axes), or neither (the global axes).
Rotation readOrientation(const YamlItem &m) {
  if (m.has("axes") && m.has("angles"))
    m["angles"].fail("give the material axes by 'axes' or by 'angles', not both");
  if (m.has("angles")) {
    const auto a = m["angles"].vector(3);
    const double r = M_PI / 180.0;
    return matmul(rotationAboutZ(a[0] * r),
                  matmul(rotationAboutY(a[1] * r), rotationAboutX(a[2] * r)));
  }
  if (!m.has("axes"))
    return identity<3>();
  const YamlItem axes = m["axes"];
  if (!axes.node.IsSequence() || axes.node.size() != 2)
    axes.fail("expected two vectors [[x, y, z], [x, y, z]]: material axis 1 and a vector in the "
              "1-2 plane");
  const auto a1 = axes.at(0).vector(3), a2 = axes.at(1).vector(3);
  const auto norm = [](const std::array<double, 3> &v) {
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  };
  const double n1 = norm(a1);
  if (!(n1 > 0.0) || !std::isfinite(n1))
    axes.at(0).fail("material axis 1 must be a non-zero vector");
  std::array<double, 3> e1{a1[0] / n1, a1[1] / n1, a1[2] / n1};
  const double d = e1[0] * a2[0] + e1[1] * a2[1] + e1[2] * a2[2];
  std::array<double, 3> e2{a2[0] - d * e1[0], a2[1] - d * e1[1], a2[2] - d * e1[2]};
  const double n2 = norm(e2);
  if (!(n2 > 1e-8 * norm(a2)) || !std::isfinite(n2))
    axes.at(1).fail("the second vector must not be parallel to material axis 1");
  for (double &c : e2)
    c /= n2;
  const std::array<double, 3> e3{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                 e1[0] * e2[1] - e1[1] * e2[0]};
  Rotation r{};
  for (int i = 0; i < 3; ++i) { // columns: the material axes in global components
    r.m[i][0] = e1[i];
    r.m[i][1] = e2[i];
    r.m[i][2] = e3[i];
  }
  return r;
}

/// E and nu of an isotropic material (any dimension).
void readIsotropicConstants(const YamlItem &m, MaterialSpec &s) {
  m.allowOnly({"region", "type", "E", "nu"});
  s.youngs = m.required("E").positive();
  s.poisson = m.required("nu").number();
  if (!(s.poisson > -1.0 && s.poisson < 0.5))
    m["nu"].fail("Poisson's ratio must lie in (-1, 0.5)");
}

/// A material of a 3D mesh: the 6 x 6 stiffness in global axes.
MaterialSpec readSolidMaterial(const YamlItem &m, MaterialSpec s) {
  if (s.type == "isotropic") {
    readIsotropicConstants(m, s);
    s.solid = IsotropicMaterial{s.youngs, s.poisson}.stiffness();
  } else if (s.type == "orthotropic") {
    m.allowOnly({"region", "type", "E1", "E2", "E3", "G12", "G13", "G23", "nu12", "nu13", "nu23",
                 "axes", "angles"});
    OrthotropicConstants k{};
    k.e1 = m.required("E1").positive();
    k.e2 = m.required("E2").positive();
    k.e3 = m.required("E3").positive();
    k.g12 = m.required("G12").positive();
    k.g13 = m.required("G13").positive();
    k.g23 = m.required("G23").positive();
    k.nu12 = m.required("nu12").number();
    k.nu13 = m.required("nu13").number();
    k.nu23 = m.required("nu23").number();
    s.solid = OrthotropicMaterial{k, readOrientation(m)}.stiffness();
  } else {
    std::vector<const char *> keys{"region", "type", "axes", "angles"};
    static const char *const kNames[21] = {"C11", "C12", "C13", "C14", "C15", "C16", "C22",
                                           "C23", "C24", "C25", "C26", "C33", "C34", "C35",
                                           "C36", "C44", "C45", "C46", "C55", "C56", "C66"};
    keys.insert(keys.end(), std::begin(kNames), std::end(kNames));
    m.allowOnly(keys);
    AnisotropicConstants k{};
    for (int i = 0; i < 21; ++i) { // the diagonal is required, couplings default to 0
      const std::string name = kNames[i];
      const bool diagonal = name[1] == name[2];
      k.c[i] = diagonal ? m.required(kNames[i]).number()
                        : (m.has(kNames[i]) ? m[kNames[i]].number() : 0.0);
    }
    s.solid = AnisotropicMaterial{k, readOrientation(m)}.stiffness();
  }
  if (!isSymmetricPositiveDefinite(s.solid))
    m.fail("the material's constitutive matrix is not positive definite (check the constants)");
  return s;
}

} // namespace

MaterialSpec readMaterial(const YamlItem &m, PlaneAnalysis analysis, int dim) {
  MaterialSpec s;
  s.line = m.line();
  m.requireMap();
  s.region = m.required("region").string();
  s.type = m.required("type").choice({"isotropic", "orthotropic", "anisotropic"});
  if (dim == 3)
    return readSolidMaterial(m, s);
  const double deg = m.has("angle") ? m["angle"].number() : 0.0;
  const double theta = deg * M_PI / 180.0;
  if (s.type == "isotropic") {
    readIsotropicConstants(m, s);
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
    MaterialSpec s = readMaterial(m, p.model.analysis, p.mesh.dim());
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
