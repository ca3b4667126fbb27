// Euler's equations as a problem (problem.hpp): y_i' = a_i y_j y_k + g_i(t, y), (i, j, k) cyclic,
// with the torque g a type (torque.hpp). Two forms:
//   - normalized, the paper's Eq. 5: a = (-1, 1, -1), y = Omega, t = tau, g = G;
//   - direct, Eq. 1 divided by the moments: a_i = (I_j - I_k) / I_i, y = omega in rad/s, t in s,
//     g = M / I (physical_scaling.hpp), for bodies with (nearly) equal moments.
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/model/problem.hpp>
#include <eulervop/model/torque.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace eulervop {

// Eq. 5: Omega1' = -Omega2 Omega3 + G1, Omega2' = Omega1 Omega3 + G2, Omega3' = -Omega1 Omega2 + G3.
// Any arithmetic T: the benchmarks' Boost.Odeint peers evaluate it on their own number types
// (benchmarks/bench_reference.cpp).
template <class T>
inline void euler_rhs(const vec3<T>& Om, const vec3<T>& G, vec3<T>& dOm) {
  dOm[0] = G[0] - Om[1] * Om[2];
  dOm[1] = G[1] + Om[0] * Om[2];
  dOm[2] = G[2] - Om[0] * Om[1];
}

// Eq. 1 divided by I_i: omega_i' = a_i omega_j omega_k + M_i / I_i, (i, j, k) cyclic, with
// a_i = (I_j - I_k) / I_i. It holds in any right-handed frame of principal axes, whatever the
// order of the moments, and for equal moments (a_i = 0 on the symmetry axis); Eq. 5 is the case
// a = (-1, 1, -1) in the normalized variables.
template <class T>
inline void direct_rhs(const vec3<T>& a, const vec3<T>& w, const vec3<T>& g, vec3<T>& dw) {
  dw[0] = g[0] + a[0] * (w[1] * w[2]);
  dw[1] = g[1] + a[1] * (w[2] * w[0]);
  dw[2] = g[2] + a[2] * (w[0] * w[1]);
}

// The coefficients a of Eq. 5 in the form of Eq. 1.
template <class T>
vec3<T> normalized_coefficients() {
  return {T(-1), T(1), T(-1)};
}

// One problem of Euler's equations on [tau0, ...], y(tau0) = Omega0. In the normalized form the
// right-hand side is Eq. 5 itself (no product by a = +-1), in the direct form Eq. 1: the two
// round alike, since a product by +-1 is exact.
template <class T, class Torque = constant_torque<T>>
struct euler_problem {
  using value_type = T;
  using torque_type = Torque;
  static constexpr std::size_t dimension = 3;
  using state_type = vec3<T>;
  using jacobian_type = std::array<vec3<T>, 3>;
  // Component i of the quadratic part is a_i y_j y_k with (j, k) = quadratic_pair[i].
  static constexpr std::array<std::array<int, 2>, 3> quadratic_pair = {{{1, 2}, {2, 0}, {0, 1}}};

  Torque torque{};
  vec3<T> Omega0{};  // the state at tau0
  T tau0 = 0;
  equation_form form = equation_form::normalized;
  vec3<T> a = normalized_coefficients<T>();

  bool normalized() const { return form == equation_form::normalized; }
  const vec3<T>& initial_state() const { return Omega0; }
  const T& initial_time() const { return tau0; }

  void rhs(const T& t, const vec3<T>& y, vec3<T>& dy) const {
    if (normalized())
      euler_rhs(y, torque.value(t, y), dy);
    else
      direct_rhs(a, y, torque.value(t, y), dy);
  }

  // J = [[0, a1 y3, a1 y2], [a2 y3, 0, a2 y1], [a3 y2, a3 y1, 0]] (plus the torque's, when it
  // depends on the state).
  void jacobian(const T& t, const vec3<T>& y, jacobian_type& J) const {
    for (int i = 0; i < 3; ++i) {
      const auto [j, k] = quadratic_pair[i];
      J[i][i] = T(0);
      J[i][j] = a[i] * y[k];
      J[i][k] = a[i] * y[j];
    }
    if constexpr (torque_traits<Torque>::depends_on_state) torque.add_jacobian(t, y, J);
  }
};

static_assert(euler_form_problem<euler_problem<double>>);

}  // namespace eulervop
