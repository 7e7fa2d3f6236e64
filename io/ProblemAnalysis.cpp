// The steps, solver and verification sections of the problem file: load factors and equilibrium
// iterations, the linear solver and the mixed model's solve settings, the closed form a run is
// checked against (io/ProblemReader.hpp). Data flow: io (input side).
#include <io/ProblemReader.hpp>
#include <mesh/Mesh.hpp>
#include <solver/Rules.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace mixcon::detail {

namespace {

/// Most load steps `increments` may ask for (their load factors are stored up front).
constexpr int kMaxIncrements = 1000000;

/// Parts at least this many element sizes thick (elementLayers) take the bulky parts' 3D AMG
/// defaults (thicknessDefaults): the shipped examples, all with fewer iterations without
/// aggressive coarsening, measured 0.57 to 2.9; the meshes where it paid 4 (a Hex20 box of 12^3:
/// 0.84 against 0.94 s), 4.4 (a Hex8 plate of 8 layers: 3.0 against 5.8 s) and more
/// (docs/performance.md, issue 20 section 1c).
constexpr double kBulkyLayers = 3.5;

} // namespace

void readIterationKeys(const YamlItem &s, NonlinearOptions &n) {
  if (s.has("iteration")) {
    const std::string v = s["iteration"].choice({"newton", "modified_newton", "none"});
    n.method = v == "none"              ? IterationMethod::None
               : v == "modified_newton" ? IterationMethod::ModifiedNewton
                                        : IterationMethod::Newton;
  }
  if (s.has("tolerance"))
    n.tolerance = s["tolerance"].positive();
  if (s.has("residual_tolerance"))
    n.residualTolerance = s["residual_tolerance"].positive();
  if (s.has("max_iterations")) {
    n.maxIterations = s["max_iterations"].integer();
    if (n.maxIterations < 1)
      s["max_iterations"].fail("must be at least 1");
  }
  if (s.has("max_cuts")) {
    n.maxCuts = s["max_cuts"].integer();
    if (n.maxCuts < 0)
      s["max_cuts"].fail("must be 0 or more");
  }
}

void readSteps(const YamlItem &top, Problem &p) {
  if (top.has("steps")) {
    const YamlItem s = top["steps"];
    if (p.hybrid)
      for (const char *key : {"increments", "load_factors"})
        if (s.has(key))
          s[key].fail("the steps of a hybrid run come from its measurement file");
    s.allowOnly({"increments", "load_factors", "iteration", "tolerance", "residual_tolerance",
                 "max_iterations", "max_cuts", "tangent"});
    for (const char *key :
         {"iteration", "tolerance", "residual_tolerance", "max_iterations", "max_cuts", "tangent"})
      if (s.has(key) && !p.model.geometricNonlinearity && p.contact.empty() && !p.hybrid)
        s[key].fail(std::string(key) +
                    " applies to geometrically nonlinear or contact analyses (model: "
                    "geometric_nonlinearity: true, or a contact: section); linear steps are single "
                    "solves");
    readIterationKeys(s, p.nonlinear);
    if (s.has("tangent")) {
      if (p.model.formulation != Formulation::Displacement)
        s["tangent"].fail("tangent applies to formulation: displacement (the mixed model always "
                          "iterates with its exact Jacobian)");
      p.tangent = s["tangent"].choice({"exact", "report"}) == "report" ? TangentKind::Report
                                                                       : TangentKind::Exact;
      if (const auto why = rules::reportTangentLaw(p.tangent, p.model.elasticLaw))
        s["tangent"].fail(*why);
    }
    if (s.has("increments") && s.has("load_factors"))
      s.fail("give 'increments' or 'load_factors', not both");
    if (s.has("increments")) {
      const int n = s["increments"].integer();
      if (n < 1)
        s["increments"].fail("must be at least 1");
      if (n > kMaxIncrements)
        s["increments"].fail("at most " + std::to_string(kMaxIncrements) + " increments");
      p.loadFactors.clear();
      for (int k = 1; k <= n; ++k)
        p.loadFactors.push_back(static_cast<double>(k) / n);
    } else if (s.has("load_factors")) {
      const YamlItem f = s["load_factors"];
      f.requireSequence();
      if (f.node.size() == 0)
        f.fail("needs at least one load factor");
      p.loadFactors.clear();
      for (std::size_t k = 0; k < f.node.size(); ++k)
        p.loadFactors.push_back(f.at(k).number());
    }
  }

  if (p.hybrid) {
    // One step per measured step; the measured values are prescribed as they are at each step.
    const std::size_t n = p.hybrid->steps.size();
    p.loadFactors.clear();
    for (std::size_t k = 1; k <= n; ++k)
      p.loadFactors.push_back(static_cast<double>(k) / n);
    if (p.model.formulation == Formulation::Mixed && !p.model.geometricNonlinearity)
      top["hybrid"].fail(
          "a hybrid run with formulation: mixed needs geometric_nonlinearity: true "
          "(the report's hybrid mode; the linear mixed model is not validated in it)");
  }
}

