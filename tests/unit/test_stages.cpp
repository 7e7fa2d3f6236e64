// Load histories (stages, issue 26): the problem grammar and its refusals, and runs that load,
// hold, unload, prop and release, press and lift, through the C++ API (runAnalysis) and the
// program. References: an elastic body's state depends only on its loads and supports, so a
// body unloaded returns to zero, a support released under load leaves the state the load alone
// gives, and stages that scale every load together equal the same load factors.
#include <apps/Analysis.hpp>
#include <io/Problem.hpp>
#include <support/Program.hpp>
#include <support/ResultsFile.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace mixcon;
using mixcon::test::maxRelativeDifference;
using mixcon::test::readStep;
using mixcon::test::stepsOf;

/// Runs `yaml` through the C++ API into `dir`; returns the result.
RunResult run(const std::string &yaml, const fs::path &dir) {
  const Problem p = parseProblem(yaml, "stages.yaml", dir.string());
  RunOptions o;
  o.outputDirectory = dir.string();
  return runAnalysis(p, o, MPI_COMM_WORLD);
}

double maxAbs(const std::vector<double> &v) {
  double m = 0.0;
  for (double x : v)
    m = std::max(m, std::abs(x));
  return m;
}

/// The message of the InputError that parsing `yaml` throws ("" when it does not).
std::string refusal(const std::string &yaml) {
  try {
    parseProblem(yaml, "stages.yaml", ".");
  } catch (const InputError &e) {
    return e.what();
  }
  return "";
}

const char *kCantilever = R"(
mesh: {generator: {type: rectangle, size: [10, 1], origin: [0, -0.5], divisions: [10, 2], element: quad8}}
model: {formulation: displacement, analysis: plane_stress, thickness: 1.0, geometric_nonlinearity: true}
materials: [{region: body, type: isotropic, E: 1.2e4, nu: 0.2}]
boundary_conditions: [{boundary: left, ux: 0}, {node_set: left_center, uy: 0}]
solver: {type: direct}
)";

} // namespace

TEST(Stages, ReadsTheHistory) {
  const Problem p = parseProblem(std::string(kCantilever) + R"(
steps: {tolerance: 0.01}
stages:
  - {name: load, increments: 4, loads: [{boundary: right, traction: [0, -1]}]}
  - {load_factors: [0.5, 1], max_iterations: 7,
     boundary_conditions: [{node_set: right_center, uy: -0.1}]}
  - {name: free, boundary_conditions: [{node_set: right_center, release: [uy]}]}
)",
                                 "stages.yaml", ".");
  ASSERT_EQ(p.stages.size(), 3u);
  EXPECT_EQ(p.stages[0].name, "load");
  EXPECT_EQ(p.stages[0].loadFactors, (std::vector<double>{0.25, 0.5, 0.75, 1.0}));
  ASSERT_EQ(p.stages[0].loads.size(), 1u);
  EXPECT_EQ(p.stages[0].loads[0].vector[1], -1.0);
  EXPECT_EQ(p.stages[1].name, "stage 2");
  EXPECT_EQ(p.stages[1].loadFactors, (std::vector<double>{0.5, 1.0}));
  EXPECT_EQ(p.stages[1].nonlinear.maxIterations, 7);
  EXPECT_EQ(p.stages[1].nonlinear.tolerance, 0.01); // from steps
  EXPECT_EQ(p.stages[0].nonlinear.maxIterations, p.nonlinear.maxIterations);
  ASSERT_EQ(p.stages[2].dirichlet.size(), 1u);
  EXPECT_TRUE(p.stages[2].dirichlet[0].release[1]);
  EXPECT_FALSE(p.stages[2].dirichlet[0].release[0]);
  EXPECT_EQ(p.stages[2].loadFactors, (std::vector<double>{1.0}));
}

