// Load histories (apps/Stages.hpp): the stage plan and the move from one stage into the next.
#include <apps/Stages.hpp>
#include <contact/RigidContact.hpp>

#include <algorithm>
#include <cstdint>
#include <sstream>

namespace mixcon {

namespace {

bool sameLoad(const LoadSpec &a, const LoadSpec &b) {
  return a.kind == b.kind && a.target == b.target;
}

/// `base` with the entries of `changes` replacing those of the same kind and target.
std::vector<LoadSpec> replaced(const std::vector<LoadSpec> &base,
                               const std::vector<LoadSpec> &changes) {
  std::vector<LoadSpec> out;
  for (const auto &l : base)
    if (std::none_of(changes.begin(), changes.end(),
                     [&](const LoadSpec &c) { return sameLoad(c, l); }))
      out.push_back(l);
  out.insert(out.end(), changes.begin(), changes.end());
  return out;
}

/// Obstacle drives of `stage` applied to the drives `drive`, `force` (per contact entry).
void applyDrives(const Problem &p, const StageSpec &stage, StagePlan &plan) {
  for (const auto &d : stage.drives)
    for (std::size_t c = 0; c < p.contact.size(); ++c)
      if (p.contact[c].type != "node_to_segment" && p.contact[c].boundary == d.boundary)
        for (int i = 0; i < 2; ++i) {
          plan.drive[c][i] = d.displacement[i];
          plan.force[c][i] = d.force[i];
        }
}

/// `loads` without the follower pressures (`geometric`: they are follower loads).
std::vector<LoadSpec> deadLoads(const std::vector<LoadSpec> &loads, bool geometric) {
  std::vector<LoadSpec> out;
  for (const auto &l : loads)
    if (!(geometric && l.kind == LoadKind::Pressure && l.follower))
      out.push_back(l);
  return out;
}

} // namespace

std::vector<StagePlan> planStages(const Problem &p) {
  StagePlan first;
  first.loadFactors = p.loadFactors;
  first.nonlinear = p.nonlinear;
  first.dirichlet = p.dirichlet;
  first.loads = p.loads;
  for (const auto &c : p.contact) {
    first.drive.push_back(c.driveDisplacement);
    first.force.push_back(c.driveForce);
  }
  if (p.stages.empty())
    return {first};
  std::vector<StagePlan> plan;
  for (std::size_t s = 0; s < p.stages.size(); ++s) {
    const StageSpec &spec = p.stages[s];
    StagePlan stage = s == 0 ? first : plan.back();
    stage.name = spec.name;
    stage.loadFactors = spec.loadFactors;
    stage.nonlinear = spec.nonlinear;
    stage.line = spec.line;
    if (s == 0)
      stage.dirichlet.insert(stage.dirichlet.end(), spec.dirichlet.begin(), spec.dirichlet.end());
    else
      stage.dirichlet = spec.dirichlet;
    stage.loads = replaced(stage.loads, spec.loads);
    applyDrives(p, spec, stage);
    plan.push_back(stage);
  }
  return plan;
}

void checkStageSupports(const Problem &p, const std::vector<StagePlan> &plan,
                        const ModelBase &model) {
  std::vector<int> held = model.constrainedFlags();
  const int dim = p.mesh.dim();
  for (std::size_t s = 1; s < plan.size(); ++s) {
    for (const auto &bc : plan[s].dirichlet) {
      const std::optional<double> *values[3] = {&bc.ux, &bc.uy, &bc.uz};
      for (LocalIndex n : p.mesh.nodesOf(bc.target))
        for (int c = 0; c < dim; ++c) {
          int &flag = held[model.dofs().dof(n, c)];
          flag = *values[c] ? 1 : bc.release[c] ? 0 : flag;
        }
    }
    try {
      model.checkRigidBodyModes(held);
    } catch (const InputError &e) {
      throw InputError(p.file + ":" + std::to_string(plan[s].line) + ": stage " +
                       std::to_string(s + 1) + " '" + plan[s].name + "': " + e.what());
    }
  }
}

std::vector<double> historyFingerprint(const std::vector<StagePlan> &plan, int stage) {
  std::ostringstream t;
  t.precision(17);
  for (int s = 0; s <= stage && s < static_cast<int>(plan.size()); ++s) {
    const StagePlan &p = plan[static_cast<std::size_t>(s)];
    t << "stage " << p.name << "\n";
    for (const auto &d : p.dirichlet) {
      t << "bc " << d.target;
      for (const auto *v : {&d.ux, &d.uy, &d.uz}) {
        t << " ";
        if (*v)
          t << **v;
        else
          t << "-";
      }
      t << " " << d.release[0] << d.release[1] << d.release[2] << "\n";
    }
    for (const auto &l : p.loads)
      t << "load " << static_cast<int>(l.kind) << " " << l.target << " " << l.vector[0] << " "
        << l.vector[1] << " " << l.vector[2] << " " << l.pressure << " " << l.follower << "\n";
    for (std::size_t c = 0; c < p.drive.size(); ++c)
      t << "drive " << c << " " << p.drive[c][0] << " " << p.drive[c][1] << " " << p.force[c][0]
        << " " << p.force[c][1] << "\n";
  }
  // FNV-1a, 64 bits: the same on every build.
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char ch : t.str()) {
    h ^= ch;
    h *= 1099511628211ull;
  }
  return {static_cast<double>(h >> 32), static_cast<double>(h & 0xffffffffull)};
}