bool mixedInIteratingDriver(const Problem &p) {
  return p.model.formulation == Formulation::Mixed &&
         (p.model.geometricNonlinearity || !p.contact.empty() || !p.stages.empty());
}

namespace {

/// The 3D displacement model's AMG settings by the part's thickness in elements (elementLayers),
/// where the solver keys leave them, and the note that says which (Problem::solverDefaultsNote).
/// Bulky parts (the cube N^3 of docs/performance.md: with the 2D settings the setup is 82% of the
/// run at N = 64 and N = 100 does not fit 24 GB) take one level of aggressive coarsening (with the
/// truncated interpolation: 7.4x faster at N = 32, for 17-22 instead of 10-11 PCG iterations) and
/// Chebyshev of order 1 (two products per level and V-cycle instead of four: 1.15-1.5x the
/// iterations, a 1.13-1.6x faster solve on the Hex8 cube and on Hex20 and Tet10 boxes, issue 17
/// table 3n). Thin parts (plates, shells, bars: a few elements through their thinnest direction)
/// keep hypre's order 2 without aggressive coarsening, which merges their few layers: the shipped
/// 3D examples take 1.5-2.5x fewer iterations with it, a Hex20 plate with a hole of 68,715
/// unknowns 65 instead of 171 (3.09 against 2.91 s), one of 268,731 unknowns 58 instead of 144,
/// far from the escalation ladder's bound of 100 (which would send a Newton run's later setups to
/// the coarse space), for 1.2x the time of that one solve (10.4 against 8.6 s) and 1.5x its
/// memory (docs/performance.md, issue 20 section 1c). Not for the 3D mixed model, whose V-cycle on
/// K^L inside its GMRES keeps BoomerAMG's defaults: with the bulky settings a large compact mesh
/// solved 2.6x faster (a 24^3 cube), but with the threaded hypre a small cantilever took 1000
/// iterations or did not converge, against 52-173 (docs/performance.md).
void thicknessDefaults(const YamlItem &top, Problem &p) {
  const auto given = [&](const char *key) { return top.has("solver") && top["solver"].has(key); };
  const bool aggressive = !given("aggressive_levels"), order = !given("chebyshev_order");
  if (!aggressive && !order)
    return;
  const double layers = elementLayers(p.mesh);
  const bool bulky = layers >= kBulkyLayers;
  std::ostringstream note;
  note << std::fixed << std::setprecision(2) << "3D AMG settings for a "
       << (bulky ? "bulky" : "thin") << " part (" << layers
       << " element sizes thick, 2 volume / (surface x element size), "
       << (bulky ? "at least " : "below ") << std::setprecision(1) << kBulkyLayers << "):";
  bool said = false; // the note names only what the rule set
  if (aggressive) {
    p.solver.aggressiveLevels = bulky ? 1 : 0;
    note << (bulky ? " one level of aggressive coarsening" : " no aggressive coarsening");
    said = true;
  }
  if (order) {
    p.solver.chebyshevOrder = bulky ? 1 : 2;
    // named unless another smoother was asked for (with `auto` the solver's line says which runs)
    if (p.solver.smoother == AmgSmoother::Automatic ||
        p.solver.smoother == AmgSmoother::Chebyshev) {
      note << (said ? "," : "") << " Chebyshev of order " << p.solver.chebyshevOrder;
      said = true;
    }
  }
  if (said)
    p.solverDefaultsNote = note.str();
}

} // namespace

