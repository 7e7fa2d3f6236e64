// Contact statuses and the report's status rules shared by rigid-obstacle and node-to-segment
// contact (host side): a penetrating open candidate closes (stick with friction, slip without);
// a closed one opens when its compression turns tensile; a stick one slips when |shear| exceeds
// mu times the compression; a slip one sticks again when its slip reverses, and otherwise its
// friction force follows mu N (an update that counts as a change until it is consistent). With
// a frozen pattern (a cycling active set) only the friction forces are updated.
// Data flow: contact.
#pragma once

#include <core/Compat.hpp>

#include <string>
#include <vector>

namespace mixcon {

enum class ContactStatus : int { Open = 0, Stick = 1, Slip = 2 };

/// "open" | "stick" | "slip".
const char *contactStatusName(ContactStatus s);

/// One candidate's measures for a status update.
struct CoulombInput {
  double normalForce = 0.0;  ///< N (compressive positive), from the contact forces
  double tangentForce = 0.0; ///< T
  double compression = 0.0;  ///< what decides release (N, or -sigma_nn of the nodal stress)
  double shear = 0.0;        ///< what decides slip (T, or tau_nt)
  double mu = 0.0;
  bool penetrates = false; ///< an open candidate lies inside the other surface
  bool reversed = false;   ///< a slip candidate moved along its friction force since the commit
};

/// What an update did: `changed` counts toward the status iterations (a status change or a
/// friction force not yet consistent with mu N); `anchor`: the candidate closed or stuck again
/// (anchor it where it is); `friction`: only the friction force changed (from `previousFriction`).
struct CoulombOutcome {
  bool changed = false;
  bool anchor = false;
  bool friction = false;
  double previousFriction = 0.0;
};

/// Applies the rules to one candidate's status and stored forces.
CoulombOutcome updateCoulomb(ContactStatus &status, double &normalForce, double &tangentForce,
                             const CoulombInput &in, bool frozen);

/// Where in an increment a candidate crossed the other surface, its gap going linearly from
/// `committed` (at the last converged state) to `current`: the fraction g0 / (g0 - g) of the
/// increment, in (0, 1), when g0 > 0 > g; otherwise -1 (no crossing to interpolate: it started
/// inside, or a gap is unknown, NaN). A node that closes is anchored there, not where the
/// increment ends (docs/contact.md, "Statuses").
double crossingFraction(double committed, double current);

/// A string of the statuses (cycle detection) and the number of closed ones.
std::string statusSignature(const std::vector<ContactStatus> &s);
LocalIndex countClosed(const std::vector<ContactStatus> &s);

} // namespace mixcon