TEST(Stages, RefusesWhatItCannotRunWithFileAndLine) {
  const std::string base = kCantilever;
  const std::string load = "loads: [{boundary: right, traction: [0, -1]}]";
  const struct {
    std::string yaml, expected;
  } cases[] = {
      {base + "stages: []\n", "stages.yaml:7:9: stages: needs at least one stage"},
      {base + "steps: {increments: 3}\nstages: [{" + load + "}]\n",
       "steps.increments: with stages, each stage gives its own increments"},
      {base + "stages: [{load_factors: [0.5, 0.8], " + load + "}]\n",
       "the last load factor of a stage must be 1"},
      {base + "stages: [{load_factors: [0.5, 0.2, 1], " + load + "}]\n",
       "stages[0].load_factors[1]: the load factors of a stage increase within (0, 1]"},
      {base + "stages: [{boundary_conditions: [{boundary: left, release: [ux]}]}]\n",
       "the first stage has nothing to release yet"},
      {base + "stages: [{" + load +
           "}, {boundary_conditions: [{node_set: right_center, release: [ux]}]}]\n",
       "releases ux of node"},
      {base + "stages: [{" + load +
           "}, {contact: [{boundary: right, drive: {displacement: [0, "
           "1]}}]}]\n",
       "no rigid obstacle of the contact section acts on 'right' (the problem has none"},
      {base + "stages: [{loads: [{boundary: right, pressure: 1}]}, {loads: [{boundary: right, "
              "pressure: 2, follower: false}]}]\n",
       "a stage changes its value, not its kind"},
      {base +
           "verification: {type: cantilever, length: 10, height: 1, load: -1, tip: "
           "right_center}\nstages: [{" +
           load + "}]\n",
       "verification: verification checks one proportional load"},
      {base + "stages: [{name: a, " + load + "}, {name: a}]\n", "stage name 'a' given twice"},
      {base + "stages: [{name: stage 2, " + load + "}, {}]\n",
       "stages[1]: stage name 'stage 2' given twice"},
      {base + "stages: [{" + load +
           "}, {boundary_conditions: [{node_set: right_center, uy: 0}]}, {boundary_conditions: "
           "[{node_set: right_center, release: [uy]}, {boundary: right, uy: 0.1}]}]\n",
       "prescribes uy of node"},
      {base + "stages: [{" + load +
           "}, {boundary_conditions: [{boundary: right, release: true}]}]\n",
       "nothing on 'right' is held: nothing to release"},
      {base + "stages: [{increment: 2, " + load + "}]\n", "unknown key 'increment'"},
      {R"(
mesh: {generator: {type: rectangle, size: [10, 1], divisions: [4, 1], element: quad4}}
model: {formulation: mixed, analysis: plane_stress, compliance: lumped}
materials: [{region: body, type: isotropic, E: 1.2e4, nu: 0.2}]
boundary_conditions: [{boundary: left, ux: 0, uy: 0}]
stages: [{loads: [{boundary: right, traction: [0, -1]}]}]
)",
       "stages.yaml:3:65: model.compliance: compliance applies to the linear mixed model without "
       "contact or stages"},
      {R"(
mesh: {generator: {type: rectangle, size: [10, 1], divisions: [4, 1], element: quad4}}
model: {formulation: mixed, analysis: plane_stress}
materials: [{region: body, type: isotropic, E: 1.2e4, nu: 0.2}]
boundary_conditions: [{boundary: left, ux: 0, uy: 0}]
solver: {type: amg, krylov: gmres}
stages: [{loads: [{boundary: right, traction: [0, -1]}]}]
)",
       "krylov applies to the linear mixed model's Schur solver only (not with "
       "geometric_nonlinearity, contact or stages)"},
      {R"(
mesh: {generator: {type: quarter_disk, radius: 1.0, divisions: [3, 2], element: quad4}}
model: {formulation: displacement, analysis: plane_strain}
materials: [{region: body, type: isotropic, E: 21000, nu: 0.3}]
boundary_conditions: [{boundary: left, ux: 0}, {boundary: bottom, uy: 0}]
contact: [{type: rigid_half_plane, boundary: arc, point: [0, 1], normal: [0, -1],
           drive: {force: [null, -10], displacement: [0, null]}}]
stages: [{contact: [{boundary: arc, drive: {displacement: [0, -0.01]}}]}]
)",
       "component y of the obstacle on 'arc' is driven by a force"},
  };
  for (const auto &c : cases) {
    const std::string message = refusal(c.yaml);
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << "expected '" << c.expected << "' in: " << message << "\n"
        << c.yaml;
    EXPECT_EQ(message.rfind("stages.yaml:", 0), 0u) << message;
  }
}

