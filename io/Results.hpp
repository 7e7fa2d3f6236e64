// Result output: HDF5 (mesh + one group per step), an XDMF index that ParaView opens, and
// summary.json with per-step convergence data; the state a restart needs is written with every
// converged step and read back by readRestart. Crash safety: every file is written under a
// temporary name and renamed into place, each step's HDF5 data goes to a file of its own
// (results.d/step-NNNNNN.h5) and results.h5 links the mesh and the steps, so a run killed at any
// moment leaves a results.h5 that opens and holds every step written. The output folder is
// locked while a writer owns it. Layout: docs/output-format.md.
// Data flow: io (output side, host data only).
#pragma once

#include <mesh/Mesh.hpp>
#include <solver/Checkpoint.hpp>

#include <exception>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace mixcon {

/// Convergence record of one load step.
struct StepRecord {
  int step = 0;            ///< numbered continuously over all stages, from 1
  double loadFactor = 0.0; ///< within its stage (the whole run without stages)
  int stage = 1;           ///< the stage (1-based; 1 without stages)
  std::string stageName;   ///< its name (empty without stages)
  /// Pseudo-time of the load history: stage k runs from k - 1 to k, time = k - 1 + load factor
  /// (the load factor without stages).
  double time = 0.0;
  int iterations = 0;        ///< nonlinear (Newton) iterations; 1 for a linear step
  int linearIterations = 0;  ///< Krylov iterations summed over the step
  double residual = 0.0;     ///< relative residual of the last solve
  double setupSeconds = 0.0; ///< solver setup (AMG hierarchy / factorization) charged to the step
  double solveSeconds = 0.0;
  double totalSeconds = 0.0;
  bool converged = false;
  /// Geometrically nonlinear steps: relative residual before the first and after every
  /// correction, relative increment norms, and the increment cuts needed.
  std::vector<double> residualHistory, incrementHistory;
  int cuts = 0;
  /// Contact runs: closed / stick / slip node counts, status updates, cycling, and the extent of
  /// the closed region (arc coordinate on the obstacle, min and max).
  int contactClosed = -1, contactStick = 0, contactSlip = 0, contactIterations = 0;
  bool contactCycled = false;
  double contactArcMin = 0.0, contactArcMax = 0.0;
  /// Rigid motion of every obstacle from its declared position (2 per obstacle).
  std::vector<double> obstacleMotion;
  /// Hybrid mode: the measured load of the step and the asymmetry of the measurements
  /// (-1: not symmetrized); NaN outside the hybrid mode.
  double measuredLoad = std::numeric_limits<double>::quiet_NaN();
  double asymmetry = -1.0;
};

/// Per contact candidate (boundary node against an obstacle) of one step.
struct ContactFields {
  std::vector<int> obstacle;
  std::vector<long> node;      ///< mesh node id
  std::vector<long> nodeIndex; ///< 0-based index of that node (the rows of the nodal arrays)
  std::vector<int> status;     ///< 0 open, 1 stick, 2 slip
  std::vector<double> gap, normalForce, tangentForce, angle, arc, x, y;
  /// Contact tractions (nodal force / the node's share of the contact boundary, current
  /// configuration) and the nodal stress rotated to the obstacle: sigma_nn = n.s.n,
  /// tau_nt = t.s.n.
  std::vector<double> normalStress, tangentStress, sigmaNN, tauNT;
};

/// Hybrid mode, per node of the measured boundary and step: the prescribed (measured)
/// displacement, the nodal stress in polar components about the centre, the tractions of the
/// reactions, and the inferred friction coefficient (NaN where undetermined: |sigma_rr| or the
/// normal traction below the threshold).
struct HybridFields {
  std::vector<long> node;      ///< mesh node id
  std::vector<long> nodeIndex; ///< 0-based index of that node (the rows of the nodal arrays)
  std::vector<double> angle, ux, uy, sigmaRR, tauRT, muStress, tractionN, tractionT, muForce;
};

