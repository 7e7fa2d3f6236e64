// Problem files: a valid file parses; each kind of bad input gives its documented error (with
// file:line), and `mixcon run` exits with code 2 on it; a run writes HDF5 + XDMF + summary.json.
#include <io/Problem.hpp>
#include <solver/Rules.hpp>

#include <support/Program.hpp>

#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <sys/stat.h>
#include <sys/wait.h>

using namespace mixcon;
namespace fs = std::filesystem;

namespace {

const char *kGood = R"(mesh:
  generator: {type: rectangle, size: [10, 1], divisions: [20, 2], element: quad8}
model: {formulation: displacement, analysis: plane_stress, thickness: 0.5}
materials:
  - {region: body, type: orthotropic, E1: 1.6e6, E2: 1.1e5, G12: 1.0e5, nu12: 0.4, angle: 30}
boundary_conditions:
  - {boundary: left, ux: 0, uy: 0}
loads:
  - {boundary: right, traction: [0, -1.0]}
  - {boundary: top, pressure: 2.0}
  - {node_set: top_right, force: [0, -100]}
  - {region: body, body_force: [0, -0.1]}
steps: {load_factors: [0.5, 1.0]}
solver: {type: direct}
output: {directory: somewhere}
)";

// A Quad4 Gmsh mesh whose second element is a bow-tie (nodes 3 4 5 6: two edges cross), which no
// reordering makes valid.
const char *kInvertedMsh = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Nodes
1 6 1 6
2 1 0 6
1
2
3
4
5
6
0 0 0
0 1 0
1 0 0
1 1 0
2 0 0
2 1 0
$EndNodes
$Elements
1 2 1 2
2 1 3 2
1 1 3 4 2
2 3 4 5 6
$EndElements
)";

// Two Quad4 elements on [0,2]x[0,1], the second written clockwise (nodes 3 4 6 5), as Gmsh writes
// a surface drawn clockwise; a physical curve "left" (x = 0), a physical point "tip" (2, 1), and
// two physical groups without elements: the curve "unused" and the point "nowhere".
const char *kGroupsMsh = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
5
0 3 "tip"
0 8 "nowhere"
1 1 "left"
1 7 "unused"
2 2 "plate"
$EndPhysicalNames
$Entities
1 1 1 0
1 2 1 0 1 3
1 0 0 0 0 1 0 1 1 2 1 -1
1 0 0 0 2 1 0 1 2 0
$EndEntities
$Nodes
3 6 1 6
0 1 0 1
6
2 1 0
1 1 0 2
1
2
0 0 0
0 1 0
2 1 0 3
3
4
5
1 0 0
1 1 0
2 0 0
$EndNodes
$Elements
3 4 1 4
0 1 15 1
1 6
1 1 1 1
2 1 2
2 1 3 2
3 1 3 4 2
4 3 4 6 5
$EndElements
)";

// A problem on kGroupsMsh: the plate clamped on the left, pulled down at its tip.
const char *kGroups = R"(mesh: {file: groups.msh}
model: {formulation: displacement, analysis: plane_stress}
materials:
  - {region: plate, type: isotropic, E: 1000, nu: 0.3}
boundary_conditions:
  - {boundary: left, ux: 0, uy: 0}
loads:
  - {node_set: tip, force: [0, -1]}
solver: {type: direct}
output: {directory: somewhere}
)";

struct BadCase {
  const char *name;
  std::string yaml;
  std::string expected; ///< substring of the message
  int line;             ///< expected line in "file:line:" (0: not checked)
};

