// Measured boundary displacements for the hybrid experimental/numerical mode (the report's
// "Hybrid Experimental/Numerical Technique"): reading the measurement file, checking that the
// points lie on the named boundary, interpolating them onto its nodes, and symmetrizing the two
// mirrored halves. Host code (input stage of the data flow: io -> solver).
#pragma once

#include <mesh/Mesh.hpp>

#include <array>
#include <string>
#include <vector>

namespace mixcon {

struct MeasuredPoint {
  double x, y, ux, uy;
  int line; ///< line in the measurement file (for messages)
};

struct MeasuredStep {
  int step;    ///< 1, 2, ... in file order
  double load; ///< the load of the step (reported, not applied)
  std::vector<MeasuredPoint> points;
};

/// Reads a CSV `step,load,x,y,ux,uy` (header line first; one row per measured point; steps
/// numbered 1, 2, ... without gaps, each with one load value). Throws InputError naming
/// `file:line` on malformed rows, missing or out-of-order steps, or an empty file.
std::vector<MeasuredStep> readMeasurements(const std::string &file);
/// Same from text (`name` for messages).
std::vector<MeasuredStep> parseMeasurements(const std::string &text, const std::string &name);

/// Throws InputError naming `file:line` for the first point farther than `maxDistance` from the
/// boundary `boundary` of `mesh` (distance to the polygon through its edge nodes). With
/// `mirrorY`, a point may instead lie near the boundary's mirror image about y = mirrorAxis (the
/// other half of a symmetric specimen, modelled by the half mesh).
void checkNearBoundary(const Mesh &mesh, const std::string &boundary,
                       const std::vector<MeasuredStep> &steps, double maxDistance,
                       const std::string &file, bool mirrorY = false, double mirrorAxis = 0.0);

/// Measured displacements of one step as functions of the polar angle about a centre:
/// piecewise linear between the measured points sorted by angle (angles in (-pi, pi]). The
/// profile is periodic when the points go all the way around (the wrap-around gap is at most
/// twice the largest gap between neighbouring points); otherwise it covers the measured range
/// only.
class AngularProfile {
public:
  AngularProfile(const MeasuredStep &step, std::array<double, 2> center);
  /// Whether theta lies within the measured range (always, when the points go all around).
  bool covers(double theta) const;
  /// Interpolated (ux, uy) at theta (covers(theta) must hold).
  std::array<double, 2> at(double theta) const;
  bool periodic() const { return periodic_; }

private:
  std::vector<double> angle_, ux_, uy_;
  bool periodic_ = false;
};

/// Values prescribed at the boundary nodes for one step.
struct BoundaryValues {
  std::vector<LocalIndex> nodes;
  std::vector<double> theta, ux, uy;
  /// max over the nodes of |u(theta) - M u(-theta)| / max |u| (M mirrors about the line through
  /// the centre along x: ux even, uy odd); -1 when the other half was not measured.
  double asymmetry = -1.0;
};

/// The measured profile at every node of `nodes` (angle about `center`). With `symmetrize` the
/// report's averaging of the two mirrored halves: u(theta) = (u(theta) + M u(-theta)) / 2, where
/// both halves are measured. Throws InputError naming the node and the step when a node lies
/// outside the measured range.
BoundaryValues boundaryValues(const Mesh &mesh, const std::vector<LocalIndex> &nodes,
                              const AngularProfile &profile, std::array<double, 2> center,
                              bool symmetrize, int step);

} // namespace mixcon
