// RigidContact: candidates, detection, statuses and the constraints of one Newton correction.
#include <contact/RigidContact.hpp>
#include <core/Transfer.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

namespace mixcon {

RigidContact::RigidContact(LocalIndex numNodes, std::vector<RigidContactSpec> specs,
                           std::vector<long> nodeIds)
    : specs_(std::move(specs)), nodeIds_(std::move(nodeIds)), numNodes_(numNodes) {
  for (std::size_t s = 0; s < specs_.size(); ++s) {
    std::set<LocalIndex> unique(specs_[s].nodes.begin(), specs_[s].nodes.end());
    for (LocalIndex n : unique) {
      node_.push_back(n);
      obstacle_.push_back(static_cast<int>(s));
    }
  }
  const std::size_t m = node_.size();
  status_.assign(m, ContactStatus::Open);
  gap_.assign(m, 0.0);
  angle_.assign(m, 0.0);
  arc_.assign(m, 0.0);
  normal_.assign(2 * m, 0.0);
  normalForce_.assign(m, 0.0);
  tangentForce_.assign(m, 0.0);
  anchorArc_.assign(m, 0.0);
  committedArc_.assign(m, 0.0);
  motion_.assign(2 * specs_.size(), 0.0);
  baseMotion_.assign(2 * specs_.size(), 0.0);
  baseForce_.assign(2 * specs_.size(), 0.0);
  for (std::size_t s = 0; s < specs_.size(); ++s)
    for (int i = 0; i < 2; ++i)
      if (specs_[s].forceDriven[i])
        driven_.push_back({static_cast<int>(s), i});
  obstacles_ =
      Kokkos::View<RigidObstacle *, DeviceSpace>("mixcon::contact::obstacles", specs_.size());
  uploadObstacles();
  nodesDevice_ = Kokkos::View<LocalIndex *, DeviceSpace>("mixcon::contact::nodes", m);
  obstacleDevice_ = Kokkos::View<int *, DeviceSpace>("mixcon::contact::obstacleOf", m);
  auto hn = hostMirror(nodesDevice_);
  auto hw = hostMirror(obstacleDevice_);
  for (std::size_t k = 0; k < m; ++k) {
    hn(k) = node_[k];
    hw(k) = obstacle_[k];
  }
  copyToDevice(nodesDevice_, hn);
  copyToDevice(obstacleDevice_, hw);
  detection_ = ContactDetection<DeviceSpace>(static_cast<LocalIndex>(m));
  buildConstraints();
}

std::string RigidContact::obstacleLabel(int s) const {
  return "obstacle " + std::to_string(s + 1) + " ('" + specs_[static_cast<std::size_t>(s)].name +
         "')";
}

void RigidContact::uploadObstacles() {
  auto ho = hostMirror(obstacles_);
  for (std::size_t s = 0; s < specs_.size(); ++s) {
    ho(s) = specs_[s].obstacle;
    for (int i = 0; i < 2; ++i)
      ho(s).point[i] += motion_[2 * s + i];
  }
  copyToDevice(obstacles_, ho);
}

void RigidContact::setLoadFactor(double lambda) {
  lambda_ = lambda;
  for (std::size_t s = 0; s < specs_.size(); ++s)
    for (int i = 0; i < 2; ++i)
      if (!specs_[s].forceDriven[i])
        motion_[2 * s + i] = baseMotion_[2 * s + i] + lambda * specs_[s].drive[i];
  uploadObstacles();
}

void RigidContact::setStageDrive(int s, const std::array<double, 2> &baseMotion,
                                 const std::array<double, 2> &drive,
                                 const std::array<double, 2> &baseForce,
                                 const std::array<double, 2> &force) {
  RigidContactSpec &spec = specs_.at(static_cast<std::size_t>(s));
  for (int i = 0; i < 2; ++i) {
    baseMotion_[2 * s + i] = baseMotion[i];
    baseForce_[2 * s + i] = baseForce[i];
    spec.drive[i] = drive[i];
    spec.force[i] = force[i];
  }
}

double RigidContact::drivenForce(const DrivenComponent &c) const {
  return baseForce_[2 * c.obstacle + c.direction] + lambda_ * specs_[c.obstacle].force[c.direction];
}

void RigidContact::moveObstacle(int s, const double *delta) {
  for (int i = 0; i < 2; ++i)
    motion_[2 * static_cast<std::size_t>(s) + i] += delta[i];
  uploadObstacles();
}

int RigidContact::seatForceDriven() {
  int moved = 0;
  for (std::size_t s = 0; s < specs_.size(); ++s) {
    const RigidContactSpec &spec = specs_[s];
    if (!spec.forceDriven[0] && !spec.forceDriven[1])
      continue;
    bool supported = false;
    for (std::size_t k = 0; k < node_.size(); ++k)
      supported = supported || (obstacle_[k] == static_cast<int>(s) &&
                                (status_[k] != ContactStatus::Open || gap_[k] <= 0.0));
    double d[2] = {spec.forceDriven[0] ? baseForce_[2 * s] + spec.force[0] : 0.0,
                   spec.forceDriven[1] ? baseForce_[2 * s + 1] + spec.force[1] : 0.0};
    const double len = std::hypot(d[0], d[1]);
    if (supported || !(len > 0.0))
      continue;
    d[0] /= len;
    d[1] /= len;
    // The first candidate the obstacle meets when it translates along d: for a circle the
    // smaller root t of |p - (c + t d)| = R (p = c + (R + gap) n from the last detection), for
    // a half-plane gap / (d . n_plane).
    const RigidObstacle &o = spec.obstacle;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < node_.size(); ++k) {
      if (obstacle_[k] != static_cast<int>(s))
        continue;
      const double n0 = normal_[2 * k], n1 = normal_[2 * k + 1];
      if (o.kind == ObstacleKind::Circle) {
        const double w0 = (o.radius + gap_[k]) * n0, w1 = (o.radius + gap_[k]) * n1; // p - c
        const double b = w0 * d[0] + w1 * d[1];
        const double disc = b * b - (w0 * w0 + w1 * w1) + o.radius * o.radius;
        if (disc >= 0.0 && b - std::sqrt(disc) >= 0.0)
          best = std::min(best, b - std::sqrt(disc));
      } else {
        const double toward = d[0] * o.normal[0] + d[1] * o.normal[1];
        if (toward > 0.0)
          best = std::min(best, gap_[k] / toward);
      }
    }
    if (!std::isfinite(best))
      throw InputError(obstacleLabel(static_cast<int>(s)) +
                       " is driven by a force but no node of its boundary lies in its path: "
                       "the force cannot be carried by the body");
    const double delta[2] = {best * d[0], best * d[1]};
    moveObstacle(static_cast<int>(s), delta);
    ++moved;
  }
  return moved;
}

