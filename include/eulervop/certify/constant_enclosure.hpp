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
#include <stdexcept>
#include <string>
#include <vector>

namespace eulervop {

inline interval enclose_constant(const expression& e, mpfr_prec_t bits) {
  if (!e.is_constant()) throw std::invalid_argument("enclose_constant: `" + e.text + "` is not a constant formula");
  const interval_precision_scope scope(bits);
  const auto undefined = [&](const char* what) {
    return std::domain_error("`" + e.text + "`: " + what + ", so it has no enclosure");
  };
  std::vector<interval> stack;
  const auto top = [&]() -> interval& { return stack.back(); };
  const auto pop = [&] {
    interval x = std::move(stack.back());
    stack.pop_back();
    return x;
  };
  for (const expression_step& s : e.code) {
    switch (s.op) {
      case expression_op::constant: {
        interval c = interval::zero(bits);
        detail::set_decimal(c, e.constants[static_cast<std::size_t>(s.arg)]);
        stack.push_back(std::move(c));
        break;
      }
      case expression_op::pi: {
        interval p = interval::zero(bits);
        mpfi_const_pi(p.get());
        stack.push_back(std::move(p));
        break;
      }
      case expression_op::variable: throw std::logic_error("enclose_constant: a variable in a constant formula");
      case expression_op::add: { const interval y = pop(); top() = top() + y; break; }
      case expression_op::sub: { const interval y = pop(); top() = top() - y; break; }
      case expression_op::mul: { const interval y = pop(); top() = top() * y; break; }
      case expression_op::div: {
        const interval y = pop();
        if (mpfi_has_zero(y.get())) throw undefined("a divisor's enclosure holds 0");
        top() = top() / y;
        break;
      }
      case expression_op::neg: top() = -top(); break;
      case expression_op::pow: {
        interval r = interval::zero(bits);
        mpfi_set_si(r.get(), 1);
        for (int k = 0; k < std::abs(s.arg); ++k) r = r * top();
        if (s.arg < 0) {
          if (mpfi_has_zero(r.get())) throw undefined("a negative power of an enclosure that holds 0");
          interval one = interval::zero(bits);
          mpfi_set_si(one.get(), 1);
          r = one / r;
        }
        top() = std::move(r);
        break;
      }
      case expression_op::sin: mpfi_sin(top().get(), top().get()); break;
      case expression_op::cos: mpfi_cos(top().get(), top().get()); break;
      case expression_op::exp: mpfi_exp(top().get(), top().get()); break;
      case expression_op::log:
        if (mpfi_is_strictly_pos(top().get()) <= 0) throw undefined("log of an enclosure that reaches 0 or below");
        mpfi_log(top().get(), top().get());
        break;
      case expression_op::sqrt:
        if (mpfi_is_nonneg(top().get()) <= 0) throw undefined("sqrt of an enclosure that reaches below 0");
        mpfi_sqrt(top().get(), top().get());
        break;
    }
  }
  if (stack.size() != 1) throw std::logic_error("enclose_constant: the program does not leave one value");
  if (mpfi_nan_p(stack[0].get()) || mpfi_bounded_p(stack[0].get()) == 0)
    throw undefined("its enclosure is not a bounded interval");
  return pop();
}

}  // namespace eulervop
