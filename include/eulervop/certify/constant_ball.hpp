// The ball of a constant formula (model/expression.hpp: a program with no time and no state, such
// as "2/3" or "cos(1.1)/2"), so that a number a scene writes as a formula enters the general path
// of --certify as a ball that holds its exact value, as a decimal does (decimal_ball, ball.hpp).
//
// The formula is the torque's own evaluator with no variable (detail/field_algebra.hpp,
// ball_formula): its decimals by arb_set_str, pi by arb_const_pi, + - * / and the functions by
// Arb's (Johansson 2017), each rounding outward, and an integer power by arb_pow_ui. A function
// undefined somewhere on its argument's ball (log of a ball that reaches 0, sqrt of one that
// reaches below 0, a division by a ball that holds 0) is a std::domain_error naming the formula:
// never a ball that might miss.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/field_algebra.hpp>
#include <eulervop/model/expression.hpp>

#include <arb.h>

#include <stdexcept>
#include <string>

namespace eulervop {

inline ball constant_ball(const expression& e, slong prec) {
  if (!e.is_constant()) throw std::invalid_argument("constant_ball: `" + e.text + "` is not a constant formula");
  ball x = detail::ball_formula(e, prec).constant_value(prec);
  if (!arb_is_finite(x.get())) throw std::domain_error("`" + e.text + "`: its ball is not finite");
  return x;
}

}  // namespace eulervop
