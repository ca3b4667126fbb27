// When a comparison run has diverged ("exploded"), and how.
#pragma once

#include <eulervop/core/outcome.hpp>
#include <eulervop/core/vec3.hpp>

#include <cmath>

namespace eulervop::detail {

// Beyond this max-norm a run has "exploded": a thousand times the largest |Omega| a bounded
// torque G can produce over the span from Omega0, |Omega0| + |G| tau_end (and the VOP phase u up
// to that times tau_end).
inline double explosion_bound(const vec3<double>& Omega0, const vec3<double>& G, double tau_end, bool phase) {
  double s = 1;
  for (int i = 0; i < 3; ++i) s += std::abs(Omega0[i]) + std::abs(G[i]) * tau_end;
  return 1e3 * s * (phase ? 1 + tau_end : 1.0);
}

inline bool finite_within(const vec3<double>& v, double bound) {
  for (double c : v)
    if (!std::isfinite(c) || std::abs(c) > bound) return false;
  return true;
}

// How a state that is not finite_within the bound failed.
inline outcome_kind divergence_kind(const vec3<double>& v) {
  return std::isfinite(v[0] + v[1] + v[2]) ? outcome_kind::norm_bound : outcome_kind::non_finite;
}

}  // namespace eulervop::detail
