// Compensated summation (TwoSum, Knuth TAOCP vol. 2, 4.2.2; core/error_free.hpp) of what the
// Runge-Kutta drivers accumulate over many steps: the state and the time.
//
// The state: c carries the rounding error of x + increment from step to step, so over n steps the
// state loses O(eps) instead of O(sqrt(n) eps). Long fixed-step runs (1e5 steps) need it: without
// it a torque-free VOP phase u = c2 tau drifts by ~sqrt(n) ulp(u) although each increment is
// exact to rounding.
// The time: an unevaluated sum t_hi + t_lo, so that after 1e6 adaptive steps the state is at the
// time the observer is told, not at a time off by sqrt(n) ulp(t).
#pragma once

#include <eulervop/core/error_free.hpp>
#include <eulervop/core/scalar_traits.hpp>

namespace eulervop::rk::detail {

// y = x0 + (inc + c_in), with c_out the rounding error of that sum; inc and bb are scratch (the
// stage work area's, so that MPFR allocates nothing). c_in and c_out may be the same value.
template <scalar T>
[[gnu::always_inline]] inline void compensated_add(const T& x0, T& inc, const T& c_in, T& c_out, T& y, T& bb) {
  inc += c_in;
  two_sum(x0, inc, y, c_out, bb);
}

// t_hi + t_lo <- t_hi + t_lo + h.
template <scalar T>
void advance_time(T& hi, T& lo, const T& h) {
  T s, err, bb;
  two_sum(hi, h, s, err, bb);
  err += lo;
  hi = s + err;
  lo = err - (hi - s);
}

}  // namespace eulervop::rk::detail
