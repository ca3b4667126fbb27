// Euler's equations with a torque of the attitude, and the attitude itself: one problem of 7
// states (problem.hpp), (y_1, y_2, y_3, q_0, ..., q_3) (docs/attitude.md, "Torques of the
// attitude"):
//   y_i' = a_i y_j y_k + g_i(t, y, q), (i, j, k) cyclic (Eq. 5, or Eq. 1 in the direct form),
//   q'   = 1/2 q (x) (0, W(y)),
// W the body rates per unit of the integrator's time in the listed axes (body_rates.hpp), q the
// attitude (body to inertial) in the listed axes. With a torque that does not read q, the rates
// evolve on their own and q follows them (reference/attitude_cascade.hpp); here it cannot.
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/model/attitude_torque.hpp>
#include <eulervop/model/body_rates.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/problem.hpp>

#include <array>
#include <cstddef>

namespace eulervop {

template <class T>
struct coupled_problem {
  using value_type = T;
  using torque_type = attitude_torque<T>;
  static constexpr std::size_t dimension = 7;
  using state_type = std::array<T, 7>;
  using jacobian_type = std::array<std::array<T, 7>, 7>;

  torque_type torque{};
  state_type initial{};  // (y, q) at tau0
  T tau0 = 0;
  equation_form form = equation_form::normalized;
  vec3<T> a = normalized_coefficients<T>();
  body_rates<T> rates;

  bool normalized() const { return form == equation_form::normalized; }
  const state_type& initial_state() const { return initial; }
  const T& initial_time() const { return tau0; }

  static vec3<T> rates_part(const state_type& x) { return {x[0], x[1], x[2]}; }
  static std::array<T, 4> attitude_part(const state_type& x) { return {x[3], x[4], x[5], x[6]}; }

  void rhs(const T& t, const state_type& x, state_type& dx) const {
    const vec3<T> y = rates_part(x);
    const std::array<T, 4> q = attitude_part(x);
    vec3<T> dy;
    if (normalized())
      euler_rhs(y, torque.value(t, y, q), dy);
    else
      direct_rhs(a, y, torque.value(t, y, q), dy);
    const vec3<T> W = rates(y);
    // q (x) (0, W), halved (exact).
    const T dw = -q[1] * W[0] - q[2] * W[1] - q[3] * W[2];
    const T dx1 = q[0] * W[0] + q[2] * W[2] - q[3] * W[1];
    const T dx2 = q[0] * W[1] - q[1] * W[2] + q[3] * W[0];
    const T dx3 = q[0] * W[2] + q[1] * W[1] - q[2] * W[0];
    for (int i = 0; i < 3; ++i) dx[i] = dy[i];
    dx[3] = dw / 2;
    dx[4] = dx1 / 2;
    dx[5] = dx2 / 2;
    dx[6] = dx3 / 2;
  }

  void jacobian(const T& t, const state_type& x, jacobian_type& J) const {
    for (auto& row : J) row.fill(T(0));
    const vec3<T> y = rates_part(x);
    const std::array<T, 4> q = attitude_part(x);
    for (int i = 0; i < 3; ++i) {
      const auto [j, k] = euler_problem<T>::quadratic_pair[i];
      J[i][j] = a[i] * y[k];
      J[i][k] = a[i] * y[j];
    }
    typename torque_type::jacobian_rows Jg;
    for (auto& row : Jg) row.fill(T(0));
    torque.add_jacobian(t, y, q, Jg);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 7; ++k) J[i][k] += Jg[i][k];
    // d q' / d q = 1/2 [[0, -W1, -W2, -W3], [W1, 0, W3, -W2], [W2, -W3, 0, W1], [W3, W2, -W1, 0]].
    const vec3<T> W = rates(y);
    const std::array<std::array<T, 4>, 4> dq = {{{T(0), -W[0], -W[1], -W[2]},
                                                 {W[0], T(0), W[2], -W[1]},
                                                 {W[1], -W[2], T(0), W[0]},
                                                 {W[2], W[1], -W[0], T(0)}}};
    // d q' / d W = 1/2 [[-q1, -q2, -q3], [q0, -q3, q2], [q3, q0, -q1], [-q2, q1, q0]], and
    // d W / d y_i is the column of the listed axis that y_i maps to.
    const std::array<std::array<T, 3>, 4> dW = {{{-q[1], -q[2], -q[3]},
                                                 {q[0], -q[3], q[2]},
                                                 {q[3], q[0], -q[1]},
                                                 {-q[2], q[1], q[0]}}};
    for (int r = 0; r < 4; ++r) {
      for (int m = 0; m < 4; ++m) J[3 + r][3 + m] = dq[r][m] / 2;
      for (int i = 0; i < 3; ++i) {
        const int u = rates.identity ? i : rates.axes.axis(i);
        T d = dW[r][u] * rates.scale[i] / 2;
        if (!rates.identity && rates.axes.sign(i) < 0) d = -d;
        J[3 + r][i] = d;
      }
    }
  }
};

static_assert(problem<coupled_problem<double>>);

}  // namespace eulervop
