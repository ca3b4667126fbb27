// The coupled problem of the rates and the attitude (model/coupled_problem.hpp) in the forms the
// reference integrator evaluates it: in T at the nodes, in double for the first residual, and
// its Jacobian in double, where the correction linearizes it.
//
// Unlike Euler's equations with a torque of time (euler_field.hpp), the increment
// f(t, x + d) - f(t, x) is not an exact quadratic here: the torque reads q through formulas and
// the gravity gradient's cos and sin. The correction takes its linear part J(x) d, a Newton-like
// step; each pass still ends with a residual in T, which alone decides convergence
// (docs/design.md section 3.2).
#pragma once

#include <eulervop/core/scalar.hpp>
#include <eulervop/model/coupled_problem.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace eulervop::detail {

template <class P>
class coupled_field {
 public:
  using T = typename P::value_type;
  static constexpr std::size_t D = P::dimension;
  using torque_traits_type = torque_traits<typename P::torque_type>;
  using node_jacobian = std::array<std::array<double, D>, D>;

  coupled_field() = default;
  explicit coupled_field(const P& problem) : problem_(problem), problem_d_(to_double(problem)) {
    a_max_ = 0;
    for (int i = 0; i < 3; ++i) a_max_ = std::max(a_max_, std::abs(problem_d_.a[i]));
  }

  const P& problem() const { return problem_; }

  void rhs(const T& t, const std::array<T, D>& x, std::array<T, D>& dx) const { problem_.rhs(t, x, dx); }
  // At node j: the torque reads the state, so there is nothing to keep from pass to pass.
  void rhs_at_node(std::size_t, const T& t, const std::array<T, D>& x, std::array<T, D>& dx) const {
    rhs(t, x, dx);
  }
  void set_node_times(const std::vector<T>&, const T&, const T&, const T&) {}
  // Its narrow passes work in T (the formulas of q are evaluated in T only).
  static constexpr bool has_double_double_rhs = false;
  void rhs_double(double t, const std::array<double, D>& x, std::array<double, D>& dx) const {
    problem_d_.rhs(t, x, dx);
  }

  // The fastest rate in sight at (t, x), for the first segment's length: |a| |y_i| and
  // sqrt(|a| |g_i|) as for the rates alone, and the turn rate |W| of q.
  double first_rate(double t, const std::array<double, D>& x) const {
    const vec3<double> y = {x[0], x[1], x[2]};
    const vec3<double> g = problem_d_.torque.value(t, y, {x[3], x[4], x[5], x[6]});
    const vec3<double> W = problem_d_.rates(y);
    double rate = std::sqrt(W[0] * W[0] + W[1] * W[1] + W[2] * W[2]);
    for (int i = 0; i < 3; ++i) rate = std::max({rate, a_max_ * std::abs(y[i]), std::sqrt(a_max_ * std::abs(g[i]))});
    return rate;
  }

  // Pins the torque's interval of breakpoints that contains t (a segment's start).
  void pin_at(const T& t) const {
    const std::size_t i = problem_.torque.interval_at(t);
    problem_.torque.pin(i);
    problem_d_.torque.pin(i);
  }

  // d f / d x at (t, x), in double.
  void jacobian_double(double t, const std::array<double, D>& x, node_jacobian& J) const {
    problem_d_.jacobian(t, x, J);
  }

 private:
  static coupled_problem<double> to_double(const P& p) {
    coupled_problem<double> d;
    d.torque = convert_torque<double>(p.torque);
    for (std::size_t i = 0; i < D; ++i) d.initial[i] = static_cast<double>(p.initial[i]);
    d.tau0 = static_cast<double>(p.tau0);
    d.form = p.form;
    for (int i = 0; i < 3; ++i) d.a[i] = static_cast<double>(p.a[i]);
    d.rates.identity = p.rates.identity;
    d.rates.axes = p.rates.axes;
    for (int i = 0; i < 3; ++i) d.rates.scale[i] = static_cast<double>(p.rates.scale[i]);
    return d;
  }

  P problem_;
  coupled_problem<double> problem_d_;
  double a_max_ = 1;
};

}  // namespace eulervop::detail