LocalIndex RigidContact::detect(const Kokkos::View<const double *[2], DeviceSpace> &coordinates,
                                const Kokkos::View<const double *, DeviceSpace> &u, int stride) {
  const LocalIndex penetrating = detectContact(
      Kokkos::DefaultExecutionSpace(), Kokkos::View<const RigidObstacle *, DeviceSpace>(obstacles_),
      Kokkos::View<const LocalIndex *, DeviceSpace>(nodesDevice_),
      Kokkos::View<const int *, DeviceSpace>(obstacleDevice_), coordinates, u, stride, detection_);
  // What the statuses and constraints read (gap, normal, angle, arc per candidate), packed on
  // the device and copied in one transfer of O(candidates).
  if (detected_.extent(0) != node_.size())
    detected_ = Kokkos::View<double *[5], DeviceSpace>("mixcon::contact::detected", node_.size());
  const auto packed = detected_;
  const auto d = detection_;
  Kokkos::parallel_for(
      "mixcon::contact::packDetection",
      Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, node_.size()),
      KOKKOS_LAMBDA(LocalIndex k) {
        packed(k, 0) = d.gap(k);
        packed(k, 1) = d.normal(k, 0);
        packed(k, 2) = d.normal(k, 1);
        packed(k, 3) = d.angle(k);
        packed(k, 4) = d.arcCoordinate(k);
      });
  const auto h = copyToHost(packed);
  for (std::size_t k = 0; k < node_.size(); ++k) {
    gap_[k] = h(k, 0);
    normal_[2 * k] = h(k, 1);
    normal_[2 * k + 1] = h(k, 2);
    angle_[k] = h(k, 3);
    arc_[k] = h(k, 4);
  }
  if (saved_.status.empty() && saved_.committedGap.empty()) {
    // The state of the first detection (the initial one, at rest) is where a node that closes
    // in the first increment starts from; kept through a rollback before anything is
    // committed. (Where it already holds the first increment's motion, a node that closes
    // there is anchored where it is, as before.)
    saved_.committedArc = arc_;
    saved_.committedGap = gap_;
  }
  buildConstraints();
  return penetrating;
}

