// A scene's exact problem for the certificate (certify/exact_problem.hpp): G and Omega(0) the
// intervals of its decimals as written. A normalized scene gives Eq. 5 directly (c1, c2 with u = 0
// mean Omega(0) = (c1, 0, c2) exactly, Eq. 12). A physical one goes through Eqs. 2-4 in intervals:
// model/physical_scaling.hpp with the interval type, for the principal axes that the plain run
// uses (ordered on the moments' doubles, which order them exactly as their decimals do).
#pragma once

#include <eulervop/certify/exact_problem.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/model/principal_axes.hpp>
#include <eulervop/scene/scene.hpp>

#include <mpfr.h>

#include <array>
#include <string>
#include <variant>

namespace eulervop::scene {

namespace detail {
inline vec3<interval> decimals_of(const decimal3& d, mpfr_prec_t bits) {
  return eulervop::detail::decimals_of({d[0].text, d[1].text, d[2].text}, bits);
}
}  // namespace detail

// Eqs. 2-4 for a physical scene in the normalized form (the scene must not need the direct form:
// its moments distinct, uses_direct_form false).
inline physical_scaling<interval> exact_scaling_of(const scene& s, mpfr_prec_t bits) {
  const interval_precision_scope scope(bits);
  const decimal3& I = *s.inertia;
  const axis_permutation axes = axis_permutation::sorting(std::array<double, 3>{I[0].value, I[1].value, I[2].value});
  const vec3<interval> user = detail::decimals_of(I, bits);
  const inertia<interval> principal{user[axes.axis(0)], user[axes.axis(1)], user[axes.axis(2)]};
  return physical_scaling<interval>(axes, principal);
}

// The scene's problem (normalized form; u = 0 for [initial] c1, c2, u).
inline exact_problem exact_problem_of(const scene& s, mpfr_prec_t bits) {
  const interval_precision_scope scope(bits);
  const vec3<interval> zero = {interval::zero(bits), interval::zero(bits), interval::zero(bits)};
  if (s.is_physical()) {
    const vec3<interval> M = s.torque ? detail::decimals_of(*s.torque, bits) : zero;
    const vec3<interval> omega0 = detail::decimals_of(std::get<initial_rates>(s.initial).rates, bits);
    exact_problem p = exact_scaling_of(s, bits).problem(M, omega0);
    if (!s.torque) p.torque.G = zero;  // +0 (an axis reversed by the relabelling would negate it)
    return p;
  }
  std::array<std::string, 3> G = {"0", "0", "0"}, Omega0;
  if (s.torque) G = {(*s.torque)[0].text, (*s.torque)[1].text, (*s.torque)[2].text};
  if (const auto* r = std::get_if<initial_rates>(&s.initial)) {
    Omega0 = {r->rates[0].text, r->rates[1].text, r->rates[2].text};
  } else {
    const auto& e = std::get<initial_elements>(s.initial);
    Omega0 = {e.c1.text, "0", e.c2.text};
  }
  return eulervop::exact_problem_of(G, Omega0, bits);
}

}  // namespace eulervop::scene
