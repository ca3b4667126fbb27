// What the integrators take, stated as the concepts they rely on.
//
// `problem`: y' = f(t, y), y(t0) = y0, with a state of a dimension known at compile time and its
// Jacobian. The Runge-Kutta steppers need no more (rk/problem_system.hpp).
//
// `euler_form_problem`: a problem of Euler's equations, y_i' = a_i y_j y_k + g_i(t, y) with
// (i, j, k) cyclic (euler_problem.hpp is its instance): the coefficients a, the form, and a
// torque g that is a `torque` (torque.hpp). The Chebyshev-Picard reference and the
// double-precision runs rely on this shape: their fast paths are the exact quadratic increment
// of the a-terms, chosen from the torque's traits.
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/model/torque.hpp>

#include <array>
#include <concepts>
#include <cstddef>

namespace eulervop {

template <class P>
concept problem = requires(const P& p, const typename P::value_type& t, const typename P::state_type& y,
                           typename P::state_type& dy, typename P::jacobian_type& J) {
  { P::dimension } -> std::convertible_to<std::size_t>;
  requires std::same_as<typename P::state_type, std::array<typename P::value_type, P::dimension>>;
  p.rhs(t, y, dy);       // dy = f(t, y)
  p.jacobian(t, y, J);   // J[i][k] = d f_i / d y_k at (t, y)
  { p.initial_state() } -> std::convertible_to<const typename P::state_type&>;
  { p.initial_time() } -> std::convertible_to<const typename P::value_type&>;
};

enum class equation_form {
  normalized,  // Eq. 5
  direct,      // Eq. 1 in the body's axes
};

template <class P>
concept euler_form_problem = problem<P> && P::dimension == 3 &&
                             torque<typename P::torque_type, typename P::value_type> && requires(const P& p) {
                               { p.a } -> std::convertible_to<const vec3<typename P::value_type>&>;
                               { p.form } -> std::convertible_to<equation_form>;
                               { p.torque } -> std::convertible_to<const typename P::torque_type&>;
                             };

}  // namespace eulervop