std::string replace(std::string s, const std::string &from, const std::string &to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

// The mesh line of kGood, replaced by the cases that change the mesh.
const char *kGenerator =
    "generator: {type: rectangle, size: [10, 1], divisions: [20, 2], element: quad8}";

std::vector<BadCase> badCases() {
  const std::string g = kGood;
  return {
      {"unknown_key", replace(g, "thickness: 0.5", "thicknes: 0.5"), "unknown key 'thicknes'", 3},
      {"missing_mesh_file", replace(g, kGenerator, "file: does-not-exist.msh"),
       "cannot open the mesh file", 2},
      {"unknown_region", replace(g, "region: body, type", "region: wood, type"),
       "unknown region 'wood'", 5},
      {"unsupported_element", replace(g, "element: quad8", "element: tri3"),
       "unsupported element 'tri3'", 2},
      {"wrong_element_order", replace(g, kGenerator, "{file: inverted.msh, element: quad8}"),
       "the mesh file has quad4 elements but the problem asks for quad8", 0},
      {"region_without_material",
       replace(g,
               "  - {region: body, type: orthotropic, E1: 1.6e6, E2: 1.1e5, G12: 1.0e5, nu12: 0.4, "
               "angle: 30}\n",
               ""),
       "has no material", 0},
      {"no_dirichlet", replace(g, "  - {boundary: left, ux: 0, uy: 0}\n", ""),
       "no Dirichlet condition anywhere", 0},
      {"unknown_boundary", replace(g, "{boundary: left, ux", "{boundary: clamp, ux"),
       "unknown boundary or node set 'clamp'", 7},
      {"negative_jacobian", replace(g, kGenerator, "file: inverted.msh"),
       "element 2 has a non-positive Jacobian", 0},
      {"condition_on_empty_boundary",
       replace(kGroups, "{boundary: left, ux: 0, uy: 0}", "{boundary: unused, ux: 0, uy: 0}"),
       "boundary 'unused' is empty", 6},
      {"force_on_empty_node_set", replace(kGroups, "{node_set: tip,", "{node_set: nowhere,"),
       "node set 'nowhere' is empty", 8},
      {"traction_on_empty_boundary",
       replace(kGroups, "{node_set: tip, force: [0, -1]}", "{boundary: unused, traction: [1, 0]}"),
       "boundary 'unused' is empty", 8},
      {"contact_on_empty_boundary",
       replace(kGroups, "solver: {type: direct}",
               "contact:\n  - {type: rigid_half_plane, boundary: unused, point: [0, -1], normal: "
               "[0, 1]}\nsolver: {type: direct}"),
       "boundary 'unused' is empty", 10},
      {"rigid_circle_inside_the_body",
       replace(g, "output: {directory: somewhere}",
               "contact:\n  - {type: rigid_circle, boundary: top, center: [5, 1.5], radius: 1}\n"
               "output: {directory: somewhere}"),
       "the rigid_circle starts inside the body: node ", 16},
      {"rigid_half_plane_inside_the_body",
       replace(g, "output: {directory: somewhere}",
               "contact:\n  - {type: rigid_half_plane, boundary: bottom, point: [0, 0.1], normal: "
               "[0, 1]}\noutput: {directory: somewhere}"),
       "the rigid_half_plane starts inside the body: node ", 16},
      {"overlapping_bodies",
       "mesh:\n  bodies:\n    - {name: a, generator: {type: rectangle, size: [1, 1], divisions: "
       "[2, "
       "2]}}\n    - {name: b, generator: {type: rectangle, size: [1, 1], divisions: [2, 2]}, "
       "offset: [0.3, 0.2]}\nmaterials:\n  - {region: a, type: isotropic, E: 1, nu: 0.3}\n  - "
       "{region: b, type: isotropic, E: 1, nu: 0.3}\nboundary_conditions:\n  - {boundary: "
       "a.left, ux: 0, uy: 0}\n",
       "' at the start: node ", 0},
      {"malformed_yaml",
       replace(g, "steps: {load_factors: [0.5, 1.0]}", "steps: {load_factors: [0.5, 1.0}"),
       "malformed YAML", 0},
      {"bad_number", replace(g, "nu12: 0.4", "nu12: zero"), "expected a number, found 'zero'", 5},
      {"indefinite_material", replace(g, "nu12: 0.4", "nu12: 4.0"), "not positive definite", 5},
      {"mixed_lumped_quad8",
       replace(g, "formulation: displacement", "formulation: mixed, compliance: lumped"),
       "compliance: lumped is not available for quad8", 3},
      {"mixed_unstable_pairing",
       replace(g, "formulation: displacement", "formulation: mixed, stress_element: quad4"),
       "Mirza-Olson", 3},
      {"mixed_key_on_displacement",
       replace(g, "thickness: 0.5", "thickness: 0.5, stabilization: 0"),
       "applies to formulation: mixed only", 3},
      {"bad_stabilization",
       replace(g, "formulation: displacement", "formulation: mixed, stabilization: 1.5"),
       "stabilization must lie in [0, 1)", 3},
      {"unknown_preconditioner",
       replace(replace(g, "formulation: displacement", "formulation: mixed"),
               "solver: {type: direct}", "solver: {type: amg, preconditioner: jacobi}"),
       "unknown value 'jacobi'", 14},
      {"nonlinear_key_on_linear",
       replace(g, "steps: {load_factors: [0.5, 1.0]}",
               "steps: {load_factors: [0.5, 1.0], iteration: newton}"),
       "applies to geometrically nonlinear or contact analyses", 13},
      {"unknown_iteration",
       replace(replace(g, "thickness: 0.5", "thickness: 0.5, geometric_nonlinearity: true"),
               "steps: {load_factors: [0.5, 1.0]}",
               "steps: {load_factors: [0.5, 1.0], iteration: secant}"),
       "unknown value 'secant'", 13},
      {"follower_on_traction",
       replace(replace(g, "thickness: 0.5", "thickness: 0.5, geometric_nonlinearity: true"),
               "traction: [0, -1.0]}", "traction: [0, -1.0], follower: true}"),
       "follower applies to pressures only", 9},
      {"follower_on_linear", replace(g, "pressure: 2.0}", "pressure: 2.0, follower: true}"),
       "follower pressure needs model: geometric_nonlinearity: true", 10},
      {"contact_unknown_boundary",
       replace(g, "output: {directory: somewhere}",
               "contact:\n  - {type: rigid_circle, boundary: hole, center: [0, 0], radius: 1}\n"
               "output: {directory: somewhere}"),
       "unknown boundary 'hole'", 16},
      {"contact_drive_component_twice",
       replace(g, "output: {directory: somewhere}",
               "contact:\n  - {type: rigid_circle, boundary: top, center: [0, 2], radius: 1, "
               "drive: {force: [0, 1], displacement: [0, null]}}\noutput: {directory: "
               "somewhere}"),
       "component x of the drive must be given exactly once", 16},
      {"contact_drive_component_missing",
       replace(g, "output: {directory: somewhere}",
               "contact:\n  - {type: rigid_circle, boundary: top, center: [0, 2], radius: 1, "
               "drive: {force: [null, 1]}}\noutput: {directory: somewhere}"),
       "component x of the drive must be given exactly once", 16},
      {"contact_status_from_on_displacement",
       replace(g, "output: {directory: somewhere}",
               "contact:\n  - {type: rigid_circle, boundary: top, center: [0, 2], radius: 1, "
               "status_from: forces}\noutput: {directory: somewhere}"),
       "status_from applies to formulation: mixed", 16},
      {"elastic_law_on_linear",
       replace(g, "thickness: 0.5", "thickness: 0.5, elastic_law: saint_venant_kirchhoff"),
       "elastic_law applies to formulation: displacement with geometric_nonlinearity", 3},
      {"elastic_law_with_report_tangent",
       replace(replace(g, "thickness: 0.5",
                       "thickness: 0.5, geometric_nonlinearity: true, elastic_law: "
                       "saint_venant_kirchhoff"),
               "steps: {load_factors: [0.5, 1.0]}",
               "steps: {load_factors: [0.5, 1.0], tangent: report}"),
       "use the exact tangent", 13},
      {"pinned_plate_too_narrow",
       replace(g, kGenerator,
               "generator: {type: pinned_plate, hole_radius: 0.5, half_width: 0.8, "
               "end_distance: 4, length: 8, divisions: [4, 6, 4, 9]}"),
       "half_width must exceed", 0},
      {"contact_negative_friction",
       replace(g, "output: {directory: somewhere}",
               "contact:\n  - {type: rigid_half_plane, boundary: bottom, point: [0, 0], normal: "
               "[0, 1], friction: -0.1}\noutput: {directory: somewhere}"),
       "friction coefficient must be 0 or positive", 16},
      {"contact_mixed_linear_operators",
       replace(replace(g, "formulation: displacement", "formulation: mixed, operators: assembled"),
               "output: {directory: somewhere}",
               "contact:\n  - {type: rigid_half_plane, boundary: bottom, point: [0, 0], normal: "
               "[0, 1]}\noutput: {directory: somewhere}"),
       "operators applies to the linear mixed model without contact or stages", 3},
      {"contact_mixed_linear_krylov",
       replace(replace(replace(g, "formulation: displacement", "formulation: mixed"),
                       "solver: {type: direct}", "solver: {type: direct, krylov: gmres}"),
               "output: {directory: somewhere}",
               "contact:\n  - {type: rigid_half_plane, boundary: bottom, point: [0, 0], normal: "
               "[0, 1]}\noutput: {directory: somewhere}"),
       "krylov applies to the linear mixed model's Schur solver only (not with "
       "geometric_nonlinearity, contact or stages)",
       14},
      {"contact_mixed_amg",
       replace(replace(replace(g, "formulation: displacement",
                               "formulation: mixed, geometric_nonlinearity: true"),
                       "solver: {type: direct}", "solver: {type: amg}"),
               "output: {directory: somewhere}",
               "contact:\n  - {type: rigid_half_plane, boundary: bottom, point: [0, 0], normal: "
               "[0, 1]}\noutput: {directory: somewhere}"),
       "solver.type: contact with the mixed model needs type: direct in this version", 14},
      {"nonlinear_mixed_compliance",
       replace(g, "formulation: displacement",
               "formulation: mixed, geometric_nonlinearity: true, compliance: lumped"),
       "compliance applies to the linear mixed model's Schur solver; the geometrically nonlinear "
       "mixed model uses the consistent M and equal-order interpolation",
       3},
      {"mixed_newton_method_on_displacement",
       replace(g, "solver: {type: direct}", "solver: {type: amg, method: schur}"),
       "method applies to the mixed model's solver: amg only", 14},
      {"stress_update_on_current_form",
       replace(g, "formulation: displacement",
               "formulation: mixed, geometric_nonlinearity: true, stress_update: projected"),
       "stress_update applies to mixed_form: incremental only", 3},
      // Repeated keys (yaml-cpp keeps both pairs; a lookup took the first): block and flow style,
      // top level and nested, each naming both lines.
      {"duplicate_key_block",
       replace(g, "output: {directory: somewhere}", "output:\n  directory: a\n  directory: b"),
       "output: key 'directory' given twice (first at line 16)", 17},
      {"duplicate_key_flow", replace(g, "nu12: 0.4,", "nu12: 0.4, nu12: 0.3,"),
       "materials[0]: key 'nu12' given twice (first at line 5, column", 5},
      {"duplicate_top_level_key",
       replace(g, "solver: {type: direct}", "solver: {type: direct}\nsolver: {type: amg}"),
       "key 'solver' given twice (first at line 14)", 15},
      // Conflicting Dirichlet values (the last one used to win), on one set and on two sets
      // sharing a node (left and bottom share the corner).
      {"conflicting_conditions_same_boundary",
       replace(g, "  - {boundary: left, ux: 0, uy: 0}\n",
               "  - {boundary: left, ux: 0, uy: 0}\n  - {boundary: left, ux: 0.1}\n"),
       "boundary_conditions[1] (line 8, on 'left') prescribes ux = 0.1 at node 1 but "
       "boundary_conditions[0] (line 7, on 'left') prescribes ux = 0 there",
       8},
      {"conflicting_conditions_shared_node",
       replace(g, "  - {boundary: left, ux: 0, uy: 0}\n",
               "  - {boundary: left, ux: 0, uy: 0}\n  - {boundary: bottom, uy: -0.5}\n"),
       "(line 8, on 'bottom') prescribes uy = -0.5 at node 1 but boundary_conditions[0] (line 7, "
       "on 'left') prescribes uy = 0 there: conflicting boundary conditions",
       8},
      // Counts and ranges of the solver section (0 iterations used to "converge").
      {"solver_max_iterations_zero",
       replace(g, "solver: {type: direct}", "solver: {type: amg, max_iterations: 0}"),
       "solver.max_iterations: must be at least 1", 14},
      {"solver_max_iterations_negative",
       replace(g, "solver: {type: direct}", "solver: {type: amg, max_iterations: -1}"),
       "solver.max_iterations: must be at least 1", 14},
      {"solver_aggressive_levels_negative",
       replace(g, "solver: {type: direct}", "solver: {type: amg, aggressive_levels: -2}"),
       "solver.aggressive_levels: must be at least 0", 14},
      {"solver_print_level_negative",
       replace(g, "solver: {type: direct}", "solver: {type: amg, print_level: -1}"),
       "solver.print_level: must be at least 0", 14},
      {"solver_interpolation_max_elements_negative",
       replace(g, "solver: {type: direct}", "solver: {type: amg, interpolation_max_elements: -4}"),
       "solver.interpolation_max_elements: must be at least 0", 14},
      {"solver_strong_threshold_out_of_range",
       replace(g, "solver: {type: direct}", "solver: {type: amg, strong_threshold: 1.5}"),
       "solver.strong_threshold: the AMG strength threshold must lie in [0, 1)", 14},
      // Files that are not regular files are refused by stat before anything is read.
      {"mesh_file_is_a_directory", replace(g, kGenerator, "file: ."),
       "the mesh file is a directory, not a regular file", 2},
      // A long value is echoed cut to 80 characters.
      {"long_value_clipped", replace(g, "nu12: 0.4", "nu12: " + std::string(100000, 'x')),
       "expected a number, found '" + std::string(77, 'x') + "...'", 5},
  };
}

class TempDir {
public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("mixcon-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter_++));
    fs::create_directories(path_);
    std::ofstream(path_ / "inverted.msh") << kInvertedMsh;
    std::ofstream(path_ / "groups.msh") << kGroupsMsh;
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path &path() const { return path_; }

private:
  fs::path path_;
  static inline int counter_ = 0;
};

} // namespace

TEST(Problem, ParsesValidFile) {
  const Problem p = parseProblem(kGood, "good.yaml", "");
  EXPECT_EQ(p.mesh.elementType, ElementType::Quad8);
  EXPECT_EQ(p.mesh.numElements(), 40);
  EXPECT_DOUBLE_EQ(p.model.thickness, 0.5);
  ASSERT_EQ(p.materials.size(), 1u);
  EXPECT_GT(std::abs(p.materials[0].stiffness.m[0][2]), 0.0); // 30 degrees: C16 != 0
  EXPECT_EQ(p.loads.size(), 4u);
  EXPECT_EQ(p.loads[1].kind, LoadKind::Pressure);
  EXPECT_EQ(p.loadFactors, (std::vector<double>{0.5, 1.0}));
  EXPECT_EQ(p.solver.type, LinearSolverType::Direct);
  EXPECT_EQ(p.outputDirectory, "somewhere");
}

TEST(Problem, ParsesMixedFormulation) {
  std::string y = replace(kGood, "formulation: displacement",
                          "formulation: mixed, compliance: consistent, stabilization: 0.2");
  y = replace(
      y, "solver: {type: direct}",
      "solver: {type: amg, krylov: gmres, preconditioner: stiffness, inner_tolerance: 1e-9}");
  const Problem p = parseProblem(y, "mixed.yaml", "");
  EXPECT_EQ(p.model.formulation, Formulation::Mixed);
  EXPECT_EQ(p.model.mixed.compliance, ComplianceMass::Consistent);
  EXPECT_DOUBLE_EQ(p.model.mixed.stabilization, 0.2);
  EXPECT_EQ(p.model.mixed.krylov, KrylovMethod::Gmres);
  EXPECT_EQ(p.model.mixed.preconditioner, SchurPreconditioner::Stiffness);
  EXPECT_DOUBLE_EQ(p.model.mixed.innerTolerance, 1e-9);
  EXPECT_EQ(p.solver.type, LinearSolverType::Amg);
}

TEST(Problem, LinearMixedMethodKeysAndTheirRefusals) {
  const std::string y = replace(kGood, "formulation: displacement", "formulation: mixed");
  const auto parse = [&](const std::string &solver) {
    return parseProblem(replace(y, "solver: {type: direct}", solver), "mixed.yaml", "");
  };
  EXPECT_EQ(parse("solver: {type: amg}").model.mixed.method, MixedLinearMethod::Auto);
  Problem p = parse("solver: {type: amg, method: block_triangular, stress_block_tolerance: 1e-3}");
  EXPECT_EQ(p.model.mixed.method, MixedLinearMethod::BlockTriangular);
  EXPECT_DOUBLE_EQ(p.model.mixed.preconditionerTolerance, 1e-3);
  EXPECT_EQ(parse("solver: {type: amg, method: schur}").model.mixed.method,
            MixedLinearMethod::Schur);
  // The Schur method's own keys select it when no method is named.
  p = parse("solver: {type: amg, krylov: gmres}");
  EXPECT_EQ(p.model.mixed.method, MixedLinearMethod::Schur);
  EXPECT_EQ(parse("solver: {type: amg, inner_tolerance: 1e-9}").model.mixed.method,
            MixedLinearMethod::Schur);
  const auto refused = [&](const std::string &solver, const std::string &model,
                           const std::string &part) {
    try {
      // (Quad4: lumped M is refused on Quad8 before the solver section is read.)
      parseProblem(replace(replace(replace(y, "formulation: mixed", model), "element: quad8",
                                   "element: quad4"),
                           "solver: {type: direct}", solver),
                   "mixed.yaml", "");
      ADD_FAILURE() << "no error for " << solver;
    } catch (const InputError &e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind("mixed.yaml:", 0), 0u) << msg;
      EXPECT_NE(msg.find(part), std::string::npos) << msg;
    }
  };
  const std::string mixed = "formulation: mixed";
  refused("solver: {type: amg, method: block_triangular, krylov: cg}", mixed,
          "krylov applies to the linear mixed model's method: schur");
  refused("solver: {type: amg, method: block_triangular, inner_tolerance: 1e-9}", mixed,
          "inner_tolerance applies to the linear mixed model's method: schur");
  refused("solver: {type: amg, stress_block_tolerance: 1e-3, krylov: gmres}", mixed,
          "krylov applies to the linear mixed model's method: schur");
  refused("solver: {type: amg, method: schur, stress_block_tolerance: 1e-3}", mixed,
          "stress_block_tolerance applies to method: block_triangular");
  refused("solver: {type: amg, stress_block_tolerance: 1e-3}",
          "formulation: mixed, compliance: lumped",
          "stress_block_tolerance applies to compliance: consistent");
  refused("solver: {type: amg, method: bramble}", mixed, "method");
}