void readSolver(const YamlItem &top, Problem &p) {
  const bool nonlinearMixed =
      p.model.geometricNonlinearity && p.model.formulation == Formulation::Mixed;
  // Its solver keys are the geometrically nonlinear model's.
  const bool drivenMixed = mixedInIteratingDriver(p);
  // The 2D mixed model in the iterating driver solves with the direct solver by default when it
  // is geometrically nonlinear or in contact (contact needs it: solver/Rules.hpp). The 3D mixed
  // model (linear and nonlinear) with its block-triangular AMG solve: the LU of its 9-per-node
  // system grows too fast in 3D (the Hex8 Lame sphere of 54,873 unknowns: 185 s and 10.7 GiB
  // against 4.2 s and 0.42 GiB, docs/performance.md), which also bounds its direct fall back.
  const bool solidMixed = p.model.formulation == Formulation::Mixed && p.mesh.dim() == 3;
  if (drivenMixed && (nonlinearMixed || !p.contact.empty()) && !solidMixed)
    p.solver.type = LinearSolverType::Direct;
  if (solidMixed)
    p.solver.directFallbackUnknowns = kSolidMixedDirectFallback;
  // The 3D displacement model's AMG: truncated interpolation (the cube N^3 of docs/performance.md);
  // the rest by the part's thickness (thicknessDefaults, after the keys).
  const bool solidDisplacement = p.mesh.dim() == 3 && !solidMixed;
  if (solidDisplacement)
    p.solver.interpolationMaxElements = 4;
  if (solidMixed)
    p.model.mixedNewton.restart = kSolidMixedRestart;
  if (top.has("solver")) {
    const YamlItem s = top["solver"];
    s.allowOnly({"type",
                 "tolerance",
                 "max_iterations",
                 "strong_threshold",
                 "aggressive_levels",
                 "print_level",
                 "krylov",
                 "preconditioner",
                 "inner_tolerance",
                 "interpolation_max_elements",
                 "nodal_coarsening",
                 "amg_matrix",
                 "amg_cycle",
                 "chebyshev_order",
                 "method",
                 "stress_block_tolerance",
                 "jacobian",
                 "rigid_body_modes",
                 "coarsest_size",
                 "smoother",
                 "reuse_hierarchy",
                 "reuse_factorization",
                 "direct_fallback",
                 "direct_when_cheaper",
                 "coarse_space"});
    const bool mixed = p.model.formulation == Formulation::Mixed;
    if (solidMixed) { // the 3D mixed model: the direct solver or the block-triangular AMG solve
      for (const char *key : {"method", "krylov", "preconditioner", "inner_tolerance"})
        if (s.has(key))
          s[key].fail(std::string(key) +
                      " applies to the 2D mixed model's solvers; the 3D mixed model solves with "
                      "the block-triangular GMRES (type: amg) or the sparse LU (type: direct)");
      s.allowOnly({"type",
                   "tolerance",
                   "max_iterations",
                   "stress_block_tolerance",
                   "direct_fallback",
                   "direct_when_cheaper",
                   "strong_threshold",
                   "aggressive_levels",
                   "interpolation_max_elements",
                   "nodal_coarsening",
                   "amg_matrix",
                   "amg_cycle",
                   "chebyshev_order",
                   "rigid_body_modes",
                   "coarsest_size",
                   "smoother",
                   "reuse_hierarchy",
                   "reuse_factorization",
                   "print_level",
                   "jacobian",
                   "coarse_space"});
    }
    for (const char *key : {"method", "stress_block_tolerance"})
      if (s.has(key) && !mixed)
        s[key].fail(std::string(key) + " applies to the mixed model's solver: amg only");
    if (s.has("jacobian") && !drivenMixed && !solidMixed)
      s["jacobian"].fail("jacobian applies to the geometrically nonlinear mixed model's (or the "
                         "linear one's with stages or contact) and the 3D mixed model's solver: "
                         "amg only");
    if (s.has("method")) {
      const bool schur = s["method"].choice({"block_triangular", "schur"}) == "schur";
      p.model.mixedNewton.method =
          schur ? MixedNewtonSolver::Schur : MixedNewtonSolver::BlockTriangular;
      p.model.mixed.method = schur ? MixedLinearMethod::Schur : MixedLinearMethod::BlockTriangular;
    }
    if (s.has("stress_block_tolerance")) {
      p.model.mixedNewton.preconditionerTolerance = s["stress_block_tolerance"].positive();
      p.model.mixed.preconditionerTolerance = p.model.mixedNewton.preconditionerTolerance;
    }
    if (mixed && !drivenMixed) {
      // The linear model's Schur keys select its Schur method when none is named (files written
      // before block_triangular became the default for consistent M keep their solve); with
      // method: block_triangular they are refused, as is the block-triangular key with schur.
      for (const char *key : {"krylov", "inner_tolerance"}) {
        if (!s.has(key))
          continue;
        if (p.model.mixed.method == MixedLinearMethod::BlockTriangular ||
            s.has("stress_block_tolerance"))
          s[key].fail(std::string(key) +
                      " applies to the linear mixed model's method: schur (block_triangular runs "
                      "flexible GMRES on the saddle point, its CG on M to "
                      "stress_block_tolerance)");
        p.model.mixed.method = MixedLinearMethod::Schur;
      }
      if (s.has("stress_block_tolerance") && p.model.mixed.method == MixedLinearMethod::Schur)
        s["stress_block_tolerance"].fail(
            "stress_block_tolerance applies to method: block_triangular (the schur method's "
            "inner CG on M runs to inner_tolerance)");
      if (s.has("stress_block_tolerance") && p.model.mixed.compliance == ComplianceMass::Lumped)
        s["stress_block_tolerance"].fail(
            "stress_block_tolerance applies to compliance: consistent (the lumped M is inverted "
            "node by node)");
    }
    if (s.has("jacobian")) {
      // The matrix-free Jacobian serves the block-triangular GMRES without contact or follower
      // pressures (their contributions are assembled); refused where it would not be taken.
      const YamlItem j = s["jacobian"];
      const std::string v = j.choice({"auto", "assembled", "matrix_free"});
      p.model.mixedNewton.jacobian = v == "matrix_free" ? JacobianForm::MatrixFree
                                     : v == "assembled" ? JacobianForm::Assembled
                                                        : JacobianForm::Automatic;
      if (p.model.mixedNewton.jacobian == JacobianForm::MatrixFree) {
        if (p.model.mixedNewton.method != MixedNewtonSolver::BlockTriangular)
          j.fail("jacobian: matrix_free needs method: block_triangular");
        if (!p.contact.empty())
          j.fail("jacobian: matrix_free is not available with contact (its corrections need the "
                 "assembled Jacobian)");
        for (const LoadSpec &l : p.loads)
          if (l.kind == LoadKind::Pressure && l.follower && p.model.geometricNonlinearity)
            j.fail("jacobian: matrix_free is not available with follower pressures (their load "
                   "stiffness is assembled); use follower: false or jacobian: assembled");
      }
    }
    for (const char *key : {"krylov", "preconditioner", "inner_tolerance"}) {
      if (s.has(key) && p.model.formulation != Formulation::Mixed)
        s[key].fail(std::string(key) + " applies to formulation: mixed only");
      if (s.has(key) && drivenMixed)
        s[key].fail(std::string(key) + " applies to the linear mixed model's Schur solver only "
                                       "(not with geometric_nonlinearity, contact or stages)");
    }
    if (s.has("krylov"))
      p.model.mixed.krylov =
          s["krylov"].choice({"cg", "gmres"}) == "gmres" ? KrylovMethod::Gmres : KrylovMethod::Cg;
    if (s.has("preconditioner")) {
      const std::string v = s["preconditioner"].choice({"auto", "lumped_schur", "stiffness"});
      p.model.mixed.preconditioner = v == "stiffness"      ? SchurPreconditioner::Stiffness
                                     : v == "lumped_schur" ? SchurPreconditioner::LumpedSchur
                                                           : SchurPreconditioner::Auto;
    }
    if (s.has("inner_tolerance"))
      p.model.mixed.innerTolerance = s["inner_tolerance"].positive();
    if (s.has("type")) {
      p.solver.type = s["type"].choice({"amg", "direct"}) == "direct" ? LinearSolverType::Direct
                                                                      : LinearSolverType::Amg;
    }
    if (p.model.mixedNewton.jacobian == JacobianForm::MatrixFree &&
        p.solver.type == LinearSolverType::Direct)
      s["jacobian"].fail("jacobian: matrix_free needs type: amg (the direct solver factors the "
                         "assembled Jacobian)");
    if (s.has("tolerance"))
      p.solver.tolerance = s["tolerance"].positive();
    // Counts of levels and elements: 0 or more.
    auto count = [&](const char *key, int least) {
      const int v = s[key].integer();
      if (v < least)
        s[key].fail("must be at least " + std::to_string(least));
      return v;
    };
    if (s.has("max_iterations")) {
      p.solver.maxIterations = s["max_iterations"].integer();
      if (const auto why = rules::iterationLimit(p.solver.maxIterations))
        s["max_iterations"].fail(*why);
    }
    if (s.has("strong_threshold")) {
      p.solver.strongThreshold = s["strong_threshold"].number();
      if (!(p.solver.strongThreshold >= 0.0 && p.solver.strongThreshold < 1.0))
        s["strong_threshold"].fail("the AMG strength threshold must lie in [0, 1)");
    }
    if (s.has("aggressive_levels"))
      p.solver.aggressiveLevels = count("aggressive_levels", 0);
    if (s.has("print_level"))
      p.solver.printLevel = count("print_level", 0);
    if (s.has("interpolation_max_elements"))
      p.solver.interpolationMaxElements = count("interpolation_max_elements", 0);
    if (s.has("nodal_coarsening"))
      p.solver.nodalCoarsening = s["nodal_coarsening"].boolean();
    if (s.has("rigid_body_modes"))
      p.solver.rigidBodyModes = s["rigid_body_modes"].boolean();
    if (s.has("amg_matrix")) {
      p.solver.separateComponents =
          s["amg_matrix"].choice({"full", "separate_components"}) == "separate_components";
      if (p.solver.separateComponents && s.has("rigid_body_modes") && p.solver.rigidBodyModes)
        s["rigid_body_modes"].fail("rigid_body_modes: true needs amg_matrix: full (the rotations "
                                   "couple the displacement components that "
                                   "separate_components drops)");
    }
    if (s.has("amg_cycle")) {
      const std::string v = s["amg_cycle"].choice({"auto", "hypre", "double", "single"});
      p.solver.cycle = v == "double"   ? AmgCycleKind::MixconDouble
                       : v == "single" ? AmgCycleKind::MixconSingle
                       : v == "hypre"  ? AmgCycleKind::Hypre
                                       : AmgCycleKind::Automatic;
    }
    if (s.has("chebyshev_order")) {
      p.solver.chebyshevOrder = count("chebyshev_order", 1);
      if (p.solver.chebyshevOrder > 4)
        s["chebyshev_order"].fail("the Chebyshev smoother's order must be 1 to 4");
    }
    if (s.has("coarsest_size"))
      p.solver.coarsestSize = count("coarsest_size", 1);
    if (s.has("smoother")) {
      const std::string v =
          s["smoother"].choice({"auto", "l1_gauss_seidel", "l1_jacobi", "chebyshev"});
      p.solver.smoother = v == "l1_jacobi"         ? AmgSmoother::L1Jacobi
                          : v == "chebyshev"       ? AmgSmoother::Chebyshev
                          : v == "l1_gauss_seidel" ? AmgSmoother::L1GaussSeidel
                                                   : AmgSmoother::Automatic;
    }
    if (s.has("reuse_hierarchy"))
      p.solver.reuseHierarchy = s["reuse_hierarchy"].boolean();
    if (s.has("reuse_factorization"))
      p.solver.reuseFactorization = s["reuse_factorization"].boolean();
    if (s.has("coarse_space")) {
      const std::string v = s["coarse_space"].choice({"none", "auto", "rigid_body"});
      p.solver.coarseSpace = v == "none"         ? CoarseSpace::None
                             : v == "rigid_body" ? CoarseSpace::RigidBody
                                                 : CoarseSpace::OnStall;
    }
    if (s.has("direct_fallback") && !s["direct_fallback"].boolean())
      p.solver.directFallbackUnknowns = 0;
    if (s.has("direct_when_cheaper")) {
      if (mixed && !drivenMixed && !solidMixed)
        s["direct_when_cheaper"].fail(
            "direct_when_cheaper applies to the displacement models, the geometrically nonlinear "
            "2D mixed model (or the linear one with stages or contact) and the 3D mixed models, "
            "which have a direct fall back; the linear 2D mixed model's AMG solve has none");
      p.solver.directWhenCheaper = s["direct_when_cheaper"].boolean();
    }
  }

  if (solidDisplacement && p.solver.type == LinearSolverType::Amg)
    thicknessDefaults(top, p);
  if (const auto why = rules::mixedContactSolver(p.model.formulation == Formulation::Mixed,
                                                 !p.contact.empty(), p.solver.type))
    top["solver"]["type"].fail(*why);
}

