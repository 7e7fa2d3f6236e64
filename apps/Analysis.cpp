// runAnalysis: builds the displacement or the mixed model from a Problem, steps through the load
// factors, prints a progress line per step, and writes HDF5/XDMF/summary.json.
#include <apps/Analysis.hpp>
#include <apps/Stages.hpp>
#include <contact/RigidContact.hpp>
#include <contact/SurfaceContact.hpp>
#include <io/Measurements.hpp>
#include <io/Restart.hpp>
#include <solver/DisplacementModel.hpp>
#include <solver/Environment.hpp>
#include <solver/MixedModel.hpp>
#include <solver/Nonlinear.hpp>
#include <solver/SolidMixedModel.hpp>
#include <solver/SolidNonlinearMixedModel.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <ostream>
#include <sstream>

namespace mixcon {

namespace {

/// The boundary length (times thickness) each node of `edges` stands for, the row sums of the
/// edges' boundary mass matrix t int N_a ds (3-point Gauss), in the configuration the nodal
/// forces refer to: X + u with geometric nonlinearity, X with small displacements (u == nullptr).
std::vector<double> boundaryShares(const Mesh &mesh, const std::vector<BoundaryEdge> &edges,
                                   const std::vector<double> *u, double thickness) {
  std::vector<double> share(mesh.numNodes(), 0.0);
  const int npe = mesh.elementType == ElementType::Quad8 ? 3 : 2;
  const double gs[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, gw[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  for (const auto &e : edges) {
    LocalIndex nodes[3];
    double x[3][2];
    for (int k = 0; k < npe; ++k) {
      nodes[k] = mesh.edgeNode(e, k);
      x[k][0] = mesh.x(nodes[k]) + (u ? (*u)[2 * nodes[k]] : 0.0);
      x[k][1] = mesh.y(nodes[k]) + (u ? (*u)[2 * nodes[k] + 1] : 0.0);
    }
    for (int q = 0; q < 3; ++q) {
      double n3[3], d3[3], n2[2], d2[2];
      if (npe == 3) {
        edgeShape<3>(gs[q], n3, d3);
      } else {
        edgeShape<2>(gs[q], n2, d2);
        for (int k = 0; k < 2; ++k) {
          n3[k] = n2[k];
          d3[k] = d2[k];
        }
      }
      double tx = 0.0, ty = 0.0;
      for (int k = 0; k < npe; ++k) {
        tx += d3[k] * x[k][0];
        ty += d3[k] * x[k][1];
      }
      const double ds = std::hypot(tx, ty) * gw[q] * thickness;
      for (int k = 0; k < npe; ++k)
        share[nodes[k]] += n3[k] * ds;
    }
  }
  return share;
}

/// How the displacement model's nodal stresses are recovered (summary.json, HDF5 attribute).
std::string nodalStressSource(ElementType type) {
  return dispatchElement(type, [](auto elem) -> std::string {
    using Elem = decltype(elem);
    if constexpr (Elem::kDim == 2)
      return "2x2 Gauss-point stresses extrapolated to the nodes and averaged";
    else if constexpr (Elem::kSimplex)
      return "C eps(u) at each element's nodes, averaged";
    else
      return "2x2x2 Gauss-point stresses extrapolated to the nodes and averaged";
  });
}

/// The problem's note on the AMG defaults it chose (Problem::solverDefaultsNote) as a log line,
/// where the AMG runs; else empty.
std::string solverDefaultsLine(const Problem &p) {
  if (p.solverDefaultsNote.empty() || p.solver.type != LinearSolverType::Amg)
    return {};
  return "mixcon: " + p.solverDefaultsNote + "\n";
}

std::string modelLine(const Problem &p, const ModelBase &model, bool mixed) {
  const int perNode = !mixed              ? p.mesh.dim()
                      : p.mesh.dim() == 3 ? FieldLayout<3>::kMixedUnknowns
                                          : FieldLayout<2>::kMixedUnknowns;
  std::ostringstream s;
  s << "mixcon: " << p.file << ": " << p.mesh.numNodes() << " nodes, " << p.mesh.numElements()
    << " " << elementTypeName(p.mesh.elementType) << " elements, " << p.mesh.dim() << "D "
    << (mixed ? "mixed model, " : "displacement model, ")
    << (p.model.geometricNonlinearity ? "geometrically nonlinear, " : "")
    << static_cast<long>(p.mesh.numNodes()) * perNode << " unknowns, " << model.numConstrained()
    << " constrained; " << Environment::describe() << "\n";
  return s.str();
}

/// Writes a step (with the state a restart needs, if given), keeps its fields in the result and
/// prints its progress line (with ETA from the steps this process ran after `firstStep`, and the
/// contact counts) to `log`, in hybrid mode a second line with the inferred friction
/// coefficients; with `verbose`, also the obstacle motions (obstacles named as in `contacts`).
void recordStep(ResultsWriter &writer, RunResult &result, const StepRecord &r, StepFields &f,
                std::ostream *log, bool verbose, const std::vector<ContactSpec> &contacts,
                int nsteps, int nstages, std::chrono::steady_clock::time_point start,
                const Checkpoint *state = nullptr, int firstStep = 0) {
  writer.writeStep(r, f, state);
  result.steps.push_back(r);
  result.displacement = std::move(f.displacement);
  result.stress = std::move(f.stress);
  if (!log)
    return;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double eta = elapsed / (r.step - firstStep) * (nsteps - r.step);
  char contact[160] = "";
  if (r.contactClosed >= 0)
    std::snprintf(contact, sizeof contact,
                  "  contact: %d nodes closed (%d stick, %d slip), %d updates%s", r.contactClosed,
                  r.contactStick, r.contactSlip, r.contactIterations,
                  r.contactCycled ? ", active set CYCLED (last pattern kept)" : "");
  char line[400];
  if (!r.stageName.empty()) { // a load history: the stage first
    std::snprintf(line, sizeof line, "stage %d/%d '%s'  ", r.stage, nstages, r.stageName.c_str());
    *log << line;
  }
  std::snprintf(line, sizeof line,
                "step %d/%d  load factor %.4g  iterations %d  cuts %d  linear its %d  residual "
                "%.2e  %s%s  %.3f s  ETA %.1f s\n",
                r.step, nsteps, r.loadFactor, r.iterations, r.cuts, r.linearIterations, r.residual,
                r.converged ? "converged" : "NOT CONVERGED", contact, r.totalSeconds, eta);
  *log << line;
  if (verbose) {
    for (std::size_t o = 0; 2 * o + 1 < r.obstacleMotion.size(); ++o)
      if (r.obstacleMotion[2 * o] != 0.0 || r.obstacleMotion[2 * o + 1] != 0.0) {
        std::snprintf(line, sizeof line, "        obstacle %zu ('%s') moved by (%.6g, %.6g)\n",
                      o + 1, o < contacts.size() ? contacts[o].boundary.c_str() : "",
                      r.obstacleMotion[2 * o], r.obstacleMotion[2 * o + 1]);
        *log << line;
      }
  }
  if (!f.hybrid.node.empty()) {
    double lo = 1e300, hi = -1e300;
    int determined = 0;
    for (double m : f.hybrid.muForce)
      if (std::isfinite(m)) {
        lo = std::min(lo, m);
        hi = std::max(hi, m);
        ++determined;
      }
    if (determined > 0)
      std::snprintf(line, sizeof line,
                    "        hybrid: measured load %.6g, mu from the hole tractions %.3f to %.3f "
                    "at %d of %zu nodes (the others undetermined)\n",
                    r.measuredLoad, lo, hi, determined, f.hybrid.node.size());
    else
      std::snprintf(line, sizeof line,
                    "        hybrid: measured load %.6g, mu undetermined everywhere (no "
                    "compression above the threshold)\n",
                    r.measuredLoad);
    *log << line;
  }
  *log << std::flush;
}

/// Hybrid mode, one step: polar stresses, reaction tractions and the inferred friction
/// coefficient at the nodes of the measured boundary (f.stress and f.reaction must be set).
void hybridFields(const Problem &p, const BoundaryValues &b, const std::vector<double> &u,
                  StepFields &f, StepRecord &r) {
  const HybridSpec &h = *p.hybrid;
  const auto share =
      boundaryShares(p.mesh, p.mesh.boundaries.at(h.boundary),
                     p.model.geometricNonlinearity ? &u : nullptr, p.model.thickness);
  auto &out = f.hybrid;
  double peakS = 0.0, peakT = 0.0;
  for (std::size_t i = 0; i < b.nodes.size(); ++i) {
    const LocalIndex n = b.nodes[i];
    const double th = b.theta[i], n0 = std::cos(th), n1 = std::sin(th);
    double snn = 0.0, snt = 0.0;
    surfaceStress(&f.stress[3 * n], n0, n1, snn, snt);
    const double gx = f.reaction[2 * n], gy = f.reaction[2 * n + 1];
    out.node.push_back(p.mesh.nodeIds.empty() ? n + 1 : p.mesh.nodeIds[n]);
    out.nodeIndex.push_back(n);
    out.angle.push_back(th);
    out.ux.push_back(b.ux[i]);
    out.uy.push_back(b.uy[i]);
    out.sigmaRR.push_back(snn);
    out.tauRT.push_back(snt);
    out.tractionN.push_back(share[n] > 0.0 ? (gx * n0 + gy * n1) / share[n] : 0.0);
    out.tractionT.push_back(share[n] > 0.0 ? (-gx * n1 + gy * n0) / share[n] : 0.0);
    peakS = std::max(peakS, -out.sigmaRR.back());
    peakT = std::max(peakT, out.tractionN.back());
  }
  // mu only where the surface is in compression by more than the threshold times the peak:
  // elsewhere the ratio divides by (nearly) zero and is reported as undetermined (NaN).
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < out.node.size(); ++i) {
    const double s = -out.sigmaRR[i], t = out.tractionN[i];
    out.muStress.push_back(
        peakS > 0.0 && s > h.threshold * peakS && s > 0.0 ? std::abs(out.tauRT[i]) / s : nan);
    out.muForce.push_back(
        peakT > 0.0 && t > h.threshold * peakT && t > 0.0 ? std::abs(out.tractionT[i]) / t : nan);
  }
  r.measuredLoad = h.steps[static_cast<std::size_t>(r.step - 1)].load;
  r.asymmetry = b.asymmetry;
}

/// The geometrically nonlinear analysis: load stepping with equilibrium iterations.
/// Per-candidate contact output of one step (rigid obstacles or node-to-segment pairs): status,
/// gap, multipliers, tractions (forces over the node's share of its boundary), the nodal stress
/// rotated to the contact frame, angle and arc coordinate, current position; and the counts.
template <class Contact>
void contactFields(const Contact &contact, const Problem &p, const std::vector<double> &u,
                   StepFields &f, StepRecord &r) {
  r.contactClosed = contact.numClosed();
  bool first = true;
  std::vector<std::vector<double>> shares;
  for (const auto &spec : p.contact)
    shares.push_back(boundaryShares(p.mesh, p.mesh.boundaries.at(spec.boundary),
                                    p.model.geometricNonlinearity ? &u : nullptr,
                                    p.model.thickness));
  auto &c = f.contact;
  for (LocalIndex k = 0; k < contact.numCandidates(); ++k) {
    const LocalIndex n = contact.candidateNode(k);
    const ContactStatus st = contact.status(k);
    c.obstacle.push_back(contact.obstacleOf(k));
    c.node.push_back(p.mesh.nodeIds.empty() ? n + 1 : p.mesh.nodeIds[n]);
    c.nodeIndex.push_back(n);
    c.status.push_back(static_cast<int>(st));
    c.gap.push_back(contact.gap(k));
    c.normalForce.push_back(st == ContactStatus::Open ? 0.0 : contact.normalForce(k));
    c.tangentForce.push_back(st == ContactStatus::Open ? 0.0 : contact.tangentForce(k));
    const double share = shares[contact.obstacleOf(k)][n];
    c.normalStress.push_back(share > 0.0 ? c.normalForce.back() / share : 0.0);
    c.tangentStress.push_back(share > 0.0 ? c.tangentForce.back() / share : 0.0);
    const double n0 = contact.normal(k)[0], n1 = contact.normal(k)[1];
    double snn = 0.0, snt = 0.0;
    surfaceStress(&f.stress[3 * n], n0, n1, snn, snt);
    c.sigmaNN.push_back(snn);
    c.tauNT.push_back(snt);
    c.angle.push_back(contact.angle(k));
    c.arc.push_back(contact.arcCoordinate(k));
    c.x.push_back(p.mesh.x(n) + u[2 * n]);
    c.y.push_back(p.mesh.y(n) + u[2 * n + 1]);
    r.contactStick += st == ContactStatus::Stick;
    r.contactSlip += st == ContactStatus::Slip;
    if (st != ContactStatus::Open) {
      const double a = contact.arcCoordinate(k);
      r.contactArcMin = first ? a : std::min(r.contactArcMin, a);
      r.contactArcMax = first ? a : std::max(r.contactArcMax, a);
      first = false;
    }
  }
}

/// One step of a run: its stage (0-based) and its load factor within the stage.
struct ScheduledStep {
  int stage = 0;
  double loadFactor = 0.0;
};

/// The steps of all stages in order.
std::vector<ScheduledStep> schedule(const std::vector<StagePlan> &plan) {
  std::vector<ScheduledStep> steps;
  for (std::size_t s = 0; s < plan.size(); ++s)
    for (double f : plan[s].loadFactors)
      steps.push_back({static_cast<int>(s), f});
  return steps;
}

/// The restart point in `directory`, checked against the problem: the same mesh and the same
/// stages and load factors up to the restart step (later steps may differ, e.g. smaller
/// increments).
RestartPoint restartPoint(const Problem &p, const std::vector<ScheduledStep> &steps,
                          const std::string &directory) {
  RestartPoint point = readRestart(directory);
  const std::string from = directory + "/results.h5";
  const Mesh &mesh = p.mesh;
  bool same = point.numNodes == mesh.numNodes() && point.numElements == mesh.numElements() &&
              point.nodes.size() == mesh.coordinates.size();
  double scale = 1.0;
  for (double x : mesh.coordinates)
    scale = std::max(scale, std::abs(x));
  for (std::size_t i = 0; same && i < point.nodes.size(); ++i)
    same = std::abs(point.nodes[i] - mesh.coordinates[i]) <= 1e-12 * scale;
  if (!same)
    throw InputError(from + ": its mesh (" + std::to_string(point.numNodes) + " nodes, " +
                     std::to_string(point.numElements) + " elements) is not the mesh of " + p.file +
                     " (" + std::to_string(mesh.numNodes()) + " nodes, " +
                     std::to_string(mesh.numElements()) + " elements)");
  const int last = point.lastStep();
  if (last >= static_cast<int>(steps.size()))
    throw InputError(from + ": the run already ended at step " + std::to_string(last) + " of " +
                     std::to_string(steps.size()) + "; nothing to restart");
  for (int i = 0; i < last; ++i) {
    const StepRecord &saved = point.steps[i].record;
    const double now = steps[i].loadFactor;
    if (std::abs(saved.loadFactor - now) > 1e-12 * std::max(1.0, std::abs(now)) ||
        saved.stage != steps[i].stage + 1) {
      std::ostringstream m;
      m << from << ": step " << i + 1 << " ran in stage " << saved.stage << " at load factor "
        << saved.loadFactor << ", but " << p.file << " gives stage " << steps[i].stage + 1 << " at "
        << now << " for it; the steps up to the restart point (" << last << ") must be the same";
      throw InputError(m.str());
    }
  }
  return point;
}

RunResult runNonlinear(const Problem &p, const RunOptions &options, MPI_Comm comm,
                       const std::vector<int> &elementMaterial,
                       const std::vector<PlaneMatrix> &stiffness,
                       const std::vector<SolidMatrix> &solidStiffness, RunResult result) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  // Warnings (failures) go to options.log whatever the verbosity; progress lines unless Quiet.
  std::ostream *warn = options.log;
  std::ostream *log = options.verbosity == Verbosity::Quiet ? nullptr : options.log;
  const bool verbose = options.verbosity == Verbosity::Verbose;
  const bool mixed = p.model.formulation == Formulation::Mixed;
  std::unique_ptr<NonlinearModel> owner;
  const NonlinearMixedModel *mixedModel = nullptr; // the mixed model's own output
  if (mixed && p.mesh.dim() == 3) {
    auto m = std::make_unique<SolidNonlinearMixedModel>(p.mesh, elementMaterial, solidStiffness,
                                                        p.model.mixed.stabilization);
    m->setForm(p.model.mixedForm);
    m->setStressUpdate(p.model.stressUpdate);
    m->setIterativeSolver(p.model.mixedNewton);
    owner = std::move(m);
  } else if (mixed) {
    auto m = std::make_unique<NonlinearMixedModel>(p.mesh, elementMaterial, stiffness,
                                                   p.model.thickness);
    mixedModel = m.get();
    m->setForm(p.model.mixedForm);
    m->setStressUpdate(p.model.stressUpdate);
    m->setStabilization(p.model.mixed.stabilization);
    m->setIterativeSolver(p.model.mixedNewton);
    owner = std::move(m);
  } else {
    auto d =
        p.mesh.dim() == 3
            ? std::make_unique<NonlinearDisplacementModel>(p.mesh, elementMaterial, solidStiffness)
            : std::make_unique<NonlinearDisplacementModel>(p.mesh, elementMaterial, stiffness,
                                                           p.model.thickness);
    d->setTangent(p.tangent);
    d->setElasticLaw(p.model.elasticLaw);
    owner = std::move(d);
  }
  NonlinearModel &model = *owner;
  // A linear body in contact or with stages: the linear model's residual in the iterating driver.
  model.setSmallDisplacements(!p.model.geometricNonlinearity);
  const std::vector<StagePlan> plan = planStages(p);
  const std::vector<ScheduledStep> steps = schedule(plan);
  applyConditions(p.mesh, plan[0].dirichlet, plan[0].loads, model,
                  p.model.geometricNonlinearity ? &model : nullptr);
  std::unique_ptr<RigidContact> contact;
  std::unique_ptr<SurfaceContact> surface;
  if (!p.contact.empty() && p.contact.front().type == "node_to_segment") {
    std::vector<SurfaceContactSpec> specs;
    for (const auto &c : p.contact) {
      SurfaceContactSpec s;
      s.contactor = p.mesh.nodesOf(c.boundary);
      s.target = boundarySegments(p.mesh, c.target);
      s.friction = c.friction;
      s.name = c.boundary + " -> " + c.target;
      specs.push_back(s);
    }
    surface = std::make_unique<SurfaceContact>(p.mesh.numNodes(), specs, p.mesh.nodeIds);
    model.setContact(surface.get());
  } else if (!p.contact.empty()) {
    std::vector<RigidContactSpec> specs;
    for (const auto &c : p.contact) {
      RigidContactSpec s;
      s.obstacle.kind = c.type == "rigid_circle" ? ObstacleKind::Circle : ObstacleKind::HalfPlane;
      s.obstacle.point[0] = c.point[0];
      s.obstacle.point[1] = c.point[1];
      s.obstacle.radius = c.radius;
      s.obstacle.normal[0] = c.normal[0];
      s.obstacle.normal[1] = c.normal[1];
      s.friction = c.friction;
      const std::size_t index = specs.size();
      for (int i = 0; i < 2; ++i) {
        s.drive[i] = plan[0].drive[index][i];
        s.forceDriven[i] = c.forceDriven[i];
        s.force[i] = plan[0].force[index][i];
      }
      s.statusFromStress = c.statusFromStress;
      s.nodes = p.mesh.nodesOf(c.boundary);
      s.name = c.boundary;
      specs.push_back(s);
    }
    contact = std::make_unique<RigidContact>(p.mesh.numNodes(), specs, p.mesh.nodeIds);
    model.setContact(contact.get());
  }
  // Hybrid mode: both displacement components of the measured boundary are prescribed; their
  // values come from the measurements, interpolated and symmetrized per step (checked here, before
  // any solve, so that a file that does not cover the boundary fails at once).
  std::vector<LocalIndex> hybridNodes;
  std::vector<BoundaryValues> measured;
  if (p.hybrid) {
    hybridNodes = p.mesh.nodesOf(p.hybrid->boundary);
    for (LocalIndex n : hybridNodes)
      for (int c = 0; c < 2; ++c)
        model.prescribe(n, c, 0.0);
    for (const auto &step : p.hybrid->steps) {
      const AngularProfile profile(step, p.hybrid->center);
      measured.push_back(boundaryValues(p.mesh, hybridNodes, profile, p.hybrid->center,
                                        p.hybrid->symmetrize, step.step));
    }
    if (log) {
      *log << "mixcon: hybrid mode: " << p.hybrid->steps.size() << " measured steps from "
           << p.hybrid->measurements << " prescribed on " << hybridNodes.size() << " nodes of '"
           << p.hybrid->boundary << "' (piecewise linear in the angle about the centre)";
      if (p.hybrid->symmetrize)
        *log << ", mirrored halves averaged";
      *log << "\n";
      for (std::size_t k = 0; k < measured.size(); ++k)
        if (measured[k].asymmetry >= 0.0) {
          char line[160];
          std::snprintf(line, sizeof line,
                        "        step %zu: load %.6g, asymmetry of the measurements %.3g %% of "
                        "the largest displacement\n",
                        k + 1, p.hybrid->steps[k].load, 100.0 * measured[k].asymmetry);
          *log << line;
        }
    }
  }
  std::optional<RestartPoint> restart;
  if (!options.restartDirectory.empty())
    restart = restartPoint(p, steps, options.restartDirectory);
  ResultsWriter writer(result.outputDirectory, p.mesh, p.writeHdf5, p.file,
                       restart ? &*restart : nullptr);
  if (log)
    *log << modelLine(p, model, mixed);
  // Without contact nothing but the supports holds the bodies: a free rigid-body mode is an
  // input error, named before any solve (bodies in contact may rest on obstacles or each other).
  if (p.contact.empty()) {
    model.checkRigidBodyModes();
    checkStageSupports(p, plan, model); // every later stage's, before any solve
  }
  model.setup(p.solver, comm);
  if (log)
    *log << "mixcon: " << iterationMethodName(p.nonlinear.method) << " iterations, epsilon "
         << p.nonlinear.tolerance << ", residual tolerance " << p.nonlinear.residualTolerance
         << ", linear solver " << model.solverName() << "\n"
         << solverDefaultsLine(p);
  LoadStepper stepper(model, plan[0].nonlinear, warn, options.verbosity);
  const int nsteps = static_cast<int>(steps.size());
  const int nstages = static_cast<int>(plan.size());
  const int firstStep = restart ? restart->lastStep() : 0;
  int stage = 0; // the stage the model is in
  const auto announce = [&](int s) {
    if (log)
      *log << "mixcon: stage " << s + 1 << "/" << nstages << " '" << plan[s].name << "' ("
           << plan[s].loadFactors.size() << " steps)\n";
  };
  // Moves the model into stage `next` (0-based); `restoring`: a restart then restores the loading.
  const auto beginStage = [&](int next, bool restoring) {
    std::vector<double> reaction;
    if (!restoring) { // the support forces that releases carry over
      model.evaluate(1.0, false);
      reaction = model.reactionHost(1.0);
    }
    enterStage(p, plan, next, model, contact.get(), restoring ? nullptr : &reaction);
    stepper.setOptions(plan[next].nonlinear);
    stepper.resume(0.0);
    stage = next;
    if (!restoring)
      announce(next);
  };
  if (nstages > 1 && !restart)
    announce(0);
  if (restart) {
    const std::string from = restart->directory + "/results.h5";
    try {
      if (restart->state.has("stepper/stage")) {
        const int saved = static_cast<int>(restart->state.getScalar("stepper/stage")) - 1;
        if (saved != steps[firstStep - 1].stage)
          throw std::runtime_error("the saved state is of stage " + std::to_string(saved + 1) +
                                   ", its step of stage " +
                                   std::to_string(steps[firstStep - 1].stage + 1));
        if (restart->state.has("stepper/history") &&
            restart->state.get("stepper/history", 2) != historyFingerprint(plan, saved))
          throw std::runtime_error(
              "its load history up to the restart point (stage " + std::to_string(saved + 1) +
              ") is not the one of " + p.file +
              ": the supports, loads and drives of the stages run so far must be the same");
        if (saved > 0)
          beginStage(saved, true);
      }
      // Finite or small-displacement kinematics (states saved before this record: not checked).
      if (restart->state.has("model/geometric_nonlinearity") &&
          (restart->state.getScalar("model/geometric_nonlinearity") != 0.0) !=
              p.model.geometricNonlinearity)
        throw std::runtime_error(
            std::string("the saved state is of a ") +
            (p.model.geometricNonlinearity ? "linear run (small displacements)"
                                           : "geometrically nonlinear run") +
            ", this problem is " +
            (p.model.geometricNonlinearity ? "geometrically nonlinear" : "linear"));
      model.restoreLoading(restart->state);
      if (restart->state.has("stepper/history_scales"))
        model.setHistoryScales(restart->state.get("stepper/history_scales", 3));
      model.restoreCommitted(restart->state);
      if (model.contactIterations())
        model.contactIterations()->restoreCommitted(restart->state);
      stepper.resume(restart->state.getScalar("stepper/load_factor"));
    } catch (const std::runtime_error &e) {
      throw InputError(from + ": " + e.what() + " (restart with the problem file of that run)");
    }
    for (const WrittenStep &w : restart->steps)
      result.steps.push_back(w.record);
    if (log)
      *log << "mixcon: restarting from step " << firstStep << " of " << from << " (load factor "
           << stepper.loadFactor() << ")\n";
  }
  result.converged = true;
  for (int k = firstStep; k < nsteps; ++k) {
    if (steps[k].stage != stage)
      beginStage(steps[k].stage, false);
    const auto stepStart = clock::now();
    const double lambda = steps[k].loadFactor;
    const double setupBefore = model.solverSetupSeconds();
    if (p.hybrid) {
      // The stepper prescribes lambda times the reference value: reference = measured / lambda.
      std::vector<ModelBase::PrescribedValue> values;
      const BoundaryValues &b = measured[k];
      for (std::size_t i = 0; i < b.nodes.size(); ++i) {
        values.push_back({b.nodes[i], 0, b.ux[i] / lambda});
        values.push_back({b.nodes[i], 1, b.uy[i] / lambda});
      }
      model.updatePrescribed(values);
    }
    const IncrementOutcome o = stepper.advance(lambda);
    StepRecord r;
    r.step = k + 1;
    r.loadFactor = o.converged ? lambda : stepper.loadFactor();
    r.stage = stage + 1;
    r.stageName = plan[stage].name;
    r.time = stage + r.loadFactor;
    r.iterations = o.iterations;
    r.linearIterations = o.linearIterations;
    r.residual = o.history.empty() ? o.initialResidual : o.history.back().residual;
    r.setupSeconds = model.solverSetupSeconds() - setupBefore;
    r.solveSeconds = o.solveSeconds;
    r.converged = o.converged;
    r.cuts = o.cuts;
    r.residualHistory.push_back(o.initialResidual);
    for (const auto &h : o.history) {
      r.residualHistory.push_back(h.residual);
      r.incrementHistory.push_back(h.increment);
    }
    StepFields f;
    f.displacement = model.displacementHost();
    f.stress = model.nodalStressHost();
    // Tetrahedra evaluate the law at their nodes (recoverSolidNodalStress), the others
    // extrapolate from the Gauss points.
    const std::string recovered =
        p.mesh.elementType == ElementType::Tet4 || p.mesh.elementType == ElementType::Tet10
            ? "evaluated at each element's nodes and averaged"
            : "Gauss points extrapolated to the nodes and averaged";
    f.stressSource =
        mixed ? (p.model.mixedForm == MixedForm::Incremental
                     ? "nodal Cauchy stress of the mixed model (2nd Piola-Kirchhoff increments "
                       "pushed forward at the nodes, Eq. (5b))"
                 : !p.model.geometricNonlinearity
                     ? "nodal stress unknowns of the mixed model (no smoothing)" // as linear runs
                     : "nodal Cauchy stress unknowns of the mixed model (current form)")
        : !p.model.geometricNonlinearity
            ? "Cauchy stress of the linear law (small displacements), " + recovered
        : p.model.elasticLaw == ElasticLaw::SaintVenantKirchhoff
            ? "Cauchy stress F S F^T / J of the St. Venant-Kirchhoff law, " + recovered
            : "Cauchy stress from the Almansi strain (Eq. (26)), " + recovered;
    // The Gauss-point stresses come from the displacements through the displacement model's law
    // (the mixed model's too: its law is the Almansi one), on the reference configuration for a
    // linear body (small displacements).
    f.gaussStressSource =
        !p.model.geometricNonlinearity
            ? "C eps(u) from the displacements (small displacements, linear law)"
        : !mixed && p.model.elasticLaw == ElasticLaw::SaintVenantKirchhoff
            ? "Cauchy stress F S F^T / J of the St. Venant-Kirchhoff law (S = C E(u), Green "
              "strain) from the displacements"
            : "Cauchy stress C e(u) from the Almansi strain of the displacements (Eq. (26))";
    f.reaction = model.reactionHost(lambda);
    if (p.writeHdf5) { // only results.h5 holds the Gauss-point fields
      model.gaussPointFieldsHost(f.gaussCoordinates, f.gaussStress, f.pointsPerElement,
                                 f.gaussGradient, f.gaussCurrentCoordinates);
      if (mixedModel)
        f.gaussInterpolatedStress = mixedModel->interpolatedGaussStressHost();
    }
    if (contact) {
      contactFields(*contact, p, model.displacementHost(), f, r);
      for (std::size_t sp = 0; sp < contact->specs().size(); ++sp)
        for (int i = 0; i < 2; ++i)
          r.obstacleMotion.push_back(contact->obstacleMotion(static_cast<int>(sp))[i]);
    }
    if (surface)
      contactFields(*surface, p, model.displacementHost(), f, r);
    if (contact || surface) {
      r.contactIterations = o.contactIterations;
      r.contactCycled = o.contactCycled;
    }
    if (p.hybrid)
      hybridFields(p, measured[k], model.displacementHost(), f, r);
    r.totalSeconds = std::chrono::duration<double>(clock::now() - stepStart).count();
    Checkpoint state; // what a restart from this step needs
    if (o.converged) {
      model.saveCommitted(state);
      state.putScalar("model/geometric_nonlinearity", p.model.geometricNonlinearity ? 1.0 : 0.0);
      if (model.contactIterations())
        model.contactIterations()->saveCommitted(state);
      state.putScalar("stepper/load_factor", stepper.loadFactor());
      state.putScalar("stepper/stage", stage + 1);
      state.put("stepper/history_scales", model.historyScales());
      state.put("stepper/history", historyFingerprint(plan, stage));
      model.saveLoading(state);
    }
    recordStep(writer, result, r, f, log, verbose, p.contact, nsteps, nstages, start,
               o.converged ? &state : nullptr, firstStep);
    if (!o.converged) {
      result.converged = false;
      writer.finish(false, "step " + std::to_string(k + 1) + ": " + o.message +
                               "; the results of the converged steps are in the output");
      if (warn)
        *warn << "mixcon: step " << k + 1 << " failed: " << o.message << "\n";
      return result;
    }
  }
  if (const CapacitanceSolve &kept = model.keptFactorization(); kept.solves() > 0) {
    // Contact corrections solved on a kept factorization (solver/CapacitanceSolve.hpp).
    result.keptFactorizationCorrections = kept.solves();
    result.keptFactorizations = kept.factorizations();
    writer.setSummaryExtra("kept_factorization",
                           "{\"factorizations\": " + std::to_string(kept.factorizations()) +
                               ", \"corrections\": " + std::to_string(kept.solves()) + "}");
    if (log)
      *log << "mixcon: " << kept.solves() << " contact corrections solved on "
           << kept.factorizations() << " kept factorization"
           << (kept.factorizations() == 1 ? "" : "s") << " of the stiffness\n";
  }
  writer.finish(true, "");
  if (log)
    *log << "mixcon: wrote " << result.outputDirectory << "/{"
         << (p.writeHdf5 ? "results.h5, results.xdmf, " : "")
         << (contact || surface ? "contact.csv, " : "") << (p.hybrid ? "hybrid.csv, " : "")
         << "summary.json}\n";
  return result;
}

} // namespace

RunResult runAnalysis(const Problem &p, const RunOptions &options, MPI_Comm comm) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  RunResult result;
  result.outputDirectory =
      options.outputDirectory.empty() ? p.outputDirectory : options.outputDirectory;
  std::ostream *log = options.verbosity == Verbosity::Quiet ? nullptr : options.log;
  const bool verbose = options.verbosity == Verbosity::Verbose;

