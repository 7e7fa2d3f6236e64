#include <contact/ContactStatus.hpp>

#include <algorithm>
#include <cmath>

namespace mixcon {

const char *contactStatusName(ContactStatus s) {
  switch (s) {
  case ContactStatus::Stick:
    return "stick";
  case ContactStatus::Slip:
    return "slip";
  case ContactStatus::Open:
  default:
    return "open";
  }
}

CoulombOutcome updateCoulomb(ContactStatus &status, double &normalForce, double &tangentForce,
                             const CoulombInput &in, bool frozen) {
  CoulombOutcome out;
  const double mu = in.mu, n = in.normalForce;
  const double sign = tangentForce >= 0 ? 1.0 : -1.0;
  const bool inconsistent =
      mu > 0.0 && std::abs(mu * n - std::abs(tangentForce)) > 1e-3 * mu * std::max(n, 1e-300);
  const ContactStatus before = status;
  if (frozen) {
    // Statuses kept; a slip candidate's friction force follows mu N.
    if (status == ContactStatus::Slip && inconsistent) {
      out.changed = out.friction = true;
      out.previousFriction = tangentForce;
    }
    const bool closed = status != ContactStatus::Open;
    normalForce = closed ? n : 0.0;
    tangentForce = status == ContactStatus::Slip ? sign * mu * n : (closed ? in.tangentForce : 0.0);
    return out;
  }
  switch (status) {
  case ContactStatus::Open:
    if (in.penetrates) {
      status = mu > 0.0 ? ContactStatus::Stick : ContactStatus::Slip;
      out.anchor = true;
      normalForce = tangentForce = 0.0;
    }
    break;
  case ContactStatus::Stick:
  case ContactStatus::Slip:
    if (in.compression < 0.0) {
      status = ContactStatus::Open;
      normalForce = tangentForce = 0.0;
      break;
    }
    if (status == ContactStatus::Stick && std::abs(in.shear) > mu * in.compression * (1 + 1e-9)) {
      status = ContactStatus::Slip;
    } else if (status == ContactStatus::Slip && mu > 0.0) {
      if (in.reversed) {
        status = ContactStatus::Stick;
        out.anchor = true;
      } else if (inconsistent) {
        out.changed = out.friction = true; // friction force not yet mu N: iterate
        out.previousFriction = tangentForce;
      }
    }
    normalForce = n;
    if (status == ContactStatus::Stick || before == ContactStatus::Stick)
      tangentForce = in.tangentForce;
    else if (status == ContactStatus::Slip)
      tangentForce = sign * mu * n;
    break;
  }
  if (status != before) {
    out.changed = true;
    out.friction = false;
  }
  return out;
}

double crossingFraction(double committed, double current) {
  return committed > 0.0 && current < 0.0 ? committed / (committed - current) : -1.0;
}

std::string statusSignature(const std::vector<ContactStatus> &s) {
  std::string r(s.size(), 'o');
  for (std::size_t k = 0; k < s.size(); ++k)
    r[k] = s[k] == ContactStatus::Open ? 'o' : (s[k] == ContactStatus::Stick ? 's' : 'l');
  return r;
}

LocalIndex countClosed(const std::vector<ContactStatus> &s) {
  LocalIndex n = 0;
  for (auto x : s)
    n += x != ContactStatus::Open;
  return n;
}

} // namespace mixcon
