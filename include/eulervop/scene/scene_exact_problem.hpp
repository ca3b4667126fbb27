// A scene's exact problem for the certificate (certify/exact_problem.hpp): G and Omega(0) the
// intervals of its decimals as written, and of its constant formulas ("2/3" for a moment:
// certify/constant_enclosure.hpp). A normalized scene gives Eq. 5 directly (c1, c2 with u = 0
// mean Omega(0) = (c1, 0, c2) exactly, Eq. 12). A physical one goes through Eqs. 2-4 in intervals:
// model/physical_scaling.hpp with the interval type, for the principal axes that the plain run
// uses (ordered on the moments' doubles, which order them exactly as their decimals do).
#pragma once

#include <eulervop/certify/constant_enclosure.hpp>
#include <eulervop/certify/exact_problem.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/model/principal_axes.hpp>
#include <eulervop/scene/input_error.hpp>
#include <eulervop/scene/scene.hpp>

#include <mpfr.h>

#include <array>
#include <stdexcept>
#include <string>
#include <variant>

namespace eulervop::scene {

namespace detail {
// The interval that holds the exact value of a number as the scene wrote it: a decimal, or a
// constant formula. A formula undefined on its enclosure is bad input naming `field`.
inline interval enclosure_of(const decimal& d, mpfr_prec_t bits, const std::string& field) {
  interval x = interval::zero(bits);
  if (!d.formula) {
    eulervop::detail::set_decimal(x, d.text);
    return x;
  }
  try {
    return enclose_constant(*d.formula, bits);
  } catch (const std::domain_error& e) {
    throw input_error("--certify: " + field + " " + e.what());
  }
}
inline vec3<interval> decimals_of(const decimal3& d, mpfr_prec_t bits, const std::string& field = "") {
  return {enclosure_of(d[0], bits, field), enclosure_of(d[1], bits, field), enclosure_of(d[2], bits, field)};
}
}  // namespace detail

// Eqs. 2-4 for a physical scene in the normalized form (the scene must not need the direct form:
// its moments distinct, uses_direct_form false).
inline physical_scaling<interval> exact_scaling_of(const scene& s, mpfr_prec_t bits) {
  const interval_precision_scope scope(bits);
  const decimal3& I = *s.inertia;
  const axis_permutation axes = axis_permutation::sorting(std::array<double, 3>{I[0].value, I[1].value, I[2].value});
  const vec3<interval> user = detail::decimals_of(I, bits, "[body] inertia");
  const inertia<interval> principal{user[axes.axis(0)], user[axes.axis(1)], user[axes.axis(2)]};
  return physical_scaling<interval>(axes, principal);
}

// The scene's problem (normalized form; u = 0 for [initial] c1, c2, u).
inline exact_problem exact_problem_of(const scene& s, mpfr_prec_t bits) {
  const interval_precision_scope scope(bits);
  const vec3<interval> zero = {interval::zero(bits), interval::zero(bits), interval::zero(bits)};
  if (s.is_physical()) {
    const vec3<interval> M = s.torque ? detail::decimals_of(*s.torque, bits, "[torque] M") : zero;
    const vec3<interval> omega0 =
        detail::decimals_of(std::get<initial_rates>(s.initial).rates, bits, "[initial] omega");
    exact_problem p = exact_scaling_of(s, bits).problem(M, omega0);
    if (!s.torque) p.torque.G = zero;  // +0 (an axis reversed by the relabelling would negate it)
    return p;
  }
  exact_problem p;
  p.torque.G = s.torque ? detail::decimals_of(*s.torque, bits, "[torque] G") : zero;
  if (const auto* r = std::get_if<initial_rates>(&s.initial)) {
    p.Omega0 = detail::decimals_of(r->rates, bits, "[initial] Omega");
  } else {
    const auto& e = std::get<initial_elements>(s.initial);
    p.Omega0 = {detail::enclosure_of(e.c1, bits, "[initial] c1"), interval::zero(bits),
                detail::enclosure_of(e.c2, bits, "[initial] c2")};
  }
  return p;
}

}  // namespace eulervop::scene