// A later stage whose supports leave a mechanism is refused before the first solve, naming the
// stage and its line: nothing is written, not even the first stage's steps.
TEST(Stages, ALaterStageThatLeavesAMechanismIsRefusedBeforeAnySolve) {
  test::ScratchDir dir("stages");
  const std::string yaml = std::string(kCantilever) + R"(
stages:
  - {name: load, increments: 2, loads: [{boundary: right, traction: [0, -1]}]}
  - {name: free, boundary_conditions: [{boundary: left, release: [ux]}]}
)";
  const Problem p = parseProblem(yaml, "stages.yaml", dir.path().string());
  RunOptions o;
  o.outputDirectory = (dir.path() / "out").string();
  try {
    runAnalysis(p, o, MPI_COMM_WORLD);
    ADD_FAILURE() << "a released support that leaves a mechanism was accepted";
  } catch (const InputError &e) {
    EXPECT_EQ(std::string(e.what()).rfind("stages.yaml:10: stage 2 'free': ", 0), 0u) << e.what();
  }
  EXPECT_TRUE(stepsOf(dir.path() / "out").empty());
}

// Stages that move every load together are the load factors of one proportional stage: the same
// steps, to round-off.
TEST(Stages, StagesOfOneProportionalLoadEqualItsLoadFactors) {
  test::ScratchDir dir("stages");
  const std::string staged = std::string(kCantilever) + R"(
stages:
  - {name: half, loads: [{boundary: right, traction: [0, -1]}]}
  - {name: whole, increments: 2, loads: [{boundary: right, traction: [0, -2]}]}
)";
  const std::string proportional = std::string(kCantilever) + R"(
loads: [{boundary: right, traction: [0, -2]}]
steps: {load_factors: [0.5, 0.75, 1.0]}
)";
  const RunResult a = run(staged, dir.path() / "staged");
  const RunResult b = run(proportional, dir.path() / "proportional");
  ASSERT_TRUE(a.converged && b.converged);
  ASSERT_EQ(a.steps.size(), 3u);
  EXPECT_EQ(a.steps[1].stage, 2);
  EXPECT_EQ(a.steps[1].stageName, "whole");
  EXPECT_DOUBLE_EQ(a.steps[1].loadFactor, 0.5);
  EXPECT_DOUBLE_EQ(a.steps[1].time, 1.5);
  for (int k = 1; k <= 3; ++k)
    for (const char *field : {"displacement", "stress"})
      EXPECT_LE(maxRelativeDifference(readStep(dir.path() / "staged", k, field),
                                      readStep(dir.path() / "proportional", k, field)),
                1e-9)
          << "step " << k << " " << field;
}

namespace {

/// A body loaded, held and unloaded: `model` and `mesh` lines, the loaded boundary, the load.
struct HoldCase {
  const char *name;
  const char *setup; ///< mesh, model, materials, supports, solver
  const char *load;  ///< the load entry
  const char *zero;  ///< the same entry at zero
};

const HoldCase kHoldCases[] = {
    {"displacement_2d", kCantilever, "{boundary: right, traction: [0, -2]}",
     "{boundary: right, traction: [0, 0]}"},
    {"displacement_2d_follower", kCantilever, "{boundary: top, pressure: 0.5}",
     "{boundary: top, pressure: 0}"},
    {"mixed_2d", R"(
mesh: {generator: {type: rectangle, size: [10, 1], origin: [0, -0.5], divisions: [10, 2], element: quad8}}
model: {formulation: mixed, analysis: plane_stress, thickness: 1.0, geometric_nonlinearity: true}
materials: [{region: body, type: isotropic, E: 1.2e4, nu: 0.2}]
boundary_conditions: [{boundary: left, ux: 0}, {node_set: left_center, uy: 0}]
solver: {type: direct}
)",
     "{boundary: right, traction: [0, -2]}", "{boundary: right, traction: [0, 0]}"},
    {"displacement_3d", R"(
mesh: {generator: {type: box, size: [4, 0.5, 0.5], divisions: [8, 1, 1], element: hex8}}
model: {formulation: displacement, geometric_nonlinearity: true}
materials: [{region: body, type: isotropic, E: 1.2e4, nu: 0.2}]
boundary_conditions: [{boundary: xmin, ux: 0, uy: 0, uz: 0}]
solver: {type: direct}
)",
     "{boundary: zmax, pressure: 20}", "{boundary: zmax, pressure: 0}"},
    {"mixed_3d", R"(
mesh: {generator: {type: box, size: [4, 0.5, 0.5], divisions: [4, 1, 1], element: hex8}}
model: {formulation: mixed, geometric_nonlinearity: true, stabilization: 0.05}
materials: [{region: body, type: isotropic, E: 1.2e4, nu: 0.2}]
boundary_conditions: [{boundary: xmin, ux: 0, uy: 0, uz: 0}]
solver: {type: direct}
)",
     "{boundary: zmax, traction: [0, 0, -20]}", "{boundary: zmax, traction: [0, 0, 0]}"},
    // The linear mixed models (small displacements in the iterating driver), with the AMG
    // solves: block-triangular GMRES in 2D, its matrix-free Jacobian in 3D.
    {"mixed_2d_linear", R"(
mesh: {generator: {type: rectangle, size: [10, 1], origin: [0, -0.5], divisions: [10, 2], element: quad8}}
model: {formulation: mixed, analysis: plane_stress, thickness: 1.0}
materials: [{region: body, type: isotropic, E: 1.2e4, nu: 0.2}]
boundary_conditions: [{boundary: left, ux: 0}, {node_set: left_center, uy: 0}]
solver: {type: amg, tolerance: 1e-11}
)",
     "{boundary: right, traction: [0, -2]}", "{boundary: right, traction: [0, 0]}"},
    {"mixed_3d_linear", R"(
mesh: {generator: {type: box, size: [4, 0.5, 0.5], divisions: [4, 1, 1], element: hex8}}
model: {formulation: mixed, stabilization: 0.05}
materials: [{region: body, type: isotropic, E: 1.2e4, nu: 0.2}]
boundary_conditions: [{boundary: xmin, ux: 0, uy: 0, uz: 0}]
solver: {type: amg, jacobian: matrix_free, tolerance: 1e-11}
)",
     "{boundary: zmax, traction: [0, 0, -20]}", "{boundary: zmax, traction: [0, 0, 0]}"},
};

} // namespace