TEST(Problem, ParsesNonlinearMixedSolver) {
  std::string y = replace(kGood, "formulation: displacement",
                          "formulation: mixed, geometric_nonlinearity: true");
  y = replace(y, "solver: {type: direct}",
              "solver: {type: amg, method: schur, stress_block_tolerance: 1e-3}");
  Problem p = parseProblem(y, "mixed.yaml", "");
  EXPECT_EQ(p.solver.type, LinearSolverType::Amg);
  EXPECT_EQ(p.model.mixedNewton.method, MixedNewtonSolver::Schur);
  EXPECT_DOUBLE_EQ(p.model.mixedNewton.preconditionerTolerance, 1e-3);
  p = parseProblem(replace(y, ", method: schur, stress_block_tolerance: 1e-3", ""), "mixed.yaml",
                   "");
  EXPECT_EQ(p.model.mixedNewton.method, MixedNewtonSolver::BlockTriangular);
  EXPECT_EQ(p.model.mixedNewton.jacobian, JacobianForm::Automatic);
}

TEST(Problem, NonlinearMixedMatrixFreeJacobianKeyIsCheckedWhereItCannotBeTaken) {
  std::string y = replace(kGood, "formulation: displacement",
                          "formulation: mixed, geometric_nonlinearity: true");
  y = replace(y, "pressure: 2.0}", "pressure: 2.0, follower: false}");
  const auto expectInputError = [](const std::string &yaml, const std::string &prefix,
                                   const std::string &part) {
    try {
      parseProblem(yaml, "mixed.yaml", "");
      ADD_FAILURE() << "no error for " << part;
    } catch (const InputError &e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(prefix, 0), 0u) << msg;
      EXPECT_NE(msg.find(part), std::string::npos) << msg;
    }
  };
  const std::string amg =
      replace(y, "solver: {type: direct}", "solver: {type: amg, jacobian: matrix_free}");
  EXPECT_EQ(parseProblem(amg, "mixed.yaml", "").model.mixedNewton.jacobian,
            JacobianForm::MatrixFree);
  EXPECT_EQ(parseProblem(replace(amg, "matrix_free", "assembled"), "mixed.yaml", "")
                .model.mixedNewton.jacobian,
            JacobianForm::Assembled);
  EXPECT_EQ(parseProblem(replace(amg, "matrix_free", "auto"), "mixed.yaml", "")
                .model.mixedNewton.jacobian,
            JacobianForm::Automatic);
  expectInputError(replace(amg, "jacobian: matrix_free", "jacobian: matrix_free, method: schur"),
                   "mixed.yaml:", "needs method: block_triangular");
  expectInputError(replace(amg, "matrix_free", "sparse"), "mixed.yaml:", "jacobian");
  expectInputError(replace(amg, "type: amg", "type: direct"), "mixed.yaml:", "needs type: amg");
  expectInputError(replace(amg, ", follower: false}", "}"), "mixed.yaml:", "follower");
  expectInputError(
      replace(kGood, "solver: {type: direct}", "solver: {type: amg, jacobian: matrix_free}"),
      "mixed.yaml:", "jacobian applies to the geometrically nonlinear mixed");
}

TEST(Problem, DirectWhenCheaperKey) {
  const std::string amg = replace(kGood, "solver: {type: direct}", "solver: {type: amg}");
  EXPECT_TRUE(parseProblem(amg, "a.yaml", "").solver.directWhenCheaper);
  const std::string off =
      replace(amg, "solver: {type: amg}", "solver: {type: amg, direct_when_cheaper: false}");
  EXPECT_FALSE(parseProblem(off, "a.yaml", "").solver.directWhenCheaper);
  try {
    parseProblem(replace(off, "formulation: displacement", "formulation: mixed"), "m.yaml", "");
    ADD_FAILURE() << "direct_when_cheaper accepted for the mixed model";
  } catch (const InputError &e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("m.yaml:", 0), 0u) << msg;
    EXPECT_NE(msg.find("the linear 2D mixed model's AMG solve has none"), std::string::npos) << msg;
  }
  // The geometrically nonlinear mixed model falls back to the LU of its Jacobian: accepted.
  std::string nonlinear =
      replace(off, "formulation: displacement", "formulation: mixed, geometric_nonlinearity: true");
  nonlinear = replace(nonlinear, "pressure: 2.0}", "pressure: 2.0, follower: false}");
  EXPECT_FALSE(parseProblem(nonlinear, "m.yaml", "").solver.directWhenCheaper);
  // So does the linear 3D mixed model, to the LU of its operator.
  const std::string solid =
      "mesh:\n  generator: {type: box, size: [4, 1, 1], divisions: [4, 1, 1], element: hex8}\n"
      "model: {formulation: mixed}\n"
      "materials:\n  - {region: body, type: isotropic, E: 1.0e4, nu: 0.3}\n"
      "boundary_conditions:\n  - {boundary: xmin, ux: 0, uy: 0, uz: 0}\n"
      "loads:\n  - {boundary: xmax, traction: [0, -1, 0]}\n"
      "solver: {type: amg, direct_when_cheaper: false}\n";
  EXPECT_FALSE(parseProblem(solid, "s.yaml", "").solver.directWhenCheaper);
  EXPECT_TRUE(parseProblem(replace(solid, ", direct_when_cheaper: false", ""), "s.yaml", "")
                  .solver.directWhenCheaper);
}

TEST(Problem, ParsesNonlinearSteps) {
  std::string y = replace(kGood, "thickness: 0.5", "thickness: 0.5, geometric_nonlinearity: true");
  y = replace(y, "steps: {load_factors: [0.5, 1.0]}",
              "steps: {increments: 4, iteration: modified_newton, tolerance: 1e-4, "
              "residual_tolerance: 1e-7, max_iterations: 12, max_cuts: 3}");
  y = replace(y, "pressure: 2.0}", "pressure: 2.0, follower: false}");
  const Problem p = parseProblem(y, "nonlinear.yaml", "");
  EXPECT_TRUE(p.model.geometricNonlinearity);
  EXPECT_EQ(p.nonlinear.method, IterationMethod::ModifiedNewton);
  EXPECT_DOUBLE_EQ(p.nonlinear.tolerance, 1e-4);
  EXPECT_DOUBLE_EQ(p.nonlinear.residualTolerance, 1e-7);
  EXPECT_EQ(p.nonlinear.maxIterations, 12);
  EXPECT_EQ(p.nonlinear.maxCuts, 3);
  EXPECT_EQ(p.loadFactors, (std::vector<double>{0.25, 0.5, 0.75, 1.0}));
  EXPECT_FALSE(p.loads[1].follower);
  // The nonlinear mixed model defaults to the direct solver.
  const Problem m =
      parseProblem(replace(replace(kGood, "formulation: displacement",
                                   "formulation: mixed, geometric_nonlinearity: true"),
                           "solver: {type: direct}\n", ""),
                   "m.yaml", "");
  EXPECT_EQ(m.solver.type, LinearSolverType::Direct);
  EXPECT_TRUE(m.loads[1].follower);
  // So does the linear mixed model in contact (the only solver there), not without contact.
  const std::string contact =
      "contact:\n  - {type: rigid_half_plane, boundary: bottom, point: [0, 0], normal: [0, 1]}\n";
  const std::string linearMixed =
      replace(replace(kGood, "formulation: displacement", "formulation: mixed"),
              "solver: {type: direct}\n", "");
  EXPECT_EQ(parseProblem(linearMixed + contact, "c.yaml", "").solver.type,
            LinearSolverType::Direct);
  EXPECT_EQ(parseProblem(linearMixed, "l.yaml", "").solver.type, LinearSolverType::Amg);
}

