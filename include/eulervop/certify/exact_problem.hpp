// The exact data of a certificate: a scene's problem with G and Omega(0) the intervals of its
// decimals as written (MPFI's mpfi_set_str: "0.1" means one tenth, not its binary neighbour).
//
// A normalized scene gives Eq. 5 directly (c1, c2 with u = 0 mean Omega(0) = (c1, 0, c2) exactly,
// Eq. 12). A physical one goes through Eqs. 2-4 in intervals: model/physical_scaling.hpp with the
// interval type, for the principal axes that the plain run uses (ordered on the moments'
// doubles, which order them exactly as their decimals do).
#pragma once

#include <eulervop/certify/interval.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/model/principal_axes.hpp>
#include <eulervop/scene/scene.hpp>

#include <mpfr.h>

#include <array>
#include <stdexcept>
#include <string>
#include <variant>

namespace eulervop {

// Eq. 5 (or Eq. 1) with a constant torque, in intervals.
using exact_problem = euler_problem<interval>;

namespace detail {
inline vec3<interval> decimals_of(const std::array<std::string, 3>& texts, mpfr_prec_t bits) {
  vec3<interval> v = {interval::zero(bits), interval::zero(bits), interval::zero(bits)};
  for (int i = 0; i < 3; ++i) set_decimal(v[i], texts[i]);
  return v;
}
inline vec3<interval> decimals_of(const scene::decimal3& d, mpfr_prec_t bits) {
  return decimals_of({d[0].text, d[1].text, d[2].text}, bits);
}
}  // namespace detail

// The coefficients a as integers: each must be exactly -1, 0 or 1 (std::invalid_argument
// otherwise), as Eq. 5's (-1, 1, -1) are. The certificate's double-precision parts multiply by
// them and count no rounding for it (bounded_chebyshev.hpp).
inline std::array<int, 3> unit_coefficients(const exact_problem& p) {
  std::array<int, 3> out{};
  for (int i = 0; i < 3; ++i) {
    const interval& a = p.a[i];
    const bool point = mpfr_equal_p(&a.get()->left, &a.get()->right);
    const long value = mpfr_get_si(&a.get()->left, MPFR_RNDN);
    if (!point || !mpfr_integer_p(&a.get()->left) || value < -1 || value > 1)
      throw std::invalid_argument("certifier: the coefficients a of Euler's equations must be -1, 0 or 1");
    out[i] = static_cast<int>(value);
  }
  return out;
}

// Eq. 5 with G and Omega(0) the decimals `G`, `Omega0`, at `bits`.
inline exact_problem exact_problem_of(const std::array<std::string, 3>& G, const std::array<std::string, 3>& Omega0,
                                      mpfr_prec_t bits) {
  const interval_precision_scope scope(bits);
  exact_problem p;
  p.torque.G = detail::decimals_of(G, bits);
  p.Omega0 = detail::decimals_of(Omega0, bits);
  return p;
}

// Eqs. 2-4 for a physical scene in the normalized form (the scene must not need the direct form:
// its moments distinct, scene::uses_direct_form false).
inline physical_scaling<interval> exact_scaling_of(const scene::scene& s, mpfr_prec_t bits) {
  const interval_precision_scope scope(bits);
  const scene::decimal3& I = *s.inertia;
  const axis_permutation axes = axis_permutation::sorting(std::array<double, 3>{I[0].value, I[1].value, I[2].value});
  const vec3<interval> user = detail::decimals_of(I, bits);
  const inertia<interval> principal{user[axes.axis(0)], user[axes.axis(1)], user[axes.axis(2)]};
  return physical_scaling<interval>(axes, principal);
}

// The scene's problem (normalized form; u = 0 for [initial] c1, c2, u).
inline exact_problem exact_problem_of(const scene::scene& s, mpfr_prec_t bits) {
  const interval_precision_scope scope(bits);
  const vec3<interval> zero = {interval::zero(bits), interval::zero(bits), interval::zero(bits)};
  if (s.is_physical()) {
    const vec3<interval> M = s.torque ? detail::decimals_of(*s.torque, bits) : zero;
    const vec3<interval> omega0 = detail::decimals_of(std::get<scene::initial_rates>(s.initial).rates, bits);
    exact_problem p = exact_scaling_of(s, bits).problem(M, omega0);
    if (!s.torque) p.torque.G = zero;  // +0 (an axis reversed by the relabelling would negate it)
    return p;
  }
  std::array<std::string, 3> G = {"0", "0", "0"}, Omega0;
  if (s.torque) G = {(*s.torque)[0].text, (*s.torque)[1].text, (*s.torque)[2].text};
  if (const auto* r = std::get_if<scene::initial_rates>(&s.initial)) {
    Omega0 = {r->rates[0].text, r->rates[1].text, r->rates[2].text};
  } else {
    const auto& e = std::get<scene::initial_elements>(s.initial);
    Omega0 = {e.c1.text, "0", e.c2.text};
  }
  return exact_problem_of(G, Omega0, bits);
}

}  // namespace eulervop