// Loaded, held, unloaded: the hold keeps the loaded state, the unloading returns displacements
// and stresses to zero (below 1e-9 of their loaded values), for both models in 2D and 3D and for
// a follower pressure.
TEST(Stages, ABodyLoadedHeldAndUnloadedReturnsToZero) {
  test::ScratchDir dir("stages");
  for (const HoldCase &c : kHoldCases) {
    const std::string yaml = std::string(c.setup) + "stages:\n  - {name: load, increments: 3, " +
                             "loads: [" + c.load + "]}\n  - {name: hold}\n" +
                             "  - {name: unload, increments: 3, loads: [" + c.zero + "]}\n";
    const fs::path out = dir.path() / c.name;
    const RunResult r = run(yaml, out);
    ASSERT_TRUE(r.converged) << c.name;
    ASSERT_EQ(stepsOf(out).size(), 7u) << c.name;
    for (const char *field : {"displacement", "stress"}) {
      const auto loaded = readStep(out, 3, field);
      ASSERT_GT(maxAbs(loaded), 0.0) << c.name;
      // Held: the same state, to the equilibrium tolerance (a hold step iterates once more).
      EXPECT_LE(maxRelativeDifference(readStep(out, 4, field), loaded), 1e-5) << c.name << " hold";
      EXPECT_LE(maxAbs(readStep(out, 7, field)), 1e-9 * maxAbs(loaded))
          << c.name << " unloaded " << field;
      // On the way down, at a third and two thirds of the load: the states of the way up
      // (an elastic body's state depends on its load, not on the path).
      EXPECT_LE(maxRelativeDifference(readStep(out, 6, field), readStep(out, 1, field)), 1e-5)
          << c.name << " unloading at 1/3";
      EXPECT_LE(maxRelativeDifference(readStep(out, 5, field), readStep(out, 2, field)), 1e-5)
          << c.name << " unloading at 2/3";
    }
  }
}

// A prop added under load pushes the tip to its value; released under the same load, the
// cantilever returns to the state the load alone gives (its support force ramps to zero).
TEST(Stages, ASupportReleasedUnderLoadLeavesTheStateOfTheLoadAlone) {
  test::ScratchDir dir("stages");
  const std::string yaml = std::string(kCantilever) + R"(
stages:
  - {name: load, increments: 3, loads: [{boundary: right, traction: [0, -2]}]}
  - {name: prop, increments: 2, boundary_conditions: [{node_set: right_center, uy: -0.05}]}
  - {name: release, increments: 3,
     boundary_conditions: [{node_set: right_center, release: [uy]}]}
)";
  const RunResult r = run(yaml, dir.path());
  ASSERT_TRUE(r.converged);
  ASSERT_EQ(r.steps.size(), 8u);
  const Problem p = parseProblem(yaml, "stages.yaml", ".");
  const std::size_t tip = 3 * static_cast<std::size_t>(p.mesh.nodesOf("right_center").at(0));
  const auto loaded = readStep(dir.path(), 3, "displacement");
  const auto propped = readStep(dir.path(), 5, "displacement");
  // (results.h5 holds 3 displacement components per node)
  EXPECT_LT(loaded[tip + 1], -0.2); // the unpropped tip deflects far more than the prop
  EXPECT_NEAR(propped[tip + 1], -0.05, 1e-12);
  // Half way through the prop stage the tip is half way between.
  EXPECT_NEAR(readStep(dir.path(), 4, "displacement")[tip + 1], 0.5 * (loaded[tip + 1] - 0.05),
              1e-12);
  for (const char *field : {"displacement", "stress"})
    EXPECT_LE(maxRelativeDifference(readStep(dir.path(), 8, field), readStep(dir.path(), 3, field)),
              1e-7)
        << field;
}