TEST(Problem, BadInputGivesDocumentedErrors) {
  TempDir dir;
  for (const auto &c : badCases()) {
    try {
      parseProblem(c.yaml, "case.yaml", dir.path().string());
      ADD_FAILURE() << c.name << ": no error";
    } catch (const InputError &e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(c.expected), std::string::npos) << c.name << ": " << msg;
      if (c.line > 0) {
        EXPECT_EQ(msg.rfind("case.yaml:" + std::to_string(c.line) + ":", 0), 0u)
            << c.name << ": " << msg;
      }
    }
  }
}

// The rules between options that the solver layer defines (solver/Rules.hpp) are the reader's:
// each bad combination is refused with the rule's own message after the key's file:line and path,
// and each rule lets the neighbouring allowed combination through.
TEST(Problem, CrossOptionRulesAreTheSolverLayersRules) {
  const std::string g = kGood;
  const std::string contact = "contact:\n  - {type: rigid_half_plane, boundary: bottom, point: [0, "
                              "0], normal: [0, 1]}\noutput: {directory: somewhere}";
  struct RuleCase {
    const char *name;
    std::string yaml;
    std::optional<std::string> rule;
    std::string where; ///< "file:line:column: path: " of the offending key
  };
  const std::vector<RuleCase> cases = {
      {"stabilization",
       replace(g, "formulation: displacement", "formulation: mixed, stabilization: 1"),
       rules::stabilizationRange(1.0), "case.yaml:3:"},
      {"lumped_compliance",
       replace(g, "formulation: displacement", "formulation: mixed, compliance: lumped"),
       rules::lumpedCompliance(ComplianceMass::Lumped, ElementType::Quad8), "case.yaml:3:"},
      {"report_tangent_law",
       replace(replace(g, "thickness: 0.5",
                       "thickness: 0.5, geometric_nonlinearity: true, elastic_law: "
                       "saint_venant_kirchhoff"),
               "steps: {load_factors: [0.5, 1.0]}",
               "steps: {load_factors: [0.5, 1.0], tangent: report}"),
       rules::reportTangentLaw(TangentKind::Report, ElasticLaw::SaintVenantKirchhoff),
       "case.yaml:13:"},
      {"mixed_contact_solver",
       replace(replace(replace(g, "formulation: displacement",
                               "formulation: mixed, geometric_nonlinearity: true"),
                       "solver: {type: direct}", "solver: {type: amg}"),
               "output: {directory: somewhere}", contact),
       rules::mixedContactSolver(true, true, LinearSolverType::Amg), "case.yaml:14:"},
      {"iteration_limit",
       replace(g, "solver: {type: direct}", "solver: {type: amg, max_iterations: 0}"),
       rules::iterationLimit(0), "case.yaml:14:"},
  };
  for (const auto &c : cases) {
    ASSERT_TRUE(c.rule) << c.name << ": the rule lets the bad combination through";
    try {
      parseProblem(c.yaml, "case.yaml", "");
      ADD_FAILURE() << c.name << ": no error";
    } catch (const InputError &e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(c.where, 0), 0u) << c.name << ": " << msg;
      ASSERT_GE(msg.size(), c.rule->size()) << c.name << ": " << msg;
      EXPECT_EQ(msg.substr(msg.size() - c.rule->size()), *c.rule) << c.name << ": " << msg;
    }
  }
  // The allowed neighbours.
  EXPECT_FALSE(rules::stabilizationRange(0.0));
  EXPECT_FALSE(rules::stabilizationRange(0.999));
  EXPECT_TRUE(rules::stabilizationRange(-1e-12));
  EXPECT_FALSE(rules::lumpedCompliance(ComplianceMass::Lumped, ElementType::Quad4));
  EXPECT_FALSE(rules::lumpedCompliance(ComplianceMass::Consistent, ElementType::Quad8));
  EXPECT_FALSE(rules::reportTangentLaw(TangentKind::Report, ElasticLaw::Almansi));
  EXPECT_FALSE(rules::reportTangentLaw(TangentKind::Exact, ElasticLaw::SaintVenantKirchhoff));
  EXPECT_FALSE(rules::mixedContactSolver(true, true, LinearSolverType::Direct));
  EXPECT_FALSE(rules::mixedContactSolver(false, true, LinearSolverType::Amg));
  EXPECT_FALSE(rules::mixedContactSolver(true, false, LinearSolverType::Amg));
  EXPECT_FALSE(rules::iterationLimit(1));
  EXPECT_TRUE(rules::iterationLimit(-3));
  // The same combinations parse where the rule allows them.
  EXPECT_NO_THROW(parseProblem(
      replace(g, "formulation: displacement", "formulation: mixed, stabilization: 0.999"),
      "case.yaml", ""));
  EXPECT_NO_THROW(parseProblem(replace(replace(g, "formulation: displacement",
                                               "formulation: mixed, geometric_nonlinearity: true"),
                                       "output: {directory: somewhere}", contact),
                               "case.yaml", ""));
}

