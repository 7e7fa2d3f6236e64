// Rigid obstacles of the report's "Rigid Pin Contact Algorithm": a circle (pin) of radius R and a
// rigid half-plane, as POD structs usable on the device, the closest-point projection of a point
// onto their surface (signed gap, outward normal, tangent, angle on the pin), and the batched
// detection kernel over (boundary node, obstacle) pairs at the current configuration.
// Conventions: the body lies outside the obstacle; the normal n points from the obstacle into the
// body; the tangent is t = (-n_y, n_x) (counter-clockwise about a pin); the gap is positive when
// the point is clear of the obstacle and negative when it penetrates. Data flow: solver -> contact.
#pragma once

#include <core/Compat.hpp>
#include <mesh/Mesh.hpp>

#include <Kokkos_Core.hpp>

namespace mixcon {

enum class ObstacleKind : int { Circle = 0, HalfPlane = 1 };

/// A rigid obstacle. Circle: `point` is the centre, `radius` R. Half-plane: `point` lies on its
/// boundary line and `normal` is the unit normal pointing out of the obstacle (into the body).
struct RigidObstacle {
  ObstacleKind kind = ObstacleKind::Circle;
  double point[2] = {0.0, 0.0};
  double radius = 0.0;
  double normal[2] = {0.0, 1.0};
};

/// The projection of one point onto an obstacle surface.
struct ObstacleProjection {
  double gap = 0.0;               ///< signed distance (negative: penetration)
  double normal[2] = {0.0, 0.0};  ///< unit, from the obstacle into the body
  double tangent[2] = {0.0, 0.0}; ///< unit, (-n_y, n_x)
  double closest[2] = {0.0, 0.0}; ///< the closest point on the obstacle surface
  double angle = 0.0;             ///< circle: atan2 of the normal (radians); half-plane: 0
  double arcCoordinate = 0.0;     ///< circle: R * angle; half-plane: (x - point) . tangent
};

/// Components of a symmetric stress s = (xx, yy, xy) on a surface with unit normal n:
/// sigma_nn = n . s . n and tau_nt = t . s . n with t = (-n_y, n_x).
KOKKOS_INLINE_FUNCTION void surfaceStress(const double *s, double n0, double n1, double &nn,
                                          double &nt) {
  const double tn0 = s[0] * n0 + s[2] * n1, tn1 = s[2] * n0 + s[1] * n1; // s . n
  nn = n0 * tn0 + n1 * tn1;
  nt = -n1 * tn0 + n0 * tn1;
}

/// Closest-point projection of (x, y) onto the obstacle surface. A point exactly at a pin's
/// centre has no normal; it gets n = (1, 0) and gap -R (deepest penetration).
KOKKOS_INLINE_FUNCTION ObstacleProjection projectOntoObstacle(const RigidObstacle &o, double x,
                                                              double y) {
  ObstacleProjection p;
  if (o.kind == ObstacleKind::Circle) {
    const double dx = x - o.point[0], dy = y - o.point[1];
    const double r = detail::sqrt(dx * dx + dy * dy);
    p.normal[0] = r > 0.0 ? dx / r : 1.0;
    p.normal[1] = r > 0.0 ? dy / r : 0.0;
    p.gap = r - o.radius;
    p.closest[0] = o.point[0] + o.radius * p.normal[0];
    p.closest[1] = o.point[1] + o.radius * p.normal[1];
    p.angle = detail::atan2(p.normal[1], p.normal[0]);
    p.arcCoordinate = o.radius * p.angle;
  } else {
    p.normal[0] = o.normal[0];
    p.normal[1] = o.normal[1];
    p.gap = (x - o.point[0]) * p.normal[0] + (y - o.point[1]) * p.normal[1];
    p.closest[0] = x - p.gap * p.normal[0];
    p.closest[1] = y - p.gap * p.normal[1];
  }
  p.tangent[0] = -p.normal[1];
  p.tangent[1] = p.normal[0];
  if (o.kind == ObstacleKind::HalfPlane)
    p.arcCoordinate = (x - o.point[0]) * p.tangent[0] + (y - o.point[1]) * p.tangent[1];
  return p;
}

/// Device results of a detection pass, one entry per (node, obstacle) candidate.
template <class MemorySpace> struct ContactDetection {
  Kokkos::View<double *, MemorySpace> gap;
  Kokkos::View<double *[2], MemorySpace> normal, tangent, closest;
  Kokkos::View<double *, MemorySpace> angle, arcCoordinate;
  explicit ContactDetection(LocalIndex n = 0)
      : gap("mixcon::contact::gap", n), normal("mixcon::contact::normal", n),
        tangent("mixcon::contact::tangent", n), closest("mixcon::contact::closest", n),
        angle("mixcon::contact::angle", n), arcCoordinate("mixcon::contact::arc", n) {}
};

/// Projects the current position x = X + u of every candidate node onto its obstacle:
/// candidate k is node `nodes(k)` against obstacle `obstacleOf(k)`; u holds `stride` unknowns per
/// node with the displacement first (2: displacement model, 5: mixed model). Returns the number
/// of candidates with gap < 0 (penetrating).
template <class ExecSpace, class MemorySpace>
LocalIndex detectContact(const ExecSpace &exec,
                         const Kokkos::View<const RigidObstacle *, MemorySpace> &obstacles,
                         const Kokkos::View<const LocalIndex *, MemorySpace> &nodes,
                         const Kokkos::View<const int *, MemorySpace> &obstacleOf,
                         const Kokkos::View<const double *[2], MemorySpace> &coordinates,
                         const Kokkos::View<const double *, MemorySpace> &u, int stride,
                         const ContactDetection<MemorySpace> &out) {
  LocalIndex penetrating = 0;
  Kokkos::parallel_reduce(
      "mixcon::contact::detect", Kokkos::RangePolicy<ExecSpace>(exec, 0, nodes.extent(0)),
      KOKKOS_LAMBDA(LocalIndex k, LocalIndex & count) {
        const LocalIndex n = nodes(k);
        const double x = coordinates(n, 0) + u(stride * n);
        const double y = coordinates(n, 1) + u(stride * n + 1);
        const ObstacleProjection p = projectOntoObstacle(obstacles(obstacleOf(k)), x, y);
        out.gap(k) = p.gap;
        out.angle(k) = p.angle;
        out.arcCoordinate(k) = p.arcCoordinate;
        for (int i = 0; i < 2; ++i) {
          out.normal(k, i) = p.normal[i];
          out.tangent(k, i) = p.tangent[i];
          out.closest(k, i) = p.closest[i];
        }
        if (p.gap < 0.0)
          ++count;
      },
      penetrating);
  return penetrating;
}

} // namespace mixcon