void RigidContact::buildConstraints() {
  auto &c = constraints_;
  c.framed.assign(numNodes_, 0);
  c.normal.assign(2 * static_cast<std::size_t>(numNodes_), 0.0);
  c.normalFixed.assign(numNodes_, 0);
  c.tangentFixed.assign(numNodes_, 0);
  c.normalStep.assign(numNodes_, 0.0);
  c.tangentStep.assign(numNodes_, 0.0);
  c.force.assign(2 * static_cast<std::size_t>(numNodes_), 0.0);
  c.obstacle.assign(numNodes_, -1);
  deviceStale_ = true;
  for (std::size_t k = 0; k < node_.size(); ++k) {
    if (status_[k] == ContactStatus::Open)
      continue;
    const LocalIndex p = node_[k];
    const double n0 = normal_[2 * k], n1 = normal_[2 * k + 1];
    c.framed[p] = 1;
    c.obstacle[p] = obstacle_[k];
    c.normal[2 * p] = n0;
    c.normal[2 * p + 1] = n1;
    c.normalFixed[p] = 1;
    c.normalStep[p] = -gap_[k];
    if (status_[k] == ContactStatus::Stick) {
      c.tangentFixed[p] = 1;
      c.tangentStep[p] = anchorArc_[k] - arc_[k];
    } else {
      // Slip: the friction force mu N opposes the tangential motion since the last commit; its
      // sign is kept from the stick reaction that started the slip (tangentForce_).
      const double mu = specs_[obstacle_[k]].friction;
      const double f = mu * std::max(normalForce_[k], 0.0) *
                       (tangentForce_[k] > 0 ? 1.0 : (tangentForce_[k] < 0 ? -1.0 : 0.0));
      c.force[2 * p] += -n1 * f; // along t = (-n_y, n_x)
      c.force[2 * p + 1] += n0 * f;
    }
  }
}

int RigidContact::updateStatus(const std::vector<double> &g, int stride, std::string &log,
                               const std::vector<double> *stress, bool frozen) {
  std::ostringstream out;
  int changes = 0;
  for (std::size_t k = 0; k < node_.size(); ++k) {
    const LocalIndex p = node_[k];
    const double n0 = normal_[2 * k], n1 = normal_[2 * k + 1];
    // Contact force on the body: the residual without the friction force already applied.
    const double gx = g[stride * p] + constraints_.force[2 * p];
    const double gy = g[stride * p + 1] + constraints_.force[2 * p + 1];
    const double nForce = gx * n0 + gy * n1, tForce = -gx * n1 + gy * n0;
    const double mu = specs_[obstacle_[k]].friction;
    // Release and slip measures: contact forces, or the nodal stresses rotated to the surface.
    double compression = nForce, shear = tForce;
    if (stress && specs_[obstacle_[k]].statusFromStress) {
      double nn = 0.0;
      surfaceStress(&(*stress)[3 * p], n0, n1, nn, shear);
      compression = -nn;
    }
    const ContactStatus before = status_[k];
    CoulombInput in{
        nForce,
        tForce,
        compression,
        shear,
        mu,
        gap_[k]<0.0,
                // Stick again when the node moves along its friction force (slip reversed).
                arcChange(k, committedArc_[k]) * tangentForce_[k]> 0.0};
    const CoulombOutcome r =
        updateCoulomb(status_[k], normalForce_[k], tangentForce_[k], in, frozen);
    if (r.anchor) {
      // A node that closes sticks where it crossed the obstacle during the increment, a
      // fraction g0 / (g0 - g) of the way from its arc at the last converged state (gap
      // g0 > 0) to the current one (gap g < 0; anchored where the increment ends instead, it
      // would carry the rest of the increment's tangential motion as a spurious stick
      // displacement). A slipping node that reverses sticks where it was at the last converged
      // state: in the reversed direction it would not have moved (stick is the trial state
      // from there).
      const double a =
          saved_.committedGap.empty() ? -1.0 : crossingFraction(saved_.committedGap[k], gap_[k]);
      if (before == ContactStatus::Slip)
        anchorArc_[k] = committedArc_[k];
      else if (a >= 0.0)
        anchorArc_[k] = arc_[k] - (1.0 - a) * arcChange(k, saved_.committedArc[k]);
      else
        anchorArc_[k] = arc_[k];
      if (before == ContactStatus::Open)
        committedArc_[k] = arc_[k]; // slip is measured from where the node closed
    }
    if (!r.changed)
      continue;
    ++changes;
    // "contact: node <mesh id> on obstacle <1-based> ('<boundary>'): ..."
    out << "    contact: node " << Mesh::externalId(nodeIds_, p) << " on "
        << obstacleLabel(obstacle_[k]) << ": ";
    if (r.friction)
      out << "friction " << r.previousFriction << " -> " << tangentForce_[k] << "\n";
    else
      out << contactStatusName(before) << " -> " << contactStatusName(status_[k]) << " (gap "
          << gap_[k] << ", N " << nForce << ", T " << tForce << ")\n";
  }
  buildConstraints();
  log = out.str();
  return changes;
}

