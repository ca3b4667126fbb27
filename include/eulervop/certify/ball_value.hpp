// A ball of Arb (Johansson 2017, "Arb: efficient arbitrary-precision midpoint-radius interval
// arithmetic", IEEE Trans. Computers 66) with value semantics, for the scalar-generic setup code
// of the general path of --certify: physical_scaling<ball_value> (model/physical_scaling.hpp)
// states Eqs. 2-4 once for every number type, and this type runs them on balls that hold the
// exact values. Each operation is Arb's, which rounds its result outward into the radius, so the
// exact result of the real operation on any points of the operands lies in the result.
//
// A value carries the precision its operations work at: a binary operation works at the larger of
// its operands'. An integer (generic code's N(0), N(1)) is an exact ball in Arb at any precision,
// so it carries none (0), and + - * of two integers are exact; a quotient or a square root needs a
// precision from one operand.
//
// There is no order: two balls that overlap are neither less nor greater, and the setup never
// needs one (the principal order of the moments is that of their decimals' doubles,
// scene_problem.hpp, uses_direct_form). Generic code that compares numbers does not compile with
// this type rather than pick a side.
#pragma once

#include <eulervop/certify/ball.hpp>

#include <arb.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace eulervop {

class ball_value {
 public:
  // 0, exact.
  ball_value() = default;
  // The integer exactly (implicit, as for the scalars: `N x = 0`).
  ball_value(int value) : b_(value) {}
  // The ball x, whose operations work at `prec` bits (> 0).
  ball_value(ball x, slong prec) : b_(std::move(x)), prec_(prec) {
    if (prec <= 0) throw std::invalid_argument("ball_value: the precision must be positive");
  }

  const ball& get() const { return b_; }
  // The precision of the value's operations; 0 for an exact integer.
  slong prec() const { return prec_; }

  friend ball_value operator+(const ball_value& x, const ball_value& y) { return binary(arb_add, x, y, exact_ring); }
  friend ball_value operator-(const ball_value& x, const ball_value& y) { return binary(arb_sub, x, y, exact_ring); }
  friend ball_value operator*(const ball_value& x, const ball_value& y) { return binary(arb_mul, x, y, exact_ring); }
  friend ball_value operator/(const ball_value& x, const ball_value& y) { return binary(arb_div, x, y, 0); }
  friend ball_value operator-(const ball_value& x) {
    ball_value out = x;
    arb_neg(out.b_.get(), out.b_.get());
    return out;
  }
  ball_value& operator+=(const ball_value& y) { return *this = *this + y; }
  friend ball_value sqrt(const ball_value& x) {
    ball_value out;
    out.prec_ = needed(x.prec_, 0);
    arb_sqrt(out.b_.get(), x.b_.get(), out.prec_);
    return out;
  }

  // No order (see above).
  friend bool operator<(const ball_value&, const ball_value&) = delete;
  friend bool operator>(const ball_value&, const ball_value&) = delete;
  friend bool operator<=(const ball_value&, const ball_value&) = delete;
  friend bool operator>=(const ball_value&, const ball_value&) = delete;
  friend bool operator==(const ball_value&, const ball_value&) = delete;

 private:
  // + - * of two exact integers: exact in Arb.
  static constexpr slong exact_ring = ARF_PREC_EXACT;

  // The larger precision of the operands, or `exact` where both are integers (0: none is exact).
  static slong needed(slong p, slong exact) {
    if (p > 0) return p;
    if (exact == 0) throw std::logic_error("ball_value: a quotient or square root of integers needs a precision");
    return exact;
  }

  template <class Op>
  static ball_value binary(Op op, const ball_value& x, const ball_value& y, slong exact) {
    ball_value out;
    out.prec_ = std::max(x.prec_, y.prec_);
    op(out.b_.get(), x.b_.get(), y.b_.get(), needed(out.prec_, exact));
    return out;
  }

  ball b_;
  slong prec_ = 0;
};

}  // namespace eulervop