  // Materials per element through regions.
  std::vector<PlaneMatrix> stiffness;
  std::vector<SolidMatrix> solidStiffness;
  std::vector<int> materialOfRegion(p.mesh.regionNames.size(), -1);
  for (const auto &m : p.materials) {
    materialOfRegion[p.mesh.regionIndex(m.region)] = static_cast<int>(stiffness.size());
    stiffness.push_back(m.stiffness);
    solidStiffness.push_back(m.solid);
  }
  std::vector<int> elementMaterial(p.mesh.numElements());
  for (LocalIndex e = 0; e < p.mesh.numElements(); ++e)
    elementMaterial[e] = materialOfRegion[p.mesh.elementRegion[e]];

  if (p.model.geometricNonlinearity || !p.contact.empty() || p.hybrid || !p.stages.empty())
    return runNonlinear(p, options, comm, elementMaterial, stiffness, solidStiffness,
                        std::move(result));
  if (!options.restartDirectory.empty())
    throw InputError(p.file + ": --restart continues a nonlinear or contact analysis; this one is "
                              "linear without contact (its steps are independent: run it again)");

  const bool mixed = p.model.formulation == Formulation::Mixed;
  // Both owners typed, so each model's own setup and statistics need no cast.
  std::unique_ptr<MixedModel> mixedModel;
  std::unique_ptr<SolidMixedModel> solidMixedModel; // the 3D mixed model
  std::unique_ptr<LinearDisplacementModel> displacementModel;
  ModelBase *base = nullptr;
  if (mixed && p.mesh.dim() == 3) {
    solidMixedModel = std::make_unique<SolidMixedModel>(p.mesh, elementMaterial, solidStiffness,
                                                        p.model.mixed.stabilization);
    solidMixedModel->setIterativeSolver(p.model.mixed.preconditionerTolerance,
                                        p.model.mixedNewton.restart, p.model.mixedNewton.jacobian);
    base = solidMixedModel.get();
  } else if (mixed) {
    mixedModel = std::make_unique<MixedModel>(p.mesh, elementMaterial, stiffness, p.model.thickness,
                                              p.model.stressElement.value_or(p.mesh.elementType));
    base = mixedModel.get();
  } else {
    displacementModel =
        p.mesh.dim() == 3
            ? std::make_unique<LinearDisplacementModel>(p.mesh, elementMaterial, solidStiffness)
            : std::make_unique<LinearDisplacementModel>(p.mesh, elementMaterial, stiffness,
                                                        p.model.thickness);
    base = displacementModel.get();
  }
  ModelBase &model = *base;
  applyConditions(p.mesh, p.dirichlet, p.loads, model, nullptr);