bool RigidContact::penetrationWithin(double relative, std::string &where) const {
  std::vector<double> extent(specs_.size(), 0.0);
  for (std::size_t k = 0; k < node_.size(); ++k)
    extent[obstacle_[k]] = std::max(extent[obstacle_[k]], std::abs(arc_[k]));
  double worst = 0.0;
  std::size_t at = 0;
  for (std::size_t k = 0; k < node_.size(); ++k) {
    if (status_[k] == ContactStatus::Open)
      continue;
    const RigidObstacle &o = specs_[obstacle_[k]].obstacle;
    const double size = o.kind == ObstacleKind::Circle ? o.radius : extent[obstacle_[k]];
    const double ratio = -gap_[k] / std::max(size, 1e-300);
    if (ratio > worst) {
      worst = ratio;
      at = k;
    }
  }
  if (worst <= relative)
    return true;
  std::ostringstream m;
  m << "node " << Mesh::externalId(nodeIds_, node_[at]) << " on " << obstacleLabel(obstacle_[at])
    << " penetrates it by " << -gap_[at] << " (" << worst << " of the obstacle size)";
  where = m.str();
  return false;
}

int RigidContact::closeTouching(double tolerance) {
  int closed = 0;
  for (std::size_t k = 0; k < node_.size(); ++k)
    if (status_[k] == ContactStatus::Open && gap_[k] <= tolerance) {
      status_[k] = specs_[obstacle_[k]].friction > 0.0 ? ContactStatus::Stick : ContactStatus::Slip;
      anchorArc_[k] = arc_[k];
      committedArc_[k] = arc_[k];
      ++closed;
    }
  buildConstraints();
  return closed;
}

double RigidContact::arcChange(std::size_t k, double from) const {
  const RigidObstacle &o = specs_[static_cast<std::size_t>(obstacle_[k])].obstacle;
  const double d = arc_[k] - from;
  // On a circle the arc is R atan2, which jumps by 2 pi R at the angle pi.
  return o.kind == ObstacleKind::Circle ? std::remainder(d, 2.0 * M_PI * o.radius) : d;
}

void RigidContact::commit() {
  committedArc_ = arc_;
  saved_ = {status_, anchorArc_, normalForce_, tangentForce_, motion_, committedArc_, gap_};
}

void RigidContact::rollback() {
  if (saved_.status.empty()) {
    std::fill(status_.begin(), status_.end(), ContactStatus::Open);
    std::fill(normalForce_.begin(), normalForce_.end(), 0.0);
    std::fill(tangentForce_.begin(), tangentForce_.end(), 0.0);
    std::fill(motion_.begin(), motion_.end(), 0.0);
  } else {
    status_ = saved_.status;
    anchorArc_ = saved_.anchorArc;
    normalForce_ = saved_.normalForce;
    tangentForce_ = saved_.tangentForce;
    motion_ = saved_.motion;
    committedArc_ = saved_.committedArc;
  }
  uploadObstacles();
  buildConstraints();
}

std::string RigidContact::signature() const { return statusSignature(status_); }

void RigidContact::saveCommitted(Checkpoint &state) const {
  const std::size_t m = node_.size();
  const bool none = saved_.status.empty(); // nothing committed yet: the initial state
  const std::vector<double> zero(m, 0.0);
  const std::vector<ContactStatus> open(m, ContactStatus::Open);
  state.putIntegers("contact/status", none ? open : saved_.status);
  state.put("contact/anchor_arc", none ? zero : saved_.anchorArc);
  state.put("contact/committed_arc", none ? zero : saved_.committedArc);
  state.put("contact/normal_force", none ? zero : saved_.normalForce);
  state.put("contact/tangential_force", none ? zero : saved_.tangentForce);
  state.put("contact/obstacle_motion",
            none ? std::vector<double>(motion_.size(), 0.0) : saved_.motion);
  state.put("contact/committed_gap", none ? zero : saved_.committedGap);
}

void RigidContact::restoreCommitted(const Checkpoint &state) {
  const std::size_t m = node_.size();
  Saved s;
  s.status = state.getIntegers<ContactStatus>("contact/status", m);
  s.anchorArc = state.get("contact/anchor_arc", m);
  s.committedArc = state.get("contact/committed_arc", m);
  s.normalForce = state.get("contact/normal_force", m);
  s.tangentForce = state.get("contact/tangential_force", m);
  s.motion = state.get("contact/obstacle_motion", motion_.size());
  // Written since the crossing-point anchor; without it a node that closes in the next
  // increment is anchored where the increment ends.
  s.committedGap =
      state.getOr("contact/committed_gap", m, std::numeric_limits<double>::quiet_NaN());
  saved_ = std::move(s);
  rollback();
}

LocalIndex RigidContact::numClosed() const { return countClosed(status_); }

} // namespace mixcon