// Overlapping releases (a boundary and a node set on it) free each component once: its support
// force is ramped down once, so that the release stage follows the same path as with one entry.
TEST(Stages, OverlappingReleasesCarryTheSupportForceOnce) {
  test::ScratchDir dir("stages");
  const std::string head = std::string(kCantilever) + R"(
stages:
  - {name: load, increments: 2, loads: [{boundary: right, traction: [0, -2]}]}
  - {name: prop, boundary_conditions: [{boundary: right, uy: -0.05}]}
)";
  const RunResult one = run(head + R"(  - {name: release, increments: 2,
     boundary_conditions: [{boundary: right, release: [uy]}]}
)",
                            dir.path() / "one");
  const RunResult two = run(head + R"(  - {name: release, increments: 2,
     boundary_conditions: [{boundary: right, release: [uy]}, {node_set: right_center, release: true}]}
)",
                            dir.path() / "two");
  ASSERT_TRUE(one.converged && two.converged);
  for (int k : {4, 5})
    EXPECT_LE(maxRelativeDifference(readStep(dir.path() / "two", k, "displacement"),
                                    readStep(dir.path() / "one", k, "displacement")),
              1e-12)
        << "step " << k;
}

// A linear body (no geometric nonlinearity) runs its stages through the iterating driver with
// small displacements: each step equals the linear model's solution (apps' linear branch,
// MixedModel and SolidMixedModel for the mixed model) of the loads it has reached, for both
// models in 2D and 3D.
TEST(Stages, ALinearBodyGoesThroughItsStages) {
  test::ScratchDir dir("stages");
  // A strip (2D, loaded on 'right') or a bar (3D, loaded on 'xmax') clamped at its left end.
  const std::string strip = R"(
mesh: {generator: {type: rectangle, size: [10, 1], origin: [0, -0.5], divisions: [10, 2], element: ELEMENT}}
boundary_conditions: [{boundary: left, ux: 0}, {node_set: left_center, uy: 0}]
)";
  const std::string bar = R"(