  ResultsWriter writer(result.outputDirectory, p.mesh, p.writeHdf5, p.file);
  if (log)
    *log << modelLine(p, model, mixed);

  if (solidMixedModel) {
    solidMixedModel->setup(p.solver, comm);
  } else if (mixed) {
    MixedOptions o = p.model.mixed;
    o.linear = p.solver;
    mixedModel->setup(o, comm);
  } else {
    displacementModel->setup(p.solver, comm);
  }
  if (log) {
    char seconds[96]; // the solver's name apart: it can be longer than any fixed buffer
    std::snprintf(seconds, sizeof seconds, "mixcon: assembly %.3f s, solver setup %.3f s (",
                  model.assemblySeconds(), model.solverSetupSeconds());
    *log << seconds << model.solverName() << ")\n" << solverDefaultsLine(p);
  }
  const double setupCharged = model.assemblySeconds() + model.solverSetupSeconds();
  const int nsteps = static_cast<int>(p.loadFactors.size());
  result.converged = true;
  for (int k = 0; k < nsteps; ++k) {
    const auto stepStart = clock::now();
    const double lambda = p.loadFactors[k];
    const LinearSolveStats s = model.solve(lambda);
    if (log && !s.note.empty())
      *log << "    load factor " << lambda << ": " << s.note << "\n";
    StepRecord r;
    r.step = k + 1;
    r.loadFactor = lambda;
    r.time = lambda;
    r.iterations = 1;
    r.linearIterations = s.iterations;
    r.residual = s.relativeResidual;
    r.setupSeconds = k == 0 ? setupCharged : 0.0;
    r.solveSeconds = s.solveSeconds;
    r.converged = s.converged;

    StepFields f;
    f.displacement = model.displacementHost();
    f.stress = model.nodalStressHost();
    f.stressSource = mixed ? "nodal stress unknowns of the mixed model (no smoothing)"
                           : nodalStressSource(p.mesh.elementType);
    f.gaussStressSource = "C eps(u) from the displacements";
    if (p.writeHdf5) { // only results.h5 holds the reactions and the Gauss-point fields
      f.reaction = model.reactionHost(lambda);
      model.gaussPointStressHost(f.gaussCoordinates, f.gaussStress, f.pointsPerElement);
    }
    r.totalSeconds =
        std::chrono::duration<double>(clock::now() - stepStart).count() + r.setupSeconds;
    recordStep(writer, result, r, f, log, verbose, p.contact, nsteps, 1, start);
    if (log && verbose) {
      char line[256];
      if (mixedModel) {
        const MixedModel &m = *mixedModel;
        if (m.innerIterations() > 0 && m.operatorApplications() > 0) {
          std::snprintf(line, sizeof line,
                        "        inner CG on M: %.1f iterations per Schur "
                        "product (%ld products)\n",
                        static_cast<double>(m.innerIterations()) / m.operatorApplications(),
                        m.operatorApplications());
          *log << line;
        }
      }
      *log << std::flush;
    }
    if (!s.converged) {
      result.converged = false;
      writer.finish(false, "step " + std::to_string(k + 1) +
                               ": the linear solver did not converge (relative residual " +
                               std::to_string(s.relativeResidual) + " after " +
                               std::to_string(s.iterations) + " iterations)");
      return result;
    }
  }

  if (!p.verification.type.empty()) {
    result.verification = verify(p, result.displacement, result.stress, p.loadFactors.back());
    writer.setSummaryExtra("verification", result.verification->json());
    if (log)
      *log << result.verification->table();
  }
  writer.finish(true, "");
  if (log)
    *log << "mixcon: wrote " << result.outputDirectory << "/{"
         << (p.writeHdf5 ? "results.h5, results.xdmf, " : "") << "summary.json}\n";
  return result;
}

} // namespace mixcon