// Reproducers found by fuzz/fuzz_problem.cpp, and the sizes the fuzz run must not allocate: each
// is an InputError naming file:line and the key.
TEST(Problem, FuzzedInputsAreInputErrorsNamingTheKey) {
  auto errorOf = [](const std::string &yaml) -> std::string {
    try {
      parseProblem(yaml, "case.yaml", "");
    } catch (const InputError &e) {
      return e.what();
    }
    return "no error";
  };
  const std::string g = kGood;
  const std::string gen = "generator: {type: rectangle, size: [10, 1], divisions: [20, 2], "
                          "element: quad8}";
  // A map used as a key (was: YAML::TypedBadConversion escaping allowOnly).
  auto msg = errorOf(
      replace(g, "  - {boundary: left, ux: 0, uy: 0}", "  - {boundary: left, ux: 0}: value"));
  EXPECT_EQ(msg.rfind("case.yaml:7:5: boundary_conditions[0]: a key must be a plain word", 0), 0u)
      << msg;
  msg = errorOf(replace(g, "steps: {", "steps: {[1, 2]: 3, "));
  EXPECT_NE(msg.find("steps: a key must be a plain word"), std::string::npos) << msg;
  // Generator divisions beyond the index range are refused before anything is allocated.
  msg = errorOf(replace(g, gen,
                        "generator: {type: rectangle, size: [10, 1], divisions: [100000, "
                        "100000]}"));
  EXPECT_EQ(msg.rfind("case.yaml:2:", 0), 0u) << msg;
  EXPECT_NE(msg.find("mesh.generator.divisions: these divisions make 1e+10 elements"),
            std::string::npos)
      << msg;
  msg = errorOf(replace(g, gen,
                        "generator: {type: pinned_plate, hole_radius: 0.5, half_width: 2, "
                        "end_distance: 4, length: 8, divisions: [40000, 40000, 4, 9]}"));
  EXPECT_NE(msg.find("mesh.generator.divisions: these divisions make"), std::string::npos) << msg;
  // Finite sizes whose coordinates overflow (was: "element 1 has a non-positive Jacobian (0)").
  msg = errorOf(replace(g, gen,
                        "generator: {type: rectangle, size: [1e308, 1], divisions: [2, 2], "
                        "origin: [1e308, 0]}"));
  EXPECT_NE(msg.find("case.yaml:2:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("mesh.generator: generator rectangle: the node coordinates overflow"),
            std::string::npos)
      << msg;
  // A grading whose geometric growth overflows (was: UBSan, signed overflow in the node lookup of
  // the generator on the NaN coordinates).
  msg = errorOf(replace(g, gen,
                        "generator: {type: pinned_plate, hole_radius: 0.5, half_width: 1, "
                        "end_distance: 4, length: 8, divisions: [13, 18, 12, 27], "
                        "grading: 1.1e110}"));
  EXPECT_NE(msg.find("case.yaml:2:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("generator pinned_plate: the node coordinates overflow"), std::string::npos)
      << msg;
  // A bad key inside the generator is located once (was: "case.yaml:2:14: mesh.generator:
  // case.yaml:2:...").
  msg = errorOf(replace(g, "element: quad8}", "element: quad8, origin: [.nan, 0]}"));
  EXPECT_EQ(msg.rfind("case.yaml:2:92: mesh.generator.origin[0]: expected a finite number", 0), 0u)
      << msg;
  // Increments whose load factors would not fit in memory (was: 16 GB of push_back).
  msg = errorOf(replace(g, "steps: {load_factors: [0.5, 1.0]}", "steps: {increments: 2000000000}"));
  EXPECT_EQ(msg.rfind("case.yaml:13:", 0), 0u) << msg;
  EXPECT_NE(msg.find("steps.increments: at most 1000000 increments"), std::string::npos) << msg;
}

// A problem file is read to at most 64 MiB (a mistaken argument is not read whole).
TEST(Problem, ProblemFileOverSixtyFourMiBIsRefused) {
  TempDir dir;
  const fs::path file = dir.path() / "huge.yaml";
  {
    std::ofstream out(file);
    out << kGood;
    const std::string comment = "# " + std::string(1022, 'c') + "\n";
    for (int i = 0; i < 65 * 1024; ++i)
      out << comment;
  }
  try {
    readProblem(file.string());
    ADD_FAILURE() << "no error";
  } catch (const InputError &e) {
    EXPECT_NE(std::string(e.what()).find("huge.yaml:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(": the problem file is larger than 67108864 bytes"),
              std::string::npos)
        << e.what();
  }
}

// Two conditions on one set prescribing a component with the same value pass, with a warning
// naming both entries; conditions on sets sharing nodes with equal values (a clamped corner) pass
// without one.
TEST(Problem, RepeatedEqualConditionsPassWithAWarning) {
  const std::string g = kGood;
  const Problem p = parseProblem(replace(g, "  - {boundary: left, ux: 0, uy: 0}\n",
                                         "  - {boundary: left, ux: 0, uy: 0}\n"
                                         "  - {boundary: bottom, uy: 0}\n"
                                         "  - {boundary: left, uy: 0}\n"),
                                 "case.yaml", "");
  ASSERT_EQ(p.dirichlet.size(), 3u);
  ASSERT_EQ(p.mesh.warnings.size(), 1u);
  EXPECT_EQ(p.mesh.warnings[0], "case.yaml:9: boundary_conditions[2] (line 9, on 'left') repeats "
                                "uy = 0 of boundary_conditions[0] (line 7, on 'left')");
}

namespace {
using mixcon::test::runMixcon;
} // namespace

TEST(Cli, BadInputExitsWithCodeTwoAndMessage) {
  TempDir dir;
  for (const auto &c : badCases()) {
    const fs::path file = dir.path() / (std::string(c.name) + ".yaml");
    std::ofstream(file) << c.yaml;
    std::string out;
    EXPECT_EQ(runMixcon("run " + file.string(), out, dir.path()), 2) << c.name << ": " << out;
    EXPECT_NE(out.find(c.expected), std::string::npos) << c.name << ": " << out;
    const bool namesFile = out.find(file.string()) != std::string::npos ||
                           out.find("inverted.msh") != std::string::npos ||
                           out.find("groups.msh") != std::string::npos;
    EXPECT_TRUE(namesFile) << "message names the problem or mesh file: " << out;
  }
  std::string out;
  EXPECT_EQ(runMixcon("run " + (dir.path() / "nothing.yaml").string(), out, dir.path()), 2);
  EXPECT_NE(out.find("cannot open the problem file"), std::string::npos) << out;
  // A problem file that is a device, a directory or a FIFO is refused by stat, before a read
  // that would never end (/dev/zero) or block (a FIFO without a writer).
  EXPECT_EQ(runMixcon("run /dev/zero", out, dir.path()), 2) << out;
  EXPECT_NE(out.find("/dev/zero: the problem file is a device, not a regular file"),
            std::string::npos)
      << out;
  EXPECT_EQ(runMixcon("run " + dir.path().string(), out, dir.path()), 2) << out;
  EXPECT_NE(out.find("the problem file is a directory"), std::string::npos) << out;
  const fs::path fifo = dir.path() / "fifo.yaml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(runMixcon("run " + fifo.string(), out, dir.path()), 2) << out;
  EXPECT_NE(out.find("fifo.yaml: the problem file is a FIFO"), std::string::npos) << out;
  // A mesh file that is a device: refused naming the problem file, line and key.
  const fs::path zero = dir.path() / "zero.yaml";
  std::ofstream(zero) << replace(kGood, kGenerator, "file: /dev/zero");
  EXPECT_EQ(runMixcon("run " + zero.string(), out, dir.path()), 2) << out;
  EXPECT_NE(out.find("zero.yaml:2:9: mesh.file: /dev/zero: the mesh file is a device"),
            std::string::npos)
      << out;
  EXPECT_EQ(runMixcon("--version", out, dir.path()), 0);
  EXPECT_NE(out.find("mixcon 0."), std::string::npos) << out;
  EXPECT_EQ(runMixcon("frobnicate", out, dir.path()), 2) << out;
}

TEST(Cli, RunWritesHdf5XdmfAndSummary) {
  TempDir dir;
  const fs::path file = dir.path() / "good.yaml";
  std::ofstream(file) << kGood;
  std::string out;
  const fs::path outDir = dir.path() / "results";
  ASSERT_EQ(runMixcon("run " + file.string() + " --output " + outDir.string(), out, dir.path()), 0)
      << out;
  EXPECT_NE(out.find("step 2/2"), std::string::npos) << "progress line per step: " << out;
  ASSERT_TRUE(fs::exists(outDir / "results.xdmf"));
  ASSERT_TRUE(fs::exists(outDir / "summary.json"));
  std::ifstream js(outDir / "summary.json");
  std::stringstream summary;
  summary << js.rdbuf();
  EXPECT_NE(summary.str().find("\"converged\": true"), std::string::npos) << summary.str();
  EXPECT_NE(summary.str().find("\"load_factor\": 0.5"), std::string::npos) << summary.str();
  std::ifstream xs(outDir / "results.xdmf");
  std::stringstream xdmf;
  xdmf << xs.rdbuf();
  EXPECT_NE(xdmf.str().find("Quadrilateral_8"), std::string::npos);
  EXPECT_NE(xdmf.str().find("results.h5:/steps/2/stress"), std::string::npos);

  const hid_t f = H5Fopen((outDir / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  auto dims = [&](const char *name) {
    const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
    EXPECT_GE(d, 0) << name;
    const hid_t s = H5Dget_space(d);
    hsize_t dd[2] = {0, 0};
    H5Sget_simple_extent_dims(s, dd, nullptr);
    H5Sclose(s);
    H5Dclose(d);
    return std::array<hsize_t, 2>{dd[0], dd[1]};
  };
  const hsize_t nn = 41 * 5 - 20 * 2; // Quad8 20x2 rectangle
  EXPECT_EQ(dims("/mesh/nodes"), (std::array<hsize_t, 2>{nn, 2}));
  EXPECT_EQ(dims("/mesh/elements"), (std::array<hsize_t, 2>{40, 8}));
  EXPECT_EQ(dims("/steps/2/displacement"), (std::array<hsize_t, 2>{nn, 3})); // z = 0
  EXPECT_EQ(dims("/steps/2/stress"), (std::array<hsize_t, 2>{nn, 3}));
  EXPECT_EQ(dims("/steps/1/gauss_points/stress"), (std::array<hsize_t, 2>{40 * 9, 3}));
  double lambda = 0;
  const hid_t g = H5Gopen2(f, "/steps/1", H5P_DEFAULT);
  const hid_t a = H5Aopen(g, "load_factor", H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_DOUBLE, &lambda);
  H5Aclose(a);
  H5Gclose(g);
  EXPECT_DOUBLE_EQ(lambda, 0.5);
  // Linear analysis: step 2 displacement is twice step 1's.
  auto read = [&](const char *name, std::size_t n) {
    std::vector<double> v(n);
    const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
    H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Dclose(d);
    return v;
  };
  const auto u1 = read("/steps/1/displacement", 3 * nn), u2 = read("/steps/2/displacement", 3 * nn);
  double maxU = 0;
  for (std::size_t i = 0; i < u1.size(); ++i) {
    EXPECT_NEAR(u2[i], 2 * u1[i], 1e-9 * (std::abs(u2[i]) + 1e-12));
    maxU = std::max(maxU, std::abs(u2[i]));
  }
  EXPECT_GT(maxU, 0.0);
  H5Fclose(f);
}

namespace {
std::string readStringAttribute(hid_t loc, const char *name) {
  const hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
  if (a < 0)
    return {};
  const hid_t t = H5Aget_type(a);
  std::string v(H5Tget_size(t), '\0');
  H5Aread(a, t, v.data());
  H5Tclose(t);
  H5Aclose(a);
  return v;
}
} // namespace

TEST(Cli, MixedRunWritesStressUnknownsAndGaussPointStresses) {
  TempDir dir;
  const fs::path file = dir.path() / "mixed.yaml";
  std::ofstream(file) << replace(replace(kGood, "formulation: displacement", "formulation: mixed"),
                                 "solver: {type: direct}", "solver: {type: amg, tolerance: 1e-10}");
  std::string out;
  const fs::path outDir = dir.path() / "results";
  ASSERT_EQ(runMixcon("run " + file.string() + " --output " + outDir.string(), out, dir.path()), 0)
      << out;
  EXPECT_NE(out.find("mixed model"), std::string::npos) << out;
  const hid_t f = H5Fopen((outDir / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t g = H5Gopen2(f, "/steps/2", H5P_DEFAULT);
  EXPECT_NE(
      readStringAttribute(g, "stress_source").find("nodal stress unknowns of the mixed model"),
      std::string::npos);
  const hid_t gp = H5Gopen2(g, "gauss_points", H5P_DEFAULT);
  EXPECT_NE(readStringAttribute(gp, "stress_source").find("from the displacements"),
            std::string::npos);
  H5Gclose(gp);
  H5Gclose(g);
  H5Fclose(f);
}

TEST(Cli, NonlinearMixedRunWritesConvergenceHistoryAndGaussFields) {
  TempDir dir;
  const fs::path file = dir.path() / "nonlinear.yaml";
  std::string y = replace(kGood, "formulation: displacement",
                          "formulation: mixed, geometric_nonlinearity: true");
  y = replace(y, "steps: {load_factors: [0.5, 1.0]}", "steps: {increments: 2, iteration: newton}");
  std::ofstream(file) << y;
  std::string out;
  const fs::path outDir = dir.path() / "results";
  ASSERT_EQ(
      runMixcon("run " + file.string() + " --verbose --output " + outDir.string(), out, dir.path()),
      0)
      << out;
  EXPECT_NE(out.find("geometrically nonlinear"), std::string::npos) << out;
  EXPECT_NE(out.find("iteration 1"), std::string::npos) << out; // per-iteration progress
  std::ifstream in(outDir / "summary.json");
  std::stringstream summary;
  summary << in.rdbuf();
  for (const char *key : {"\"residuals\"", "\"increments\"", "\"convergence_orders\"", "\"cuts\""})
    EXPECT_NE(summary.str().find(key), std::string::npos) << key;
  const hid_t f = H5Fopen((outDir / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  for (const char *name :
       {"/steps/2/gauss_points/displacement_gradient", "/steps/2/gauss_points/current_coordinates",
        "/steps/2/gauss_points/interpolated_stress"}) {
    const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
    EXPECT_GE(d, 0) << name;
    if (d >= 0)
      H5Dclose(d);
  }
  const hid_t g = H5Gopen2(f, "/steps/2", H5P_DEFAULT);
  EXPECT_NE(readStringAttribute(g, "stress_source").find("nodal Cauchy stress unknowns"),
            std::string::npos);
  H5Gclose(g);
  H5Fclose(f);
}

TEST(Cli, ContactRunWritesContactFieldsAndCsv) {
  TempDir dir;
  std::string out;
  const fs::path outDir = dir.path() / "hertz";
  ASSERT_EQ(runMixcon("run " + std::string(MIXCON_SOURCE_DIR) +
                          "/examples/hertz/hertz_report.yaml --output " + outDir.string(),
                      out, dir.path()),
            0)
      << out;
  EXPECT_NE(out.find("nodes closed"), std::string::npos) << out;
  std::ifstream csv(outDir / "contact.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "step,load_factor,obstacle,node_id,status,gap,normal_force,tangential_force,"
                    "angle_deg,arc,x,y,normal_stress,tangential_stress,sigma_nn,tau_nt,stage,time");
  int rows = 0, closed = 0;
  for (std::string line; std::getline(csv, line); ++rows)
    closed += line.find(",slip,") != std::string::npos;
  EXPECT_GT(rows, 12);
  EXPECT_GT(closed, 0);
  const hid_t f = H5Fopen((outDir / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t d = H5Dopen2(f, "/steps/12/contact/normal_force", H5P_DEFAULT);
  EXPECT_GE(d, 0);
  if (d >= 0)
    H5Dclose(d);
  H5Fclose(f);
  std::ifstream in(outDir / "summary.json");
  std::stringstream summary;
  summary << in.rdbuf();
  EXPECT_NE(summary.str().find("\"contact\": {\"closed\""), std::string::npos);
}

// Contact tractions in contact.csv: a block (W = 2, H = 1, plane strain, E = 21000, nu = 0.3)
// pressed by delta = 0.01 onto a frictionless rigid plane is uniformly compressed, sigma_yy =
// -E delta / (H (1 - nu^2)) (free lateral expansion). Every base node must report that as its
// traction (nodal force over its boundary share: end nodes have half shares) and as -sigma_nn.
TEST(Cli, ContactTractionsOfAUniformlyCompressedBlock) {
  TempDir dir;
  const fs::path problem = dir.path() / "block.yaml";
  std::ofstream(problem) << "mesh:\n  generator: {type: rectangle, size: [2, 1], divisions: [8, "
                            "4], element: quad8}\n"
                            "model: {analysis: plane_strain}\n"
                            "materials:\n  - {region: body, type: isotropic, E: 21000, nu: 0.3}\n"
                            "boundary_conditions:\n  - {boundary: left, ux: 0}\n"
                            "  - {boundary: top, uy: -0.01}\n"
                            "contact:\n  - {type: rigid_half_plane, boundary: bottom, point: [0, "
                            "0], normal: [0, 1]}\n"
                            "steps: {increments: 1}\n"
                            "output: {directory: block, hdf5: false}\n";
  std::string out;
  ASSERT_EQ(runMixcon("run " + problem.string() + " --output " + (dir.path() / "block").string(),
                      out, dir.path()),
            0)
      << out;
  std::ifstream csv(dir.path() / "block" / "contact.csv");
  std::string line;
  std::getline(csv, line);
  const double expected = 21000.0 * 0.01 / (1.0 - 0.09);
  int rows = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');)
      cells.push_back(c);
    ASSERT_EQ(cells.size(), 18u) << line;
    EXPECT_EQ(cells[4], "slip") << line;
    EXPECT_NEAR(std::stod(cells[12]), expected, 1e-6 * expected) << line;
    EXPECT_NEAR(std::stod(cells[13]), 0.0, 1e-6 * expected) << line;
    EXPECT_NEAR(std::stod(cells[14]), -expected, 1e-6 * expected) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 17); // the 8 Quad8 edges' 17 nodes
}

namespace {
/// The uniformly compressed block above, with HDF5 output.
const char *kCompressedBlock =
    "mesh:\n  generator: {type: rectangle, size: [2, 1], divisions: [8, 4], element: quad8}\n"
    "model: {analysis: plane_strain}\n"
    "materials:\n  - {region: body, type: isotropic, E: 21000, nu: 0.3}\n"
    "boundary_conditions:\n  - {boundary: left, ux: 0}\n  - {boundary: top, uy: -0.01}\n"
    "contact:\n  - {type: rigid_half_plane, boundary: bottom, point: [0, 0], normal: [0, 1]}\n"
    "steps: {increments: 1}\n"
    "output: {directory: block}\n";

std::vector<double> readDoubles(hid_t f, const char *name) {
  const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0)
    return {};
  const hid_t s = H5Dget_space(d);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(s)));
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(s);
  H5Dclose(d);
  return v;
}

/// The `stress_source` attribute of /steps/<step>/gauss_points of a run's results.h5.
std::string gaussStressSource(const fs::path &outDir, int step) {
  const hid_t f = H5Fopen((outDir / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0)
    return "(no results.h5)";
  const hid_t gp =
      H5Gopen2(f, ("/steps/" + std::to_string(step) + "/gauss_points").c_str(), H5P_DEFAULT);
  const std::string v = gp >= 0 ? readStringAttribute(gp, "stress_source") : "(no group)";
  if (gp >= 0)
    H5Gclose(gp);
  H5Fclose(f);
  return v;
}
} // namespace

// The Gauss-point stresses are labelled by the law that produced them: C eps(u) for a linear
// body in contact (small displacements, on the nonlinear driver), the St. Venant-Kirchhoff
// Cauchy stress for that law, and the Almansi law's only where it is used.
TEST(Cli, GaussPointStressSourceNamesTheLaw) {
  TempDir dir;
  std::string out;
  const fs::path block = dir.path() / "block.yaml";
  std::ofstream(block) << kCompressedBlock;
  ASSERT_EQ(runMixcon("run " + block.string() + " --output " + (dir.path() / "block").string(), out,
                      dir.path()),
            0)
      << out;
  const std::string contact = gaussStressSource(dir.path() / "block", 1);
  EXPECT_NE(contact.find("C eps(u)"), std::string::npos) << contact;
  EXPECT_EQ(contact.find("Almansi"), std::string::npos) << contact;

  const fs::path svk = dir.path() / "svk.yaml";
  std::string y = replace(kGood, "formulation: displacement",
                          "formulation: displacement, geometric_nonlinearity: true, "
                          "elastic_law: saint_venant_kirchhoff");
  std::ofstream(svk) << replace(y, "steps: {load_factors: [0.5, 1.0]}",
                                "steps: {increments: 2, iteration: newton}");
  ASSERT_EQ(runMixcon("run " + svk.string() + " --output " + (dir.path() / "svk").string(), out,
                      dir.path()),
            0)
      << out;
  const std::string law = gaussStressSource(dir.path() / "svk", 2);
  EXPECT_NE(law.find("St. Venant-Kirchhoff"), std::string::npos) << law;
  EXPECT_EQ(law.find("Almansi"), std::string::npos) << law;

  const fs::path almansi = dir.path() / "almansi.yaml";
  std::ofstream(almansi) << replace(
      replace(kGood, "formulation: displacement",
              "formulation: displacement, geometric_nonlinearity: true"),
      "steps: {load_factors: [0.5, 1.0]}", "steps: {increments: 2, iteration: newton}");
  ASSERT_EQ(runMixcon("run " + almansi.string() + " --output " + (dir.path() / "almansi").string(),
                      out, dir.path()),
            0)
      << out;
  EXPECT_NE(gaussStressSource(dir.path() / "almansi", 2).find("Almansi"), std::string::npos);
}

// The per-node contact arrays (the XDMF's contact_* attributes) of the uniformly compressed
// block: every base node slips (frictionless) with the traction E delta / (H (1 - nu^2)) and no
// gap; every other node is no candidate (-1, gap NaN, zero traction). Vectors are N x 3 with
// z = 0 and the stress datasets name their components.
TEST(Cli, ContactNodalArraysAndThreeComponentVectors) {
  TempDir dir;
  std::string out;
  const fs::path block = dir.path() / "block.yaml";
  std::ofstream(block) << kCompressedBlock;
  const fs::path outDir = dir.path() / "block";
  ASSERT_EQ(runMixcon("run " + block.string() + " --output " + outDir.string(), out, dir.path()), 0)
      << out;
  const hid_t f = H5Fopen((outDir / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const std::vector<double> x = readDoubles(f, "/mesh/nodes");
  const std::size_t nn = x.size() / 2;
  std::vector<int> status(nn, -9);
  const hid_t d = H5Dopen2(f, "/steps/1/contact_nodal/status", H5P_DEFAULT);
  ASSERT_GE(d, 0);
  H5Dread(d, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, status.data());
  H5Dclose(d);
  const auto gap = readDoubles(f, "/steps/1/contact_nodal/gap");
  const auto pn = readDoubles(f, "/steps/1/contact_nodal/normal_traction");
  const auto pt = readDoubles(f, "/steps/1/contact_nodal/tangential_traction");
  ASSERT_EQ(gap.size(), nn);
  ASSERT_EQ(pn.size(), nn);
  ASSERT_EQ(pt.size(), nn);
  const double expected = 21000.0 * 0.01 / (1.0 - 0.09);
  int base = 0;
  for (std::size_t i = 0; i < nn; ++i) {
    if (std::abs(x[2 * i + 1]) < 1e-12) {
      ++base;
      EXPECT_EQ(status[i], 2) << "node " << i;
      EXPECT_NEAR(pn[i], expected, 1e-6 * expected) << "node " << i;
      EXPECT_NEAR(pt[i], 0.0, 1e-6 * expected) << "node " << i;
      EXPECT_NEAR(gap[i], 0.0, 1e-9) << "node " << i;
    } else {
      EXPECT_EQ(status[i], -1) << "node " << i;
      EXPECT_TRUE(std::isnan(gap[i])) << "node " << i;
      EXPECT_EQ(pn[i], 0.0) << "node " << i;
    }
  }
  EXPECT_EQ(base, 17);
  const auto u = readDoubles(f, "/steps/1/displacement");
  const auto r = readDoubles(f, "/steps/1/reaction");
  ASSERT_EQ(u.size(), 3 * nn);
  ASSERT_EQ(r.size(), 3 * nn);
  double top = 0.0;
  for (std::size_t i = 0; i < nn; ++i) {
    EXPECT_EQ(u[3 * i + 2], 0.0);
    EXPECT_EQ(r[3 * i + 2], 0.0);
    if (std::abs(x[2 * i + 1] - 1.0) < 1e-12)
      top = u[3 * i + 1];
  }
  EXPECT_NEAR(top, -0.01, 1e-9); // the prescribed uy in the second column
  for (const char *name : {"/steps/1/stress", "/steps/1/gauss_points/stress"}) {
    const hid_t s = H5Dopen2(f, name, H5P_DEFAULT);
    ASSERT_GE(s, 0) << name;
    const hid_t a = H5Aopen(s, "components", H5P_DEFAULT);
    ASSERT_GE(a, 0) << name;
    const hid_t t = H5Aget_type(a), space = H5Aget_space(a);
    const std::size_t width = H5Tget_size(t);
    ASSERT_EQ(H5Sget_simple_extent_npoints(space), 3) << name;
    std::string packed(3 * width, '\0');
    H5Aread(a, t, packed.data());
    const char *expectedNames[] = {"xx", "yy", "xy"};
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(std::string(packed.c_str() + c * width, std::min<std::size_t>(2, width)),
                expectedNames[c])
          << name;
    H5Sclose(space);
    H5Tclose(t);
    H5Aclose(a);
    H5Dclose(s);
  }
  H5Fclose(f);
  std::ifstream xs(outDir / "results.xdmf");
  std::stringstream xdmf;
  xdmf << xs.rdbuf();
  for (const char *name : {"\"contact_status\"", "\"contact_normal_traction\"",
                           "\"contact_tangential_traction\"", "\"contact_gap\"", "\"reaction\""})
    EXPECT_NE(xdmf.str().find(name), std::string::npos) << name;
}

TEST(Problem, ParsesAForceDrivenPinPerComponent) {
  const std::string text =
      replace(kGood, "output: {directory: somewhere}",
              "contact:\n  - {type: rigid_circle, boundary: top, center: [0, 2], radius: 1, "
              "friction: 0.7, drive: {force: [-200, null], displacement: [null, 0.5]}}\n"
              "output: {directory: somewhere}");
  const Problem p = parseProblem(text, "pin.yaml", "");
  ASSERT_EQ(p.contact.size(), 1u);
  const ContactSpec &c = p.contact[0];
  EXPECT_TRUE(c.forceDriven[0]);
  EXPECT_FALSE(c.forceDriven[1]);
  EXPECT_DOUBLE_EQ(c.driveForce[0], -200.0);
  EXPECT_DOUBLE_EQ(c.driveDisplacement[1], 0.5);
  EXPECT_DOUBLE_EQ(c.friction, 0.7);
}

// The hybrid section: measurements read at parse time; a file that does not match the mesh, a
// contact section beside it, or steps given twice are refused with the file and line.
TEST(Problem, HybridSectionReadsMeasurementsAndRefusesMismatches) {
  TempDir dir;
  std::ofstream(dir.path() / "m.csv") << "step,load,x,y,ux,uy\n1,5,0,1,0,-1e-3\n1,5,10,1,0,-1e-3\n"
                                         "2,10,0,1,0,-2e-3\n2,10,10,1,0,-2e-3\n";
  std::ofstream(dir.path() / "far.csv") << "step,load,x,y,ux,uy\n1,5,0,1,0,0\n1,5,5,0.5,0,0\n";
  const std::string hybrid = "hybrid: {measurements: m.csv, boundary: top, center: [5, 0], "
                             "symmetrize: false, max_distance: 0.01}\n";
  const std::string base =
      replace(replace(kGood, "steps: {load_factors: [0.5, 1.0]}\n", ""),
              "output: {directory: somewhere}", hybrid + "output: {directory: somewhere}");
  const Problem p = parseProblem(base, "h.yaml", dir.path().string());
  ASSERT_TRUE(p.hybrid.has_value());
  EXPECT_EQ(p.hybrid->steps.size(), 2u);
  EXPECT_EQ(p.loadFactors, (std::vector<double>{0.5, 1.0}));
  EXPECT_FALSE(p.hybrid->symmetrize);
  const auto error = [&](const std::string &text) {
    try {
      parseProblem(text, "h.yaml", dir.path().string());
    } catch (const InputError &e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error(replace(base, "m.csv", "far.csv")).find("far.csv:3: the measured point (5, 0.5)"),
            std::string::npos);
  EXPECT_NE(error(replace(base, "m.csv", "none.csv")).find("cannot open the measurement file"),
            std::string::npos);
  EXPECT_NE(error(replace(base, "boundary: top, center", "boundary: rim, center"))
                .find("unknown boundary 'rim'"),
            std::string::npos);
  EXPECT_NE(error(replace(base, "output: {directory: somewhere}",
                          "steps: {increments: 3}\noutput: {directory: somewhere}"))
                .find("the steps of a hybrid run come from its measurement file"),
            std::string::npos);
  EXPECT_NE(error(replace(base, "output: {directory: somewhere}",
                          "contact:\n  - {type: rigid_half_plane, boundary: bottom, point: [0, "
                          "0], normal: [0, 1]}\noutput: {directory: somewhere}"))
                .find("remove the contact section"),
            std::string::npos);
}

TEST(Cli, HybridRunWritesStressesAndFrictionPerStep) {
  TempDir dir;
  std::string out;
  const fs::path outDir = dir.path() / "hybrid";
  ASSERT_EQ(runMixcon("run " + std::string(MIXCON_SOURCE_DIR) +
                          "/examples/hybrid/hybrid.yaml --output " + outDir.string(),
                      out, dir.path()),
            0)
      << out;
  EXPECT_NE(out.find("hybrid mode: 18 measured steps"), std::string::npos) << out;
  EXPECT_NE(out.find("asymmetry of the measurements"), std::string::npos) << out;
  std::ifstream csv(outDir / "hybrid.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "step,load,node_id,angle_deg,ux,uy,sigma_rr,tau_rt,mu_stress,traction_n,"
                    "traction_t,mu_force");
  int rows = 0, undetermined = 0;
  for (std::string line; std::getline(csv, line); ++rows)
    undetermined += line.find("nan") != std::string::npos;
  EXPECT_EQ(rows, 18 * 13);   // 18 steps, 13 hole nodes
  EXPECT_GT(undetermined, 0); // the open part of the hole: no mu
  const hid_t f = H5Fopen((outDir / "results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t d = H5Dopen2(f, "/steps/18/hybrid/mu_force", H5P_DEFAULT);
  EXPECT_GE(d, 0);
  if (d >= 0)
    H5Dclose(d);
  H5Fclose(f);
}

// Several bodies and node-to-segment contact: names, offsets, materials per body; errors for a
// repeated body name, an unknown contact boundary, the same surface twice and rigid obstacles
// mixed with node-to-segment contact.
TEST(Problem, ParsesBodiesAndNodeToSegmentContact) {
  const std::string bodies = R"(mesh:
  bodies:
    - {name: lower, generator: {type: rectangle, size: [2, 1], divisions: [4, 2]}}
    - {name: upper, generator: {type: rectangle, size: [1, 1], divisions: [3, 2]}, offset: [0.5, 1]}
model: {formulation: displacement, analysis: plane_stress, thickness: 1.0}
materials:
  - {region: lower, type: isotropic, E: 1000, nu: 0.3}
  - {region: upper, type: isotropic, E: 2000, nu: 0.3}
boundary_conditions:
  - {boundary: lower.bottom, ux: 0, uy: 0}
  - {boundary: upper.top, ux: 0, uy: -0.001}
contact:
  - {type: node_to_segment, contactor: upper.bottom, target: lower.top, friction: 0.3}
solver: {type: direct}
output: {directory: somewhere}
)";
  const Problem p = parseProblem(bodies, "bodies.yaml", "");
  EXPECT_EQ(p.mesh.numElements(), 8 + 6);
  EXPECT_EQ(p.mesh.numNodes(), 15 + 12);
  EXPECT_EQ(p.mesh.regionNames, (std::vector<std::string>{"lower", "upper"}));
  for (LocalIndex n : p.mesh.nodesOf("upper.bottom")) {
    EXPECT_NEAR(p.mesh.y(n), 1.0, 1e-14);
    EXPECT_GE(p.mesh.x(n), 0.5 - 1e-14);
  }
  ASSERT_EQ(p.contact.size(), 1u);
  EXPECT_EQ(p.contact[0].type, "node_to_segment");
  EXPECT_EQ(p.contact[0].boundary, "upper.bottom");
  EXPECT_EQ(p.contact[0].target, "lower.top");
  EXPECT_DOUBLE_EQ(p.contact[0].friction, 0.3);
  struct Bad {
    std::string from, to, expected;
  };
  const std::string rigid =
      "  - {type: rigid_half_plane, boundary: lower.bottom, point: [0, 0], normal: [0, 1]}\n";
  for (const Bad &b :
       {Bad{"name: upper,", "name: lower,", "the body name 'lower' is used twice"},
        Bad{"name: upper,", "name: up.per,", "contain no '.'"},
        Bad{"target: lower.top", "target: lower.roof", "unknown boundary 'lower.roof'"},
        Bad{"target: lower.top", "target: upper.bottom", "must be different boundaries"},
        Bad{"friction: 0.3}\n", "friction: 0.3}\n" + rigid, "not supported in this version"},
        Bad{"{boundary: lower.bottom, ux: 0, uy: 0}", "{boundary: bottom, ux: 0, uy: 0}",
            "bottom"}}) {
    const std::string text = replace(bodies, b.from, b.to);
    try {
      parseProblem(text, "bodies.yaml", "");
      ADD_FAILURE() << b.to << ": no error";
    } catch (const InputError &e) {
      EXPECT_NE(std::string(e.what()).find(b.expected), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("bodies.yaml:", 0), 0u) << e.what();
    }
  }
}

// Node-to-segment contact through the program: two blocks with matching meshes pressed by a top
// displacement; every contactor node of the upper block closes and carries the uniform contact
// traction E delta / (2 H (1 - nu^2)) (two blocks of height H in series, plane strain).
TEST(Cli, NodeToSegmentRunWritesTheMultipliers) {
  TempDir dir;
  const fs::path problem = dir.path() / "stack.yaml";
  std::ofstream(problem)
      << "mesh:\n  bodies:\n"
         "    - {name: lower, generator: {type: rectangle, size: [2, 1], divisions: [4, 2]}}\n"
         "    - {name: upper, generator: {type: rectangle, size: [2, 1], divisions: [4, 2]}, "
         "offset: [0, 1]}\n"
         "model: {analysis: plane_strain}\n"
         "materials:\n  - {region: lower, type: isotropic, E: 21000, nu: 0.3}\n"
         "  - {region: upper, type: isotropic, E: 21000, nu: 0.3}\n"
         "boundary_conditions:\n  - {boundary: lower.left, ux: 0}\n"
         "  - {boundary: upper.left, ux: 0}\n"
         "  - {boundary: lower.bottom, uy: 0}\n"
         "  - {boundary: upper.top, uy: -0.01}\n"
         "contact:\n  - {type: node_to_segment, contactor: upper.bottom, target: lower.top}\n"
         "steps: {increments: 1}\n"
         "solver: {type: amg}\n"
         "output: {directory: stack, hdf5: false}\n";
  std::string out;
  ASSERT_EQ(runMixcon("run " + problem.string() + " --output " + (dir.path() / "stack").string(),
                      out, dir.path()),
            0)
      << out;
  EXPECT_NE(out.find("contact.csv"), std::string::npos) << out;
  std::ifstream csv(dir.path() / "stack" / "contact.csv");
  std::string line;
  std::getline(csv, line);
  const double expected = 21000.0 * 0.01 / (2.0 * (1.0 - 0.09));
  int rows = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');)
      cells.push_back(c);
    ASSERT_EQ(cells.size(), 18u) << line;
    EXPECT_EQ(cells[2], "1") << line; // the pair, numbered from 1
    EXPECT_EQ(cells[4], "slip") << line;
    EXPECT_NEAR(std::stod(cells[11]), 1.0 - 0.005, 1e-6) << line; // current y of the interface
    EXPECT_NEAR(std::stod(cells[12]), expected, 1e-5 * expected) << line;
    EXPECT_NEAR(std::stod(cells[14]), -expected, 1e-5 * expected) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 5); // the upper block's 5 base nodes
}

// A clockwise Gmsh element is reordered with one warning on stderr, and the run succeeds.
TEST(Cli, ClockwiseGmshElementsAreReorientedWithAWarning) {
  TempDir dir;
  const fs::path file = dir.path() / "groups.yaml";
  std::ofstream(file) << replace(kGroups, "directory: somewhere",
                                 "directory: " + (dir.path() / "out").string() + ", hdf5: false");
  std::string out;
  ASSERT_EQ(runMixcon("run -q " + file.string(), out, dir.path()), 0) << out;
  EXPECT_NE(out.find("mixcon: warning: " + (dir.path() / "groups.msh").string() +
                     ": 1 of 2 quadrangles had clockwise nodes"),
            std::string::npos)
      << out;
  const Problem p = readProblem(file.string());
  ASSERT_EQ(p.mesh.warnings.size(), 1u);
  EXPECT_NO_THROW(validateMesh(p.mesh));
}

// The node named for an obstacle that starts inside the body is the deepest one, by its mesh id;
// an obstacle that only touches the body is accepted.
TEST(Problem, ObstacleStartingInsideIsRefusedNamingTheDeepestNode) {
  const Problem good = parseProblem(kGood, "good.yaml", "");
  const Mesh &m = good.mesh;
  LocalIndex centre = -1; // the top node at x = 5, deepest in a circle centred at (5, 1.5)
  for (LocalIndex n = 0; n < m.numNodes(); ++n)
    if (std::abs(m.x(n) - 5.0) < 1e-12 && std::abs(m.y(n) - 1.0) < 1e-12)
      centre = n;
  ASSERT_GE(centre, 0);
  const auto contact = [](const std::string &c) {
    return replace(kGood, "output: {directory: somewhere}",
                   "contact:\n  - " + c + "\noutput: {directory: somewhere}");
  };
  try {
    parseProblem(contact("{type: rigid_circle, boundary: bottom, center: [5, 1.5], radius: 1}"),
                 "pin.yaml", "");
    ADD_FAILURE() << "no error";
  } catch (const InputError &e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("pin.yaml:16:", 0), 0u) << msg;
    EXPECT_NE(msg.find("contact[0]"), std::string::npos) << msg;
    // Not on the contact boundary: the body's node is checked as well.
    EXPECT_NE(msg.find("node " + std::to_string(m.nodeIds[centre]) + " (of the body"),
              std::string::npos)
        << msg;
  }
  // Touching at the start is fine: a circle tangent to the top, a plane through the bottom, and a
  // penetration within the tolerance (1e-4 of the body's size).
  EXPECT_NO_THROW(parseProblem(
      contact("{type: rigid_circle, boundary: top, center: [5, 2], radius: 1}"), "a.yaml", ""));
  EXPECT_NO_THROW(parseProblem(
      contact("{type: rigid_half_plane, boundary: bottom, point: [3, 0], normal: [0, 2]}"),
      "b.yaml", ""));
  EXPECT_NO_THROW(parseProblem(
      contact("{type: rigid_half_plane, boundary: bottom, point: [0, 0.0005], normal: [0, 1]}"),
      "c.yaml", ""));
  EXPECT_THROW(parseProblem(contact("{type: rigid_half_plane, boundary: bottom, point: [0, "
                                    "0.002], normal: [0, 1]}"),
                            "d.yaml", ""),
               InputError);
}

// Bodies that touch (matching or non-matching nodes along the interface) are accepted; a body
// moved into the other is refused naming both bodies, the node and the element.
TEST(Problem, OverlappingBodiesAreRefusedTouchingOnesAccepted) {
  const std::string bodies = R"(mesh:
  bodies:
    - {name: lower, generator: {type: rectangle, size: [2, 1], divisions: [4, 2]}}
    - {name: upper, generator: {type: rectangle, size: [1, 1], divisions: [3, 2]}, offset: [0.5, 1]}
materials:
  - {region: lower, type: isotropic, E: 1000, nu: 0.3}
  - {region: upper, type: isotropic, E: 2000, nu: 0.3}
boundary_conditions:
  - {boundary: lower.bottom, ux: 0, uy: 0}
  - {boundary: upper.top, ux: 0, uy: -0.001}
)";
  EXPECT_NO_THROW(parseProblem(bodies, "touch.yaml", ""));
  EXPECT_NO_THROW(
      parseProblem(replace(bodies, "offset: [0.5, 1]", "offset: [2, 0.3]"), "side.yaml", ""));
  // Within the tolerance (0.1 of the element's diameter): 0.04 deep, 0.057 of the lower
  // elements' diameter and 0.067 of the upper ones'.
  EXPECT_NO_THROW(
      parseProblem(replace(bodies, "offset: [0.5, 1]", "offset: [0.5, 0.96]"), "shallow.yaml", ""));
  try {
    // 0.2 deep: node (1, 1) of the lower body lies 0.167 from the edges of an upper element,
    // 0.28 of its diameter.
    parseProblem(replace(bodies, "offset: [0.5, 1]", "offset: [0.5, 0.8]"), "deep.yaml", "");
    ADD_FAILURE() << "no error";
  } catch (const InputError &e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind("deep.yaml:", 0), 0u) << msg;
    EXPECT_NE(msg.find("body 'lower' overlaps body 'upper' at the start: node "), std::string::npos)
        << msg;
    EXPECT_NE(msg.find("lies inside element"), std::string::npos) << msg;
  }
  // A body entirely inside another (no edge crosses): its nodes are inside.
  EXPECT_THROW(parseProblem(replace(replace(bodies, "size: [1, 1], divisions: [3, 2]",
                                            "size: [0.2, 0.2], divisions: [1, 1]"),
                                    "offset: [0.5, 1]", "offset: [0.65, 0.15]"),
                            "inside.yaml", ""),
               InputError);
}
