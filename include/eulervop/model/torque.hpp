// The torque term of Euler's equations, g(t, y) in y_i' = a_i y_j y_k + g_i(t, y)
// (euler_problem.hpp): G of Eq. 5, or M_i / I_i in the direct form of Eq. 1.
//
// A torque is a type. Its traits say what it depends on, and the integrators choose their fast
// paths from them at compile time (docs/design.md, "The problem and its torque"):
//   - a torque that does not depend on the state cancels from every difference
//     f(t, y + d) - f(t, y), which is then the exact quadratic increment of Eq. 1 or 5: the
//     reference integrator's double-precision correction and its residual updates rest on it;
//   - a torque that depends on neither the time nor the state is one vector, read once per run.
//
// The interface of a torque type over the number type T is the concept `torque` below:
//   static constexpr bool depends_on_time, depends_on_state;
//   value(t, y) -> vec3<T> (or a reference to one): g at time t and state y;
//   add_jacobian(t, y, J): J[i][k] += d g_i / d y_k (only when it depends on the state);
//   convert_torque<double>(torque), found by argument-dependent lookup: the same torque in double
//   (the reference integrator evaluates its first residual in double).
// A torque with breakpoints (the concept piecewise_torque, expression_torque.hpp) also gives
//   breakpoints() -> the increasing times where its formulas change;
//   interval_at(t), pin(interval) const, unpin() const: the integrators end every segment and step
//   at a breakpoint, and pin the interval they work in, so that a segment ending on a
//   breakpoint sees the formulas of its own side there.
// The double-precision comparison runs (runs/comparison_run.hpp) are compiled once, for the
// constant torque and for one type that holds any other torque (runs/varying_torque.hpp): a
// torque type of the user's own runs there without instantiating drivers of its own.
#pragma once

#include <eulervop/core/vec3.hpp>

#include <array>
#include <concepts>
#include <cstddef>

namespace eulervop {

template <class Torque>
struct torque_traits {
  static constexpr bool depends_on_time = Torque::depends_on_time;
  static constexpr bool depends_on_state = Torque::depends_on_state;
  static constexpr bool is_constant = !depends_on_time && !depends_on_state;
};

// A torque type G over the number type T (the interface above).
template <class G, class T>
concept torque = requires(const G& g, const T& t, const vec3<T>& y, std::array<vec3<T>, 3>& J) {
  { G::depends_on_time } -> std::convertible_to<bool>;
  { G::depends_on_state } -> std::convertible_to<bool>;
  { g.value(t, y) } -> std::convertible_to<vec3<T>>;
  convert_torque<double>(g);
  requires !G::depends_on_state || requires { g.add_jacobian(t, y, J); };
};

// True when the torque is one vector for the whole run.
template <class Torque>
inline constexpr bool is_constant_torque_v = torque_traits<Torque>::is_constant;

// A torque whose formulas change at breakpoints (see above).
template <class Torque>
concept piecewise_torque = requires(const Torque& g, std::size_t i) {
  g.breakpoints();
  g.interval_at(g.breakpoints().front());
  g.pin(i);
  g.unpin();
};

// A constant torque: the paper's case (Eq. 5 with constant G).
template <class T>
struct constant_torque {
  static constexpr bool depends_on_time = false;
  static constexpr bool depends_on_state = false;

  vec3<T> G{};

  const vec3<T>& value(const T&, const vec3<T>&) const { return G; }
};

template <class U, class T>
constant_torque<U> convert_torque(const constant_torque<T>& torque) {
  return {{static_cast<U>(torque.G[0]), static_cast<U>(torque.G[1]), static_cast<U>(torque.G[2])}};
}

}  // namespace eulervop
