// Euler's equations (model/euler_problem.hpp) in the forms the reference integrator evaluates
// them: in T at the nodes, in double for the first residual, and their increment
// f(t, x + d) - f(t, x) in double and double-double for the corrections and residual updates.
//
// The equations are quadratic, so for a torque that does not depend on the state the increment
// is exactly g_i = a_i (x_j d_k + x_k d_j + d_j d_k), (i, j, k) cyclic: the torque cancels,
// whatever its time. A torque of the state adds its own linear term J_g(x) d, which makes the
// correction a Newton-like step (the residual in T still decides convergence).
#pragma once

#include <eulervop/core/error_free.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/reference/detail/node_sines.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cmath>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

namespace eulervop::detail {

template <euler_form_problem P>
class euler_field {
 public:
  using T = typename P::value_type;
  using torque_traits_type = torque_traits<typename P::torque_type>;
  using double_torque = decltype(convert_torque<double>(std::declval<const typename P::torque_type&>()));
  static constexpr std::size_t D = 3;
  // The torque's Jacobian at one node, where the correction linearizes it.
  using node_jacobian = std::array<vec3<double>, 3>;

  euler_field() = default;
  explicit euler_field(const P& problem)
      : problem_(problem), torque_d_(convert_torque<double>(problem.torque)) {
    if constexpr (!torque_traits_type::depends_on_time && !torque_traits_type::depends_on_state)
      constant_torque_dd_ = split(problem.torque.value(problem.tau0, vec3<T>{}));
    if (problem.normalized()) return;  // a = (-1, 1, -1): exact in double
    a_max_ = 0;
    for (int i = 0; i < 3; ++i) {
      const double_double a = to_double_double(problem.a[i]);
      a_d_[i] = a.hi;
      a_lo_[i] = a.lo;
      a_max_ = std::max(a_max_, std::abs(a_d_[i]));
    }
  }

  const P& problem() const { return problem_; }

  void rhs(const T& t, const vec3<T>& x, vec3<T>& dx) const { problem_.rhs(t, x, dx); }
  // The same at node j of the segment whose node times `set_node_times` last received: a torque
  // of time alone is evaluated there once per segment, not in every pass (the passes of one
  // segment see the same times; a sinq costs about 0.7 us in quad). The same operations as rhs,
  // so the same bits.
  void rhs_at_node(std::size_t j, const T& t, const vec3<T>& x, vec3<T>& dx) const {
    if constexpr (caches_torque) {
      if (problem_.normalized())
        euler_rhs(x, node_torque_[j], dx);
      else
        direct_rhs(problem_.a, x, node_torque_[j], dx);
    } else {
      rhs(t, x, dx);
    }
  }
  // t: the node times, t_j = (alpha + alpha_lo) + beta s_j, alpha + alpha_lo the segment's exact
  // midpoint. In quad, a law of time whose sines and cosines have arguments affine in t gets them
  // from one sine per segment (node_sines.hpp); otherwise, and wherever node_sines declines, a
  // value per node.
  void set_node_times(const std::vector<T>& t, const T& alpha, const T& alpha_lo, const T& beta) {
    if constexpr (caches_torque) {
      node_torque_dd_.resize(t.size());
      bool batched = false;
      if constexpr (std::is_same_v<T, quad> &&
                    requires { problem_.torque.values_at_nodes(alpha, alpha_lo, beta, t, affine_sine_type{}, node_torque_); }) {
        if (!sines_ || sines_->degree() + 1 != t.size()) sines_.emplace(t.size() - 1);
        batched = problem_.torque.values_at_nodes(
            alpha, alpha_lo, beta, t,
            [this](const T& a, const T& a_lo, const T& b, bool cosine, std::vector<T>& out) {
              return sines_->evaluate(a, a_lo, b, cosine, out);
            },
            node_torque_);
      }
      if (!batched) {
        node_torque_.resize(t.size());
        for (std::size_t j = 0; j < t.size(); ++j) node_torque_[j] = problem_.torque.value(t[j], vec3<T>{});
      }
      for (std::size_t j = 0; j < t.size(); ++j) node_torque_dd_[j] = split(node_torque_[j]);
    }
  }

