// Which equations the reference integrator evaluates for a problem: Euler's equations of 3 states
// (euler_field.hpp), or the rates and the attitude coupled by a torque of the attitude, 7 states
// (coupled_field.hpp). The two differ in the correction's increment: exact and quadratic for the
// first (with a torque that does not read the state), linearized for the second.
#pragma once

#include <eulervop/model/coupled_problem.hpp>
#include <eulervop/model/problem.hpp>
#include <eulervop/reference/detail/coupled_field.hpp>
#include <eulervop/reference/detail/euler_field.hpp>

namespace eulervop {

template <class P>
inline constexpr bool is_coupled_problem_v = false;
template <class T>
inline constexpr bool is_coupled_problem_v<coupled_problem<T>> = true;

// What the Chebyshev-Picard integrator takes.
template <class P>
concept picard_problem = euler_form_problem<P> || is_coupled_problem_v<P>;

namespace detail {

template <class P>
struct field_selector {
  using type = euler_field<P>;
};
template <class T>
struct field_selector<coupled_problem<T>> {
  using type = coupled_field<coupled_problem<T>>;
};
template <class P>
using field_of = typename field_selector<P>::type;

}  // namespace detail
}  // namespace eulervop
