// What the tests of the VOP formulations under a torque of time or state share
// (test_vop_varying_*.cpp): the test torques (the interface of model/torque.hpp), the same laws as
// the scene's formulas, and the error of a run against the quad reference. The test torques run
// in the compiled run drivers (runs/varying_torque.hpp holds any torque type).
#pragma once

#include <eulervop/core/outcome_text.hpp>
#include <eulervop/model/error_measure.hpp>
#include <eulervop/model/expression_torque.hpp>
#include <eulervop/model/torque_law.hpp>
#include <eulervop/reference/integrate.hpp>
#include <eulervop/runs/comparison_run.hpp>
#include <eulervop/scene/expression_parser.hpp>
#include <eulervop/special/elliptic.hpp>
#include <eulervop/vop/frame.hpp>
#include <eulervop/vop/vop_system.hpp>
#include <eulervop/vop/vop_theta_system.hpp>

#include "test_torques.hpp"
#include "vop_test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace vop_varying {

using eulervop::formulation;
using eulervop::quad;
using eulervop::vec3;

// ---- Test torques (the interface of model/torque.hpp) ----

// G = a (sin tau, cos 2 tau, 1): a torque of time, as a type of our own.
template <class T>
struct wobble_torque {
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = false;
  T a;
  vec3<T> value(const T& t, const vec3<T>&) const {
    using std::cos;
    using std::sin;
    return {a * sin(t), a * cos(2 * t), a};
  }
};
template <class U, class T>
wobble_torque<U> convert_torque(const wobble_torque<T>& g) {
  return {static_cast<U>(g.a)};
}

using eulervop::test_torques::damping_torque;

// A torque of time and state with every component different, for the chain rule: a wrong
// component, a missing rotation into the frame or Omega taken from the wrong frame all show.
template <class T>
struct mixed_torque {
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = true;
  vec3<T> value(const T& t, const vec3<T>& y) const {
    using std::cos;
    using std::sin;
    return {T("0.3") * sin(t) + T("0.2") * y[1], T("-0.5") * y[0] * y[2] + cos(t), T("0.1") * y[2] - T("0.2")};
  }
  void add_jacobian(const T&, const vec3<T>& y, std::array<vec3<T>, 3>& J) const {
    J[0][1] += T("0.2");
    J[1][0] += T("-0.5") * y[2];
    J[1][2] += T("-0.5") * y[0];
    J[2][2] += T("0.1");
  }
};
template <class U, class T>
mixed_torque<U> convert_torque(const mixed_torque<T>&) {
  return {};
}

// A piecewise torque of time: a (sin tau, 0, 1) before the breakpoint b, a (-1, cos tau, 0) from b
// on. With breakpoints (piecewise_torque): the runs split the step that crosses b and pin the
// interval; Pieces = false is the same function without them, which the runs step across.
template <class T, bool Pieces>
struct switched_torque {
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = false;
  T a, b;
  std::vector<T> breaks;                      // {b}
  mutable std::optional<std::size_t> pinned;  // the interval a run pinned, in its own copy

  std::size_t interval_at(const T& t) const { return t < b ? 0 : 1; }
  vec3<T> value(const T& t, const vec3<T>&) const {
    using std::cos;
    using std::sin;
    if ((pinned ? *pinned : interval_at(t)) == 0) return {a * sin(t), T(0), a};
    return {-a, a * cos(t), T(0)};
  }
  const std::vector<T>& breakpoints() const
    requires Pieces
  {
    return breaks;
  }
  void pin(std::size_t i) const
    requires Pieces
  {
    pinned = i;
  }
  void unpin() const
    requires Pieces
  {
    pinned.reset();
  }
};
template <class U, class T, bool Pieces>
switched_torque<U, Pieces> convert_torque(const switched_torque<T, Pieces>& g) {
  return {static_cast<U>(g.a), static_cast<U>(g.b), {static_cast<U>(g.b)}, std::nullopt};
}
static_assert(eulervop::piecewise_torque<switched_torque<double, true>>);
static_assert(!eulervop::piecewise_torque<switched_torque<double, false>>);