void readVerification(const YamlItem &v, Problem &p) {
  v.requireMap();
  auto &s = p.verification;
  s.type = v.required("type").choice({"lame_cylinder", "lame_sphere", "cantilever"});
  if (v.has("tolerance"))
    s.tolerance = v["tolerance"].positive();
  if (s.type == "lame_sphere" && p.mesh.dim() == 2)
    v["type"].fail("lame_sphere is the 3D closed form (a thick-walled sphere); this mesh is 2D");
  if (s.type == "lame_cylinder" && p.mesh.dim() == 3) {
    // The 3D form is the plane-strain slice of a cylinder along z: both end faces held in z.
    const Mesh &mesh = p.mesh;
    double zlo = mesh.z(0), zhi = mesh.z(0);
    for (LocalIndex n = 0; n < mesh.numNodes(); ++n) {
      zlo = std::min(zlo, mesh.z(n));
      zhi = std::max(zhi, mesh.z(n));
    }
    std::vector<char> held(mesh.numNodes(), 0);
    for (const DirichletSpec &d : p.dirichlet)
      if (d.uz && *d.uz == 0.0)
        for (LocalIndex n : mesh.nodesOf(d.target))
          held[n] = 1;
    const double tol = 1e-9 * std::max(1.0, zhi - zlo);
    for (LocalIndex n = 0; n < mesh.numNodes(); ++n)
      if ((std::abs(mesh.z(n) - zlo) < tol || std::abs(mesh.z(n) - zhi) < tol) && !held[n])
        v["type"].fail("lame_cylinder on a 3D mesh is the plane-strain slice of a cylinder along "
                       "z: hold both end faces in z (uz: 0 at z = " +
                       std::to_string(zlo) + " and z = " + std::to_string(zhi) + "); node " +
                       std::to_string(mesh.nodeId(n)) + " is free in z");
  }
  if (s.type == "lame_cylinder" || s.type == "lame_sphere") {
    v.allowOnly(
        {"type", "tolerance", "inner_radius", "outer_radius", "inner_pressure", "outer_pressure"});
    s.innerRadius = v.required("inner_radius").positive();
    s.outerRadius = v.required("outer_radius").positive();
    s.innerPressure = v.required("inner_pressure").number();
    s.outerPressure = v.has("outer_pressure") ? v["outer_pressure"].number() : 0.0;
  } else {
    if (p.mesh.dim() == 3)
      v.allowOnly({"type", "tolerance", "length", "height", "width", "load", "tip"});
    else
      v.allowOnly({"type", "tolerance", "length", "height", "load", "tip"});
    s.length = v.required("length").positive();
    s.height = v.required("height").positive();
    if (p.mesh.dim() == 3) // 2D: the width is the model's thickness
      s.width = v.required("width").positive();
    s.load = v.required("load").number();
    s.tipNodeSet = v.required("tip").string();
    checkTarget(p.mesh, v["tip"], s.tipNodeSet);
  }
  if (p.materials.size() != 1 || p.materials[0].type != "isotropic")
    v.fail("closed-form verification needs a single isotropic material");
  if (p.model.geometricNonlinearity)
    v.fail("the closed forms of verification are linear; run without geometric_nonlinearity "
           "(the nonlinear cantilever is checked by examples/cantilever_study.py and the "
           "validation tests)");
}

} // namespace mixcon::detail
