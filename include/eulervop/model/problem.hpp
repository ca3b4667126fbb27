// What every integrator takes: a problem y' = f(t, y), y(t0) = y0, with a state of a dimension
// known at compile time, its Jacobian, and a torque type whose traits say what it depends on
// (torque.hpp). The Chebyshev-Picard reference, the Runge-Kutta runs and the certifier are
// templates over it; euler_problem.hpp is its instance for Euler's equations.
#pragma once

#include <array>
#include <concepts>
#include <cstddef>

namespace eulervop {

template <class P>
concept problem = requires(const P& p, const typename P::value_type& t, const typename P::state_type& y,
                           typename P::state_type& dy, typename P::jacobian_type& J) {
  typename P::torque_type;
  { P::dimension } -> std::convertible_to<std::size_t>;
  requires std::same_as<typename P::state_type, std::array<typename P::value_type, P::dimension>>;
  p.rhs(t, y, dy);       // dy = f(t, y)
  p.jacobian(t, y, J);   // J[i][k] = d f_i / d y_k at (t, y)
  { p.initial_state() } -> std::convertible_to<const typename P::state_type&>;
  { p.initial_time() } -> std::convertible_to<const typename P::value_type&>;
};

}  // namespace eulervop