mesh: {generator: {type: box, size: [4, 0.5, 0.5], divisions: [4, 1, 1], element: ELEMENT}}
boundary_conditions: [{boundary: xmin, ux: 0, uy: 0, uz: 0}]
)";
  const char *isotropic = "[{region: body, type: isotropic, E: 1.2e4, nu: 0.2}]";
  const struct {
    const char *name, *element, *model, *materials, *solver;
    double tolerance; ///< of the comparison: the direct solver's, or an iterative one's
  } cases[] = {
      {"displacement_2d", "quad8",
       "{formulation: displacement, analysis: plane_stress, thickness: 1.0}", isotropic,
       "{type: direct}", 1e-9},
      {"mixed_2d", "quad8", "{formulation: mixed, analysis: plane_stress, thickness: 1.0}",
       "[{region: body, type: orthotropic, E1: 1.2e4, E2: 4e3, G12: 2e3, nu12: 0.25, angle: 30}]",
       "{type: direct}", 1e-9},
      {"mixed_2d_report", "quad4",
       "{formulation: mixed, analysis: plane_strain, thickness: 1.0, stabilization: 0}",
       "[{region: body, type: isotropic, E: 1.2e4, nu: 0.3}]", "{type: direct}", 1e-9},
      {"mixed_3d", "hex20", "{formulation: mixed, stabilization: 0.05}", isotropic,
       "{type: direct}", 1e-9},
      // The iterative solves: the block-triangular GMRES on the assembled J0 (2D), on the
      // matrix-free one (3D); the linear runs solve with their own methods.
      {"mixed_2d_amg", "quad8", "{formulation: mixed, analysis: plane_stress, thickness: 1.0}",
       isotropic, "{type: amg, tolerance: 1e-12}", 1e-7},
      {"mixed_3d_matrix_free", "hex8", "{formulation: mixed, stabilization: 0.05}", isotropic,
       "{type: amg, jacobian: matrix_free, tolerance: 1e-12}", 1e-7},
  };
  for (const auto &c : cases) {
    const bool solid = c.element[0] == 'h';
    std::string setup = solid ? bar : strip;
    setup.replace(setup.find("ELEMENT"), 7, c.element);
    setup += std::string("model: ") + c.model + "\nmaterials: " + c.materials +
             "\nsolver: " + c.solver + "\n";
    const std::string end = solid ? "xmax" : "right";
    const auto traction = [&](const char *planar, const char *spatial) {
      return "{boundary: " + end + ", traction: " + (solid ? spatial : planar) + "}";
    };
    const fs::path staged = dir.path() / c.name / "staged", linear = dir.path() / c.name / "linear";
    const RunResult a =
        run(setup + "stages:\n  - {name: bend, loads: [" + traction("[0, -1]", "[0, 0, -1]") +
                "]}\n  - {name: pull, increments: 2, loads: [" + traction("[3, 0]", "[3, 0, 0]") +
                "]}\n",
            staged);
    const RunResult b =
        run(setup + "loads: [" + traction("[1.5, -0.5]", "[1.5, 0, -0.5]") + "]\n", linear);
    ASSERT_TRUE(a.converged && b.converged) << c.name;
    ASSERT_EQ(a.steps.size(), 3u) << c.name;
    // Half way through 'pull' the traction is (1.5, -0.5): the linear run's state.
    for (const char *field : {"displacement", "stress"})
      EXPECT_LE(maxRelativeDifference(readStep(staged, 2, field), readStep(linear, 1, field)),
                c.tolerance)
          << c.name << " " << field;
  }
}

// Rigid contact: an obstacle driven down presses the quarter cylinder, driven back it lets go:
// the contact forces vanish (the top node, touching at the start, may stay closed without force)
// and the body returns to zero; the displacement model with and without friction, the mixed
// model (geometrically nonlinear and linear, its statuses from its nodal stresses) with friction.
TEST(Stages, ARigidObstaclePressedAndLiftedLetsGo) {
  test::ScratchDir dir("stages");
  const struct {
    const char *name, *model, *mu;
  } cases[] = {
      {"displacement", "{formulation: displacement, analysis: plane_strain}", "0"},
      {"displacement_friction", "{formulation: displacement, analysis: plane_strain}", "0.3"},
      {"mixed_friction",
       "{formulation: mixed, analysis: plane_strain, geometric_nonlinearity: true}", "0.3"},
      {"mixed_linear_friction", "{formulation: mixed, analysis: plane_strain}", "0.3"},
  };
  for (const auto &c : cases) {
    const std::string yaml = std::string(R"(
mesh: {generator: {type: quarter_disk, radius: 1.0, divisions: [6, 4], element: quad4}}
model: )") + c.model + R"(
materials: [{region: body, type: isotropic, E: 21000, nu: 0.3}]
boundary_conditions: [{boundary: left, ux: 0}, {boundary: bottom, uy: 0}]
contact: [{type: rigid_half_plane, boundary: arc, point: [0, 1], normal: [0, -1], friction: )" +
                             c.mu + R"(}]
stages:
  - {name: press, increments: 4, contact: [{boundary: arc, drive: {displacement: [0, -0.016]}}]}
  - {name: lift, increments: 4, contact: [{boundary: arc, drive: {displacement: [0, 0]}}]}
solver: {type: direct}
)";
    const fs::path out = dir.path() / c.name;
    const RunResult r = run(yaml, out);
    ASSERT_TRUE(r.converged) << c.name;
    ASSERT_EQ(r.steps.size(), 8u);
    EXPECT_GE(r.steps[3].contactClosed, 1) << c.name;
    EXPECT_DOUBLE_EQ(r.steps[3].obstacleMotion[1], -0.016);
    EXPECT_DOUBLE_EQ(r.steps[5].obstacleMotion[1], -0.008); // half way up
    EXPECT_LE(r.steps[7].contactClosed, 1) << c.name;
    EXPECT_LE(maxAbs(readStep(out, 8, "contact/normal_force")),
              1e-9 * maxAbs(readStep(out, 4, "contact/normal_force")))
        << c.name;
    for (const char *field : {"displacement", "stress"})
      EXPECT_LE(maxAbs(readStep(out, 8, field)), 1e-9 * maxAbs(readStep(out, 4, field)))
          << c.name << " " << field;
  }
}

// A force-driven pin (the report's wood plate with the displacement model): stages that raise
// the force on the pin from half to all of it equal the load factors 0.5 and 1 (the force on
// the obstacle has a base too).
TEST(Stages, AForceDrivenObstacleFollowsItsStages) {
  test::ScratchDir dir("stages");
  const std::string setup = R"(
mesh: {generator: {type: pinned_plate, element: quad4, hole_radius: 0.5, half_width: 2.0,
                   end_distance: 4.0, length: 8.0, divisions: [4, 6, 4, 9], grading: 1.25}}
model: {formulation: displacement, analysis: plane_stress}
materials: [{region: body, type: orthotropic, E1: 1.8e6, E2: 9.0e4, G12: 1.17e5, nu12: 0.45}]
boundary_conditions: [{boundary: bottom, uy: 0}, {boundary: far, ux: 0}]
solver: {type: direct}
contact:
  - {type: rigid_circle, boundary: hole, center: [0, 0], radius: 0.5, friction: 0.7,
     drive: {force: [-200, null], displacement: [null, 0]}}
)";
  const RunResult staged = run(setup + R"(
stages:
  - {name: half, contact: [{boundary: hole, drive: {force: [-100, null], displacement: [null, 0]}}]}
  - {name: all, contact: [{boundary: hole, drive: {force: [-200, null], displacement: [null, 0]}}]}
)",
                               dir.path() / "staged");
  const RunResult proportional =
      run(setup + "steps: {load_factors: [0.5, 1]}\n", dir.path() / "proportional");
  ASSERT_TRUE(staged.converged && proportional.converged);
  ASSERT_EQ(staged.steps.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k)
    EXPECT_NEAR(staged.steps[k].obstacleMotion[0], proportional.steps[k].obstacleMotion[0],
                1e-9 * std::abs(proportional.steps[1].obstacleMotion[0]))
        << "step " << k + 1;
  for (int k : {1, 2})
    for (const char *field : {"displacement", "contact/normal_force"})
      EXPECT_LE(maxRelativeDifference(readStep(dir.path() / "staged", k, field),
                                      readStep(dir.path() / "proportional", k, field)),
                1e-8)
          << "step " << k << " " << field;
}