void applyConditions(const Mesh &mesh, const std::vector<DirichletSpec> &dirichlet,
                     const std::vector<LoadSpec> &loads, ModelBase &model,
                     NonlinearModel *nonlinear, double scale, double followerBase) {
  for (const auto &bc : dirichlet)
    for (LocalIndex n : mesh.nodesOf(bc.target)) {
      if (bc.ux)
        model.prescribe(n, 0, *bc.ux);
      if (bc.uy)
        model.prescribe(n, 1, *bc.uy);
      if (bc.uz)
        model.prescribe(n, 2, *bc.uz);
    }
  for (const auto &l : loads) {
    const std::array<double, 3> v{scale * l.vector[0], scale * l.vector[1], scale * l.vector[2]};
    switch (l.kind) {
    case LoadKind::Traction:
      model.addSideLoad(mesh.boundaries.at(l.target), v, 0.0);
      break;
    case LoadKind::Pressure:
      if (nonlinear && l.follower)
        nonlinear->addFollowerPressure(mesh.boundaries.at(l.target), scale * l.pressure,
                                       followerBase * l.pressure);
      else
        model.addSideLoad(mesh.boundaries.at(l.target), {0.0, 0.0, 0.0}, scale * l.pressure);
      break;
    case LoadKind::Force:
      for (LocalIndex n : mesh.nodesOf(l.target))
        model.addNodalForce(n, v);
      break;
    case LoadKind::BodyForce: {
      const int region = mesh.regionIndex(l.target);
      if (mesh.dim() == 3)
        model.addBodyForce3D([&mesh, region, v](double, double, double, LocalIndex e) {
          return mesh.elementRegion[e] == region ? v : std::array<double, 3>{0.0, 0.0, 0.0};
        });
      else
        model.addBodyForce([&mesh, region, v](double, double, LocalIndex e) {
          return mesh.elementRegion[e] == region ? std::array<double, 2>{v[0], v[1]}
                                                 : std::array<double, 2>{0.0, 0.0};
        });
      break;
    }
    }
  }
}

void enterStage(const Problem &p, const std::vector<StagePlan> &plan, int stage,
                NonlinearModel &model, RigidContact *contact, const std::vector<double> *reaction) {
  const StagePlan &from = plan.at(static_cast<std::size_t>(stage - 1));
  const StagePlan &to = plan.at(static_cast<std::size_t>(stage));
  const Mesh &mesh = p.mesh;
  NonlinearModel *follower = p.model.geometricNonlinearity ? &model : nullptr;
  model.beginStage();
  // The base: the dead loads the previous stage reached. The reference: the end minus the base.
  // Follower pressures: the previous ones ramp from their value to 0, the new ones from 0 up.
  model.clearFollowerPressures();
  applyConditions(mesh, {}, deadLoads(from.loads, follower != nullptr), model, nullptr);
  model.loadsToBase();
  applyConditions(mesh, {}, to.loads, model, follower);
  applyConditions(mesh, {}, from.loads, model, follower, -1.0, 1.0);
  const int dim = mesh.dim();
  for (const auto &bc : to.dirichlet) {
    applyConditions(mesh, {bc}, {}, model, nullptr);
    for (int c = 0; c < dim; ++c)
      if (bc.release[c])
        for (LocalIndex n : mesh.nodesOf(bc.target))
          model.release(n, c, reaction ? (*reaction)[static_cast<std::size_t>(dim) * n + c] : 0.0);
  }
  model.commitStage();
  if (contact)
    for (std::size_t c = 0; c < p.contact.size(); ++c) {
      std::array<double, 2> drive{}, force{};
      for (int i = 0; i < 2; ++i) {
        drive[i] = to.drive[c][i] - from.drive[c][i];
        force[i] = to.force[c][i] - from.force[c][i];
      }
      contact->setStageDrive(static_cast<int>(c), from.drive[c], drive, from.force[c], force);
    }
}

} // namespace mixcon