  // For a torque that does not read the state: f(t_j, x) hl at node j in double-double from x in
  // double-double, about 2^-104 relative, for the residual that drives the second correction
  // (picard_residuals.hpp). No operation in T: x, the torque and a are split once.
  static constexpr bool has_double_double_rhs = !torque_traits_type::depends_on_state;
  void scaled_rhs(std::size_t j, const std::array<double_double, 3>& x, const double_double& hl,
                  std::array<double_double, 3>& out) const {
    const std::array<double_double, 3>& g = caches_torque ? node_torque_dd_[j] : constant_torque_dd_;
    for (int i = 0; i < 3; ++i) {
      const auto [a, b] = P::quadratic_pair[i];
      const double_double q = mul(mul(x[a], x[b]), double_double{a_d_[i], a_lo_[i]});  // exact for a = +-1 (Eq. 5)
      out[i] = mul(add(g[i], q), hl);
    }
  }
  void rhs_double(double t, const vec3<double>& x, vec3<double>& dx) const {
    direct_rhs(a_d_, x, torque_d_.value(t, x), dx);
  }
  // The fastest rate in sight at (t, x), for the first segment's length: |a| |y_i|, and
  // sqrt(|a| |g_i|) for the spin-up from rest.
  double first_rate(double t, const vec3<double>& x) const {
    const vec3<double> g = torque_d_.value(t, x);
    double rate = 0;
    for (int i = 0; i < 3; ++i) rate = std::max({rate, a_max_ * std::abs(x[i]), std::sqrt(a_max_ * std::abs(g[i]))});
    return rate;
  }

  // The quadratic part of the increment at one node, in double (products by a = +-1 are exact).
  [[gnu::always_inline]] void increment(double x1, double x2, double x3, double d1, double d2, double d3,
                                        double& g1, double& g2, double& g3) const {
    g1 = a_d_[0] * (x2 * d3 + x3 * d2 + d2 * d3);
    g2 = a_d_[1] * (x1 * d3 + x3 * d1 + d1 * d3);
    g3 = a_d_[2] * (x1 * d2 + x2 * d1 + d1 * d2);
  }

  // J(x) v for the quadratic part's Jacobian at x in double, J_ij = a_i x_k, J_ik = a_i x_j: for
  // the correction's implicit node step (picard_correction.hpp).
  std::array<double, 3> quadratic_jacobian_times(const std::array<double, 3>& x, const std::array<double, 3>& v) const {
    return {a_d_[0] * (x[2] * v[1] + x[1] * v[2]), a_d_[1] * (x[2] * v[0] + x[0] * v[2]),
            a_d_[2] * (x[1] * v[0] + x[0] * v[1])};
  }

  // The same in double-double from x in double-double, errs by about 2^-100 |d|.
  std::array<double_double, 3> increment(const std::array<double_double, 3>& x, double d1, double d2,
                                         double d3) const {
    const double_double &x1 = x[0], &x2 = x[1], &x3 = x[2];
    std::array<double_double, 3> g = {add(add(mul(x2, d3), mul(x3, d2)), two_product(d2, d3)),
                                      add(add(mul(x1, d3), mul(x3, d1)), two_product(d1, d3)),
                                      add(add(mul(x1, d2), mul(x2, d1)), two_product(d1, d2))};
    for (int i = 0; i < 3; ++i) g[i] = mul(g[i], double_double{a_d_[i], a_lo_[i]});  // exact for a = +-1 (Eq. 5)
    return g;
  }

  // Pins the torque's interval of breakpoints that contains t (a segment's start: no segment
  // crosses a breakpoint), in T and in double; nothing for a torque without breakpoints.
  void pin_at(const T& t) const {
    if constexpr (piecewise_torque<typename P::torque_type>) {
      const std::size_t i = problem_.torque.interval_at(t);
      problem_.torque.pin(i);
      torque_d_.pin(i);
    }
  }

  // d g / d x of a torque of the state, at (t, x), in double.
  void torque_jacobian(double t, const vec3<double>& x, std::array<vec3<double>, 3>& J) const {
    for (auto& row : J) row = {0.0, 0.0, 0.0};
    torque_d_.add_jacobian(t, x, J);
  }

 private:
  static constexpr bool caches_torque = torque_traits_type::depends_on_time && !torque_traits_type::depends_on_state;
  // The shape of the callback values_at_nodes takes (for the requires-test above).
  struct affine_sine_type {
    bool operator()(const T&, const T&, const T&, bool, std::vector<T>&) const { return false; }
  };
  static std::array<double_double, 3> split(const vec3<T>& v) {
    return {to_double_double(v[0]), to_double_double(v[1]), to_double_double(v[2])};
  }

  P problem_;
  std::vector<vec3<T>> node_torque_;  // the torque at the nodes (a torque of time alone)
  std::optional<node_sines> sines_;    // quad: sines of arguments affine in t, for this degree
  std::vector<std::array<double_double, 3>> node_torque_dd_;  // the same in double-double
  std::array<double_double, 3> constant_torque_dd_{};         // a constant torque in double-double
  double_torque torque_d_;
  std::array<double, 3> a_d_{-1.0, 1.0, -1.0}, a_lo_{};
  double a_max_ = 1;
};

}  // namespace eulervop::detail