// A node that closes during an increment sticks where it touched the target, not where the
// increment ends. A block (1 x 1, its bottom 0.1 above the target) is driven at its top along
// a diagonal, (0.2, -0.15) in n increments, with friction 10 (stick everywhere). Until its
// bottom touches, at 2/3 of the drive, it translates rigidly; from there the bottom sticks.
// Reference: the bottom ends at ux = 0.2 * 2/3 and uy = -0.1 whatever n (touching inside the
// only increment, the third of 4 or the fourth of 5). Anchored where the closing increment ends,
// it would end at 0.2 (n = 1), 0.2 * 3/4 = 0.15 (n = 4) or 0.2 * 4/5 = 0.16 (n = 5). On a rigid
// plane the motion is exact; on an elastic base 1000 times stiffer than the block, the base's own
// deformation leaves a few 1e-5 (in the closing increment some bottom nodes cross from one
// target segment to the next, and in the single increment of n = 1 they slide 0.13, over two
// segments).
TEST(Stages, ANodeThatClosesInAnIncrementSticksWhereItTouched) {
  test::ScratchDir dir("stages");
  const std::string block =
      "{type: rectangle, size: [1, 1], origin: [0, 0.1], divisions: [2, 2], element: quad4}";
  const struct {
    const char *name, *setup;
    double tolerance;
  } cases[] = {
      {"rigid_half_plane", R"(
mesh: {generator: BLOCK}
materials: [{region: body, type: isotropic, E: 1000, nu: 0.3}]
boundary_conditions: [{boundary: top, ux: 0.2, uy: -0.15}]
contact: [{type: rigid_half_plane, boundary: bottom, point: [0, 0], normal: [0, 1], friction: 10}]
)",
       1e-9},
      {"node_to_segment", R"(
mesh:
  bodies:
    - {name: block, generator: BLOCK}
    - name: base
      generator: {type: rectangle, size: [2.9, 0.5], origin: [-0.95, -0.5], divisions: [37, 2],
                  element: quad4}
materials:
  - {region: block, type: isotropic, E: 1000, nu: 0.3}
  - {region: base, type: isotropic, E: 1.0e6, nu: 0.3}
boundary_conditions: [{boundary: block.top, ux: 0.2, uy: -0.15}, {boundary: base.bottom, ux: 0, uy: 0}]
contact: [{type: node_to_segment, contactor: block.bottom, target: base.top, friction: 10}]
)",
       2e-4},
  };
  for (const auto &c : cases)
    for (int n : {1, 4, 5}) {
      std::string yaml =
          std::string("model: {formulation: displacement, analysis: "
                      "plane_strain}\nsolver: {type: direct}\nsteps: {increments: ") +
          std::to_string(n) + "}\n" + c.setup;
      yaml.replace(yaml.find("BLOCK"), 5, block);
      const std::string what = std::string(c.name) + ", " + std::to_string(n) + " increments";
      const Problem p = parseProblem(yaml, "touch.yaml", dir.path().string());
      RunOptions o;
      o.outputDirectory = (dir.path() / (std::string(c.name) + std::to_string(n))).string();
      const RunResult r = runAnalysis(p, o, MPI_COMM_WORLD);
      ASSERT_TRUE(r.converged) << what;
      int bottom = 0;
      for (LocalIndex k = 0; k < p.mesh.numNodes(); ++k) {
        if (std::abs(p.mesh.coordinate(k, 1) - 0.1) > 1e-12)
          continue;
        ++bottom;
        EXPECT_NEAR(r.displacement[2 * k], 0.2 * 2.0 / 3.0, c.tolerance) << what << ", node " << k;
        EXPECT_NEAR(r.displacement[2 * k + 1], -0.1, c.tolerance) << what << ", node " << k;
      }
      EXPECT_EQ(bottom, 3) << what;
    }
}