/// Host arrays of one step's fields (row-major); d = the mesh's dimension (2 today), s = its Voigt
/// size (3: xx, yy, xy), the components of the mesh's row of the output table
/// (io/OutputLayout.hpp).
struct StepFields {
  std::vector<double> displacement; ///< N x d (written N x 3, z = 0 in 2D, for ParaView)
  std::vector<double> stress;       ///< N x s nodal Cauchy stress (Voigt order)
  std::vector<double> reaction;     ///< N x d (internal minus external force; nonzero at supports)
  std::vector<double> gaussCoordinates; ///< (E * nq) x d
  std::vector<double> gaussStress;      ///< (E * nq) x s
  int pointsPerElement = 0;
  /// Geometrically nonlinear runs (empty otherwise): du/dx (d x d per point, row-major; in 2D
  /// du/dx, du/dy, dv/dx, dv/dy), current point coordinates, and (mixed model) the nodal stresses
  /// interpolated there.
  std::vector<double> gaussGradient, gaussCurrentCoordinates, gaussInterpolatedStress;
  std::string stressSource;      ///< how the nodal stresses were obtained (an HDF5 attribute)
  std::string gaussStressSource; ///< how the Gauss-point stresses were obtained (an attribute)
  ContactFields contact;         ///< empty without contact
  HybridFields hybrid;           ///< empty outside the hybrid mode
};

/// Which optional node arrays a written step has (for the XDMF index).
struct StepArrays {
  bool reaction = false, contact = false, hybrid = false;
};

/// A step as written: its record, its summary.json entry and its optional node arrays.
struct WrittenStep {
  StepRecord record;
  std::string summary;
  StepArrays arrays;
};

struct RestartPoint; // io/Restart.hpp

class ResultsWriter {
public:
  /// Locks `directory` (created with its parents) for this run, removes the output files of an
  /// earlier run there (results.h5, results.d/, results.xdmf, summary.json, contact.csv,
  /// hybrid.csv) and, if `hdf5`, writes the mesh. With `resume`, keeps that run's steps up to
  /// resume->lastStep() instead (and drops its later ones) and continues after them. Throws
  /// std::runtime_error naming the file and the system's reason when something cannot be
  /// written, or when another run holds the folder.
  ResultsWriter(std::string directory, const Mesh &mesh, bool hdf5, std::string problemFile,
                const RestartPoint *resume = nullptr);
  ~ResultsWriter();
  ResultsWriter(const ResultsWriter &) = delete;
  ResultsWriter &operator=(const ResultsWriter &) = delete;

  /// Writes a step (its HDF5 file, then results.h5, results.xdmf and summary.json); `state`, if
  /// given, is saved with it for a restart. Throws std::runtime_error on a failed write.
  void writeStep(const StepRecord &record, const StepFields &fields,
                 const Checkpoint *state = nullptr);
  /// Adds a raw JSON member (e.g. "verification": {...}) to summary.json and rewrites it.
  void setSummaryExtra(const std::string &key, const std::string &jsonValue);
  /// Marks the run finished (or failed, with a message) in summary.json.
  void finish(bool success, const std::string &message);

  const std::string &directory() const { return directory_; }

private:
  void writeXdmf() const;
  void writeSummary() const;
  void writeMesh() const;
  /// results.h5: external links to results.d/mesh.h5 and to every step's file.
  void writeIndex() const;
  void resumeFrom(const RestartPoint &point);
  void writeState(long long group, const Checkpoint &state) const;
  void writeContact(long long group, const StepRecord &record, const ContactFields &c);
  /// /steps/k/contact_nodal: the candidates' status, gap and tractions as arrays over all nodes.
  void writeContactNodal(long long group, const ContactFields &c) const;

  std::string directory_;
  std::string problemFile_;
  const Mesh &mesh_;
  bool hdf5_;
  int lock_ = -1;                             ///< file descriptor holding the folder's lock
  int uncaught_ = std::uncaught_exceptions(); ///< at construction (to see an error unwinding)
  std::vector<WrittenStep> steps_;
  std::vector<std::pair<std::string, std::string>> extra_;
  bool contactCsvStarted_ = false, hybridCsvStarted_ = false;
  void writeHybrid(long long group, const StepRecord &r, const HybridFields &h);
  /// A CSV of this run's output folder opened for appending one step's rows: created with its
  /// header by the first call (`started` false), appended to afterwards (10 digits).
  std::ofstream appendCsv(const std::string &name, bool &started, const char *header) const;
  std::string status_ = "running";
  std::string message_;
};

/// JSON string literal with escapes.
std::string jsonString(const std::string &s);

} // namespace mixcon
