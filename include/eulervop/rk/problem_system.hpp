// A problem (model/problem.hpp) as a system of the Runge-Kutta steppers: sys(x, dxdt, t) is
// problem.rhs(t, x, dxdt), the time passed through.
//
// It holds a copy of the problem (for Euler's equations a few constants), so that a system made
// for a run refers to nothing that could end before it.
#pragma once

#include <eulervop/model/problem.hpp>

namespace eulervop::rk {

template <problem Problem>
struct problem_system {
  using value_type = typename Problem::value_type;
  using state_type = typename Problem::state_type;

  Problem problem;

  [[gnu::always_inline]] void operator()(const state_type& x, state_type& dxdt, const value_type& t) const {
    problem.rhs(t, x, dxdt);
  }
};

}  // namespace eulervop::rk