#if defined(MIXCON_APP)
// The program: progress lines name the stage, steps are numbered continuously with their stage
// and pseudo-time in summary.json, contact.csv and the XDMF time series ParaView animates.
TEST(Stages, OutputNamesStagesAndNumbersStepsContinuously) {
  test::ScratchDir dir("stages");
  const fs::path file = dir.path() / "press.yaml";
  std::ofstream(file) << R"(
mesh: {generator: {type: quarter_disk, radius: 1.0, divisions: [6, 4], element: quad4}}
model: {formulation: displacement, analysis: plane_strain, thickness: 1.0}
materials: [{region: body, type: isotropic, E: 21000, nu: 0.3}]
boundary_conditions: [{boundary: left, ux: 0}, {boundary: bottom, uy: 0}]
contact: [{type: rigid_half_plane, boundary: arc, point: [0, 1], normal: [0, -1]}]
stages:
  - {name: press, increments: 2, contact: [{boundary: arc, drive: {displacement: [0, -0.01]}}]}
  - {name: hold}
  - {name: lift, load_factors: [0.5, 1], contact: [{boundary: arc, drive: {displacement: [0, 0]}}]}
solver: {type: direct}
)";
  std::string out;
  ASSERT_EQ(test::runMixcon("run " + file.string() + " --output " + (dir.path() / "out").string(),
                            out, dir.path()),
            0)
      << out;
  EXPECT_NE(out.find("stage 2/3 'hold'  step 3/5  load factor 1"), std::string::npos) << out;
  EXPECT_NE(out.find("stage 3/3 'lift'  step 5/5"), std::string::npos) << out;
  std::stringstream summary;
  summary << std::ifstream(dir.path() / "out" / "summary.json").rdbuf();
  EXPECT_NE(summary.str().find("{\"step\": 4, \"stage\": 3, \"stage_name\": \"lift\", \"time\": "
                               "2.5, \"load_factor\": 0.5"),
            std::string::npos)
      << summary.str();
  std::stringstream xdmf;
  xdmf << std::ifstream(dir.path() / "out" / "results.xdmf").rdbuf();
  std::vector<double> times;
  const std::string tag = "<Time Value=\"";
  for (auto at = xdmf.str().find(tag); at != std::string::npos; at = xdmf.str().find(tag, at + 1))
    times.push_back(std::stod(xdmf.str().substr(at + tag.size())));
  EXPECT_EQ(times, (std::vector<double>{0.5, 1.0, 2.0, 2.5, 3.0}));
  std::ifstream csv(dir.path() / "out" / "contact.csv");
  std::string header, line, last;
  std::getline(csv, header);
  EXPECT_EQ(header.substr(header.size() - 11), ",stage,time") << header;
  while (std::getline(csv, line))
    last = line;
  EXPECT_EQ(last.substr(last.size() - 4), ",3,3") << last;
}
#endif
