// The problem description: everything a run needs (mesh, model, materials, boundary conditions,
// loads, steps, solver, output, closed-form verification), read from a YAML problem file whose
// format docs/problem-format.md documents key by key. Data flow: io (input side).
#pragma once

#include <io/Measurements.hpp>
#include <kernels/Material.hpp>
#include <mesh/Mesh.hpp>
#include <solver/MixedOptions.hpp>
#include <solver/NonlinearOptions.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace mixcon {

enum class Formulation { Displacement, Mixed };

struct ModelSpec {
  Formulation formulation = Formulation::Displacement;
  PlaneAnalysis analysis = PlaneAnalysis::PlaneStress;
  double thickness = 1.0;
  bool geometricNonlinearity = false;
  /// Mixed formulation only: stress interpolation (default: the mesh's element), compliance mass,
  /// stabilization a, and the Schur solve settings (MixedOptions.linear is Problem::solver).
  std::optional<ElementType> stressElement;
  MixedOptions mixed;
  /// Geometrically nonlinear mixed model: its form and (form incremental) stress update.
  MixedForm mixedForm = MixedForm::Current;
  StressUpdate stressUpdate = StressUpdate::Projected;
  /// Geometrically nonlinear mixed model, solver: amg — the iterative solve of its Jacobian.
  MixedNewtonSolverOptions mixedNewton;
  /// Geometrically nonlinear displacement model: elastic law.
  ElasticLaw elasticLaw = ElasticLaw::Almansi;
};

struct MaterialSpec {
  std::string region;
  std::string type;      ///< isotropic | orthotropic | anisotropic
  PlaneMatrix stiffness; ///< 2D: [C] in global axes for the model's plane analysis
  SolidMatrix solid{};   ///< 3D: the 6 x 6 Voigt [C] in global axes
  double youngs = 0.0;   ///< isotropic only (for verification); 0 otherwise
  double poisson = 0.0;  ///< isotropic only
  int line = 0;
};

/// Prescribed displacement components on a boundary or node set (scaled by the load factor).
struct DirichletSpec {
  std::string target;
  std::optional<double> ux, uy, uz; ///< uz: 3D meshes only
  /// Stages after the first only: the components (x, y, z) this entry frees (`release`).
  std::array<bool, 3> release{false, false, false};
  int line = 0;
};

enum class LoadKind { Traction, Pressure, Force, BodyForce };

struct LoadSpec {
  LoadKind kind = LoadKind::Traction;
  std::string target;                          ///< boundary, node set or region
  std::array<double, 3> vector{0.0, 0.0, 0.0}; ///< traction, force, body force (2D: z = 0)
  double pressure = 0.0;
  /// Pressure only, geometrically nonlinear analyses: normal to the deformed boundary (default)
  /// or a dead load on the reference geometry.
  bool follower = true;
  int line = 0;
};

/// A rigid obstacle in contact with the nodes of a boundary, or (node_to_segment) the nodes of a
/// contactor boundary against the segments of a target boundary (`contact:` list).
struct ContactSpec {
  std::string type;     ///< rigid_circle | rigid_half_plane | node_to_segment
  std::string boundary; ///< the contacting boundary of the body (node_to_segment: the contactor)
  std::string target;   ///< node_to_segment: the target boundary
  std::array<double, 2> point{0.0, 0.0};  ///< circle centre / a point on the plane
  double radius = 0.0;                    ///< circle
  std::array<double, 2> normal{0.0, 1.0}; ///< half-plane: unit normal into the body
  double friction = 0.0;
  std::array<double, 2> driveDisplacement{0.0, 0.0}; ///< obstacle motion at load factor 1
  std::array<bool, 2> forceDriven{false, false};     ///< components driven by a force instead
  std::array<double, 2> driveForce{0.0, 0.0};        ///< force on the obstacle at load factor 1
  bool statusFromStress = true; ///< mixed model: nodal stresses (true) or forces decide
  int line = 0;
};