// The torque law G = (0.01 sin(tau), 0.01 cos(2 tau), 0.01) through the scene's expression parser.
inline std::shared_ptr<const eulervop::torque_law> wobble_law() {
  const eulervop::scene::expression_variables vars{{"tau", "Omega1", "Omega2", "Omega3"}};
  auto law = std::make_shared<eulervop::torque_law>();
  law->base = {eulervop::scene::parse_expression("0.01*sin(tau)", vars),
               eulervop::scene::parse_expression("0.01*cos(2*tau)", vars),
               eulervop::scene::parse_expression("0.01", vars)};
  return law;
}

// The piecewise torque of switched_torque as the scene's formulas: base a (sin tau, 0, 1), and a
// piece [b, 100) with a (-1, cos tau, 0), a = 0.02, b = 7.77.
inline std::shared_ptr<const eulervop::torque_law> switched_law() {
  const eulervop::scene::expression_variables vars{{"tau", "Omega1", "Omega2", "Omega3"}};
  auto law = std::make_shared<eulervop::torque_law>();
  law->base = {eulervop::scene::parse_expression("0.02*sin(tau)", vars), eulervop::scene::parse_expression("0", vars),
               eulervop::scene::parse_expression("0.02", vars)};
  eulervop::torque_piece piece;
  piece.from = eulervop::constant_expression("7.77");
  piece.to = eulervop::constant_expression("100");
  piece.terms = {eulervop::scene::parse_expression("-0.02", vars),
                 eulervop::scene::parse_expression("0.02*cos(tau)", vars),
                 eulervop::scene::parse_expression("0", vars)};
  law->pieces.push_back(piece);
  return law;
}


// ---- Helpers ----

template <class T, class Torque>
eulervop::euler_problem<T, Torque> problem(const Torque& g, const vec3<T>& Omega0) {
  eulervop::euler_problem<T, Torque> p;
  p.torque = g;
  p.Omega0 = Omega0;
  p.tau0 = T(0);
  return p;
}

inline const vec3<double> paper_Omega0 = {0.5, 0, 1};
inline const vec3<quad> paper_Omega0_q = {quad("0.5"), quad(0), quad(1)};

inline double paper_h() { return eulervop::elliptic_modulus<double>(0.5).K() / 200; }

// The largest Eq. 20 error of a run's samples (at tau0 + n h) against the reference; every sample
// finite.
inline double max_error(const eulervop::run_result& r, const eulervop::dense_trajectory<quad>& ref, double h) {
  double worst = 0;
  for (std::size_t i = 0; i < r.Omega.size(); ++i) {
    for (double v : r.Omega[i]) EXPECT_TRUE(std::isfinite(v));
    const double tau = h * static_cast<double>(r.sample_steps[i]);  // the run's own grid time
    worst = std::max(worst, static_cast<double>(eulervop::eq20_error(ref(quad(tau)), r.Omega[i])));
  }
  return worst;
}

// The largest Eq. 20 error of an adaptive run's samples (at their recorded times).
inline double max_error_at_taus(const eulervop::run_result& r, const eulervop::dense_trajectory<quad>& ref) {
  double worst = 0;
  for (std::size_t i = 0; i < r.Omega.size(); ++i) {
    for (double v : r.Omega[i]) EXPECT_TRUE(std::isfinite(v));
    const quad tau = quad(r.sample_tau[i]) + quad(r.sample_tau_lo[i]);  // the compensated time
    worst = std::max(worst, static_cast<double>(eulervop::eq20_error(ref(tau), r.Omega[i])));
  }
  return worst;
}

// Random states in both regimes (vop_test::random_regime_states, as in tests/test_vop_theta.cpp).
inline std::vector<vec3<quad>> random_states(int n, bool minor) {
  return vop_test::random_regime_states(n, minor, minor ? 4242 : 2424, 3.0);
}
using vop_test::chain_rule_mismatch;

}  // namespace vop_varying
