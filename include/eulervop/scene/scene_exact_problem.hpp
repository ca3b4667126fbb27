// A scene's exact problem for the certificate (certify/exact_problem.hpp): G and Omega(0) the
// intervals of its decimals as written, and of its constant formulas ("2/3" for a moment:
// certify/constant_enclosure.hpp). A normalized scene gives Eq. 5 directly (c1, c2 and u give
// Omega(0) by Eq. 12, with Jacobi's functions enclosed). A physical one goes through Eqs. 2-4 in intervals:
// model/physical_scaling.hpp with the interval type, for the principal axes that the plain run
// uses (ordered on the moments' doubles, which order them exactly as their decimals do).
#pragma once

#include <eulervop/certify/constant_enclosure.hpp>
#include <eulervop/certify/exact_problem.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/certify/jacobi_enclosure.hpp>
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

// Omega(0) of the elements c1, c2, u (Eq. 12): (c1 cn u, c1 sn u, c2 dn u) with k = c1/c2, Jacobi's
// functions enclosed by Arb's theta functions (certify/jacobi_enclosure.hpp); (c1, 0, c2) exactly
// at u = 0.
inline vec3<interval> exact_Omega_of_elements(const initial_elements& e, mpfr_prec_t bits) {
  const interval c1 = detail::enclosure_of(e.c1, bits, "[initial] c1");
  const interval c2 = detail::enclosure_of(e.c2, bits, "[initial] c2");
  const interval u = detail::enclosure_of(e.u, bits, "[initial] u");
  if (mpfi_is_zero(u.get())) return {c1, interval::zero(bits), c2};  // exactly 0: the decimal was zero
  const slong prec = static_cast<slong>(bits);
  const ball b1 = ball_of(c1, prec), b2 = ball_of(c2, prec);
  ball k;
  arb_div(k.get(), b1.get(), b2.get(), prec);
  jacobi_enclosures v;
  try {
    v = jacobi_enclosure(k, ball_of(u, prec), prec);
  } catch (const std::domain_error& err) {
    throw input_error("--certify: [initial] u = " + e.u.text + ": " + err.what());
  }
  arb_mul(v.cn.get(), v.cn.get(), b1.get(), prec);
  arb_mul(v.sn.get(), v.sn.get(), b1.get(), prec);
  arb_mul(v.dn.get(), v.dn.get(), b2.get(), prec);
  const auto to_interval = [&](const ball& x) {
    interval out = interval::zero(bits);
    mpfr_t lo, hi;
    mpfr_init2(lo, bits);
    mpfr_init2(hi, bits);
    arb_get_interval_mpfr(lo, hi, x.get());  // rounded outward
    mpfi_interv_fr(out.get(), lo, hi);
    mpfr_clear(lo);
    mpfr_clear(hi);
    return out;
  };
  return {to_interval(v.cn), to_interval(v.sn), to_interval(v.dn)};
}

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

// The scene's problem (normalized form).
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
    p.Omega0 = exact_Omega_of_elements(std::get<initial_elements>(s.initial), bits);
  }
  return p;
}

}  // namespace eulervop::scene
