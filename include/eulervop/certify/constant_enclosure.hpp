// The enclosure of a constant formula (model/expression.hpp: a program with no time and no state,
// such as "2/3" or "cos(1.1)/2"), so that a number a scene writes as a formula enters the
// certificate as an interval that holds its exact value, as a decimal does (set_decimal).
//
// Each step is MPFI's interval extension of its operation, rounded outward: the decimal
// constants by set_decimal, pi by mpfi_const_pi, + - * / and the functions by MPFI's own (which
// are inclusion-isotone), and an integer power by repeated products (a wider but valid enclosure
// when the base holds 0). A function that is undefined somewhere on its argument's enclosure
// (log of an interval that reaches 0, sqrt of one that reaches below 0, a division by an interval
// that holds 0) is a std::domain_error naming the function: never an enclosure that might miss.
#pragma once

#include <eulervop/certify/interval.hpp>
#include <eulervop/model/expression.hpp>

#include <mpfi.h>
#include <mpfr.h>

#include <cstdlib>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace eulervop {

namespace detail {

// 1 in an interval of `bits`.
inline interval interval_one(mpfr_prec_t bits) {
  interval one = interval::zero(bits);
  mpfi_set_si(one.get(), 1);
  return one;
}

// x^n by |n| products, then the reciprocal for n < 0.
inline interval integer_power(const interval& x, int n, const std::function<std::domain_error(const char*)>& undefined) {
  interval r = interval_one(x.bits());
  for (int k = 0; k < std::abs(n); ++k) r = r * x;
  if (n >= 0) return r;
  if (mpfi_has_zero(r.get())) throw undefined("a negative power of an enclosure that holds 0");
  return interval_one(x.bits()) / r;
}

// One function step on the top of the stack, in place.
inline void apply_function(expression_op op, interval& x, const std::function<std::domain_error(const char*)>& undefined) {
  switch (op) {
    case expression_op::sin: mpfi_sin(x.get(), x.get()); break;
    case expression_op::cos: mpfi_cos(x.get(), x.get()); break;
    case expression_op::exp: mpfi_exp(x.get(), x.get()); break;
    case expression_op::tanh: mpfi_tanh(x.get(), x.get()); break;
    case expression_op::atan: mpfi_atan(x.get(), x.get()); break;
    case expression_op::sinh: mpfi_sinh(x.get(), x.get()); break;
    case expression_op::cosh: mpfi_cosh(x.get(), x.get()); break;
    case expression_op::log:
      if (mpfi_is_strictly_pos(x.get()) <= 0) throw undefined("log of an enclosure that reaches 0 or below");
      mpfi_log(x.get(), x.get());
      break;
    case expression_op::sqrt:
      if (mpfi_is_nonneg(x.get()) <= 0) throw undefined("sqrt of an enclosure that reaches below 0");
      mpfi_sqrt(x.get(), x.get());
      break;
    default: throw std::logic_error("enclose_constant: not a function step");
  }
}

}  // namespace detail

inline interval enclose_constant(const expression& e, mpfr_prec_t bits) {
  if (!e.is_constant()) throw std::invalid_argument("enclose_constant: `" + e.text + "` is not a constant formula");
  const interval_precision_scope scope(bits);
  const std::function<std::domain_error(const char*)> undefined = [&](const char* what) {
    return std::domain_error("`" + e.text + "`: " + what + ", so it has no enclosure");
  };
  std::vector<interval> stack;
  const auto pop = [&] {
    interval x = std::move(stack.back());
    stack.pop_back();
    return x;
  };
  for (const expression_step& s : e.code) {
    switch (s.op) {
      case expression_op::constant:
        stack.push_back(interval::zero(bits));
        detail::set_decimal(stack.back(), e.constants[static_cast<std::size_t>(s.arg)]);
        break;
      case expression_op::pi:
        stack.push_back(interval::zero(bits));
        mpfi_const_pi(stack.back().get());
        break;
      case expression_op::variable: throw std::logic_error("enclose_constant: a variable in a constant formula");
      case expression_op::add: { const interval y = pop(); stack.back() = stack.back() + y; break; }
      case expression_op::sub: { const interval y = pop(); stack.back() = stack.back() - y; break; }
      case expression_op::mul: { const interval y = pop(); stack.back() = stack.back() * y; break; }
      case expression_op::div: {
        const interval y = pop();
        if (mpfi_has_zero(y.get())) throw undefined("a divisor's enclosure holds 0");
        stack.back() = stack.back() / y;
        break;
      }
      case expression_op::neg: stack.back() = -stack.back(); break;
      case expression_op::pow: stack.back() = detail::integer_power(stack.back(), s.arg, undefined); break;
      default: detail::apply_function(s.op, stack.back(), undefined); break;
    }
  }
  if (stack.size() != 1) throw std::logic_error("enclose_constant: the program does not leave one value");
  if (mpfi_nan_p(stack[0].get()) || mpfi_bounded_p(stack[0].get()) == 0)
    throw undefined("its enclosure is not a bounded interval");
  return pop();
}

}  // namespace eulervop
