// Load histories: the stages of a problem as the driver runs them (the loads, supports and
// obstacle drives each stage reaches), and the move of a model from one stage into the next:
// what the previous stage reached becomes the base, the new stage's changes the reference that
// its load factor scales (solver/ModelBase.hpp, beginStage). Data flow: apps (uses io, solver,
// contact).
#pragma once

#include <io/Problem.hpp>
#include <solver/NonlinearModel.hpp>

#include <array>
#include <string>
#include <vector>

namespace mixcon {

class RigidContact;

/// One stage as the driver runs it.
struct StagePlan {
  std::string name; ///< empty without stages
  std::vector<double> loadFactors;
  NonlinearOptions nonlinear;
  /// The supports entries that act at its start: the first stage's are every support (the
  /// top-level ones and its own), a later one's are its own (end values and releases).
  std::vector<DirichletSpec> dirichlet;
  /// The loads at its end; entries of the same kind and target sum.
  std::vector<LoadSpec> loads;
  /// Per entry of the problem's contact list: the obstacle's drive at the stage's end
  /// (displacement, and force on force-driven components).
  std::vector<std::array<double, 2>> drive, force;
  int line = 0;
};

/// The stages of `p`. Without `stages`, one stage: the top-level entries as they are, scaled by
/// the problem's load factors. With them, the first stage reaches the top-level entries and its
/// own (its own replace the top-level loads and drives of the same kind and target), and every
/// later stage replaces what it names and keeps the rest.
std::vector<StagePlan> planStages(const Problem &p);

/// The prescribed displacements of `dirichlet` and the `loads` on a model, each load times
/// `scale`; pressures marked follower go to `nonlinear` (geometrically nonlinear runs, else
/// nullptr) as follower pressures starting from `followerBase` times theirs.
void applyConditions(const Mesh &mesh, const std::vector<DirichletSpec> &dirichlet,
                     const std::vector<LoadSpec> &loads, ModelBase &model,
                     NonlinearModel *nonlinear, double scale = 1.0, double followerBase = 0.0);

/// Refuses, before the first solve, a later stage whose supports leave a body free to move as a
/// rigid body (a release that leaves a mechanism): the supports of `model` (the first stage's)
/// changed stage by stage as the plan prescribes and releases them, each checked
/// (ModelBase::checkRigidBodyModes). InputError "file:line: stage k 'name': ...". Bodies in
/// contact may rest on obstacles: call it without contact only.
void checkStageSupports(const Problem &p, const std::vector<StagePlan> &plan,
                        const ModelBase &model);

/// A fingerprint (64 bits as two 32-bit halves) of what the stages 0 ... `stage` apply: their
/// names, supports, loads and drives. A restart checks that the problem's history up to its
/// restart point is the saved run's.
std::vector<double> historyFingerprint(const std::vector<StagePlan> &plan, int stage);

/// Moves `model` from the end of stage `stage` - 1 into stage `stage` (0-based, >= 1): the loads,
/// prescribed values and follower pressures reached become the base, the stage's changes the
/// reference; released supports carry `reaction` (the reactions at the end of the previous
/// stage, N x dim; nullptr when a restart restores the loading afterwards); the rigid obstacles
/// of `contact` (may be nullptr) get their drives.
void enterStage(const Problem &p, const std::vector<StagePlan> &plan, int stage,
                NonlinearModel &model, RigidContact *contact, const std::vector<double> *reaction);

} // namespace mixcon