/// A rigid obstacle's drive at the end of a stage (a `contact:` entry of a stage): its
/// displacement and the force on it, per component as the obstacle's own `drive` gives them.
struct DriveSpec {
  std::string boundary; ///< names the obstacle (its contact boundary)
  std::array<double, 2> displacement{0.0, 0.0};
  std::array<double, 2> force{0.0, 0.0};
  std::array<bool, 2> forceDriven{false, false};
  int line = 0;
};

/// One stage of a load history (`stages:`). Its loads, prescribed displacements and obstacle
/// drives are the values reached at its end; it starts where the previous stage ended and moves
/// linearly to them with its load factors. What a stage does not name keeps its value.
struct StageSpec {
  std::string name;
  std::vector<double> loadFactors{1.0}; ///< within the stage, increasing, the last 1
  std::vector<DirichletSpec> dirichlet; ///< end values, or components released
  std::vector<LoadSpec> loads;          ///< end values per kind and target (they replace)
  std::vector<DriveSpec> drives;        ///< end values per obstacle
  NonlinearOptions nonlinear;           ///< the stage's iteration settings
  int line = 0;
};

struct VerificationSpec {
  std::string type; ///< empty: none; lame_cylinder | lame_sphere | cantilever
  double innerRadius = 0, outerRadius = 0, innerPressure = 0, outerPressure = 0;
  double length = 0, height = 0, load = 0;
  double width = 0; ///< cantilever in 3D: the section's width (2D: the model's thickness)
  std::string tipNodeSet;
  double tolerance = 0.02;
};

/// Hybrid experimental/numerical mode: measured displacements prescribed on a boundary, step by
/// step (io/Measurements.hpp).
struct HybridSpec {
  std::string measurements;               ///< the CSV, resolved against the problem's folder
  std::string boundary;                   ///< where the displacements were measured
  std::array<double, 2> center{0.0, 0.0}; ///< pole of the angle, sigma_rr and tau_rt
  bool symmetrize = true;                 ///< average the mirrored halves (about y = center y)
  double maxDistance = 0.0;               ///< farthest a point may lie from the boundary
  double threshold = 0.05;                ///< |sigma_rr| below this times the peak: no mu
  std::vector<MeasuredStep> steps;        ///< read at parse time
  int line = 0;
};

struct Problem {
  std::string file; ///< the problem file (for messages)
  Mesh mesh;
  ModelSpec model;
  std::vector<MaterialSpec> materials;
  std::vector<DirichletSpec> dirichlet;
  std::vector<LoadSpec> loads;
  std::vector<ContactSpec> contact;
  std::optional<HybridSpec> hybrid;
  std::vector<double> loadFactors{1.0};
  /// The load history (`stages:`); empty: one proportional stage, the top-level
  /// boundary_conditions, loads and contact drives scaled by `loadFactors`. With stages, those
  /// top-level entries are where the first stage goes (with its own entries).
  std::vector<StageSpec> stages;
  /// Equilibrium iterations of geometrically nonlinear analyses (steps: iteration, tolerance...).
  NonlinearOptions nonlinear;
  /// Displacement model: the tangent of the iterations (steps: tangent).
  TangentKind tangent = TangentKind::Exact;
  LinearSolverOptions solver;
  /// Why the solver's defaults were chosen as they were where the problem decided it (the 3D AMG
  /// settings of a thin or a bulky part); printed with the solver's set-up. Empty: nothing to say.
  std::string solverDefaultsNote;
  std::string outputDirectory = "out";
  bool writeHdf5 = true;
  VerificationSpec verification;
};

/// Reads and validates a problem file; throws InputError ("file:line:column: what") on any
/// invalid content: unknown keys, missing files, unknown names, regions without material, no
/// Dirichlet condition, unsupported or mismatched elements, inverted elements.
Problem readProblem(const std::string &path);

/// Same, from YAML text; relative mesh paths resolve against `baseDirectory`.
Problem parseProblem(const std::string &yamlText, const std::string &name,
                     const std::string &baseDirectory);

} // namespace mixcon
