// A scene's numbers as balls that hold their exact values, for the general path of --certify
// (scene_certification_problem.hpp): a decimal as written or a constant formula
// (certify/constant_ball.hpp), Omega(0) of the elements c1, c2, u (Eq. 12, Jacobi's functions
// enclosed by certify/jacobi_enclosure.hpp), and Eqs. 2-4 of a physical body
// (model/physical_scaling.hpp run on certify/ball_value.hpp), for the principal axes the plain run
// uses: ordered on the moments' doubles, which order them exactly as their decimals do.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/ball_value.hpp>
#include <eulervop/certify/constant_ball.hpp>
#include <eulervop/certify/jacobi_enclosure.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/model/principal_axes.hpp>
#include <eulervop/scene/input_error.hpp>
#include <eulervop/scene/scene.hpp>

#include <arb.h>

#include <array>
#include <stdexcept>
#include <string>

namespace eulervop::scene {

// The ball of a number as the scene wrote it, at `prec` bits: a decimal, a constant formula, or a
// binary64 number exactly (decimal::binary). A formula undefined on its ball is bad input naming
// `field`.
inline ball ball_of_decimal(const decimal& d, slong prec, const std::string& field) {
  if (d.binary) {
    ball x;
    arb_set_d(x.get(), d.value);
    return x;
  }
  if (!d.formula) return decimal_ball(d.text, prec);
  try {
    return constant_ball(*d.formula, prec);
  } catch (const std::domain_error& e) {
    throw input_error("--certify: " + field + " " + e.what());
  }
}

inline vec3<ball_value> ball_values_of(const decimal3& d, slong prec, const std::string& field) {
  vec3<ball_value> out;
  for (int i = 0; i < 3; ++i) out[i] = ball_value(ball_of_decimal(d[i], prec, field), prec);
  return out;
}

// Omega(0) of the elements c1, c2, u (Eq. 12): (c1 cn u, c1 sn u, c2 dn u) with k = c1/c2;
// (c1, 0, c2) exactly at u = 0.
inline std::array<ball, 3> ball_Omega_of_elements(const initial_elements& e, slong prec) {
  const ball c1 = ball_of_decimal(e.c1, prec, "[initial] c1");
  const ball c2 = ball_of_decimal(e.c2, prec, "[initial] c2");
  const ball u = ball_of_decimal(e.u, prec, "[initial] u");
  if (arb_is_zero(u.get())) return {c1, ball(), c2};  // exactly 0: the number was zero
  ball k;
  arb_div(k.get(), c1.get(), c2.get(), prec);
  jacobi_enclosures v;
  try {
    v = jacobi_enclosure(k, u, prec);
  } catch (const std::domain_error& err) {
    throw input_error("--certify: [initial] u = " + e.u.text + ": " + err.what());
  }
  arb_mul(v.cn.get(), v.cn.get(), c1.get(), prec);
  arb_mul(v.sn.get(), v.sn.get(), c1.get(), prec);
  arb_mul(v.dn.get(), v.dn.get(), c2.get(), prec);
  return {v.cn, v.sn, v.dn};
}

// Eqs. 2-4 for a physical scene in the normalized form (the scene must not need the direct form:
// its moments distinct, uses_direct_form false).
inline physical_scaling<ball_value> ball_scaling_of(const scene& s, slong prec) {
  const decimal3& I = *s.inertia;
  const axis_permutation axes = axis_permutation::sorting(std::array<double, 3>{I[0].value, I[1].value, I[2].value});
  const vec3<ball_value> user = ball_values_of(I, prec, "[body] inertia");
  const inertia<ball_value> principal{user[axes.axis(0)], user[axes.axis(1)], user[axes.axis(2)]};
  return physical_scaling<ball_value>(axes, principal);
}

}  // namespace eulervop::scene
