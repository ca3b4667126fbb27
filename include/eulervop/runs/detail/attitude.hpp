// The attitude beside the rates of a comparison run (settings.hpp, attitude_settings;
// docs/attitude-runs.md): the run steps (y, q), seven components, with its own method, step or
// controller, where y is what it steps anyway (Omega of Eq. 5 or omega of Eq. 1, or the VOP
// elements) and
//
//   dq/dtau = 1/2 q (x) (0, W),   W = body_rates(Omega)          (core/quaternion.hpp)
//
// with Omega the rates of the stage: y itself for a direct step, Eq. 12 of the stage's elements
// in the run's frame for an element step (vop_run_state::stage_Omega). q rides on the same
// Runge-Kutta stages and the same compensated sum as y, so it is the augmented system integrated
// by the run's method, and the representation changes of a VOP run (bands, regimes, phase turns)
// leave it alone: it is the same attitude in every representation.
//
// With a torque that reads the attitude (reads_attitude below) each stage shows the torque its
// own q first, and q feeds back into y: the run integrates the coupled problem of 7 states. With
// any other torque q never feeds back into y: every stage of y is formed, evaluated and summed
// exactly as without q (component by component, the same operations), and the error estimate of
// an adaptive step is measured on y alone (attitude_embedded_rk below: the same norm, over the
// same three components, as rk::embedded_rk), as is the starting step. So the rates, their steps,
// their samples and their errors are bit for bit those of the run without the attitude
// (tests/test_report_attitude.cpp checks it).
#pragma once

#include <eulervop/core/outcome.hpp>
#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/body_rates.hpp>
#include <eulervop/rk/adaptive_driver.hpp>
#include <eulervop/rk/embedded_rk.hpp>
#include <eulervop/runs/settings.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <type_traits>

namespace eulervop::detail {

// The stepped state of a run with attitude: y (3), then q = (w, x, y, z).
using attitude_state = std::array<double, 7>;

inline vec3<double> head(const attitude_state& s) { return {s[0], s[1], s[2]}; }
inline void set_head(attitude_state& s, const vec3<double>& y) {
  s[0] = y[0];
  s[1] = y[1];
  s[2] = y[2];
}
inline quaternion<double> quat(const attitude_state& s) { return {s[3], s[4], s[5], s[6]}; }
inline attitude_state join(const vec3<double>& y, const quaternion<double>& q) {
  return {y[0], y[1], y[2], q.w, q.x, q.y, q.z};
}

// dq/dtau = 1/2 q (x) (0, W) into ds[3..6], q from s.
inline void put_attitude_rate(const attitude_state& s, const vec3<double>& W,
                                                     attitude_state& ds) {
  const quaternion<double> d = attitude_rate(quat(s), W);
  ds[3] = d.w;
  ds[4] = d.x;
  ds[5] = d.y;
  ds[6] = d.z;
}

// A VOP run's state, y or (y, q), leaves the elements' domain at t (vop_run_state::leave_elements):
// y becomes Omega with its compensation zero; q and its compensation stay.
template <class Run, class S>
inline void leave_elements_of(Run& run, double t, S& state, S& comp) {
  if constexpr (std::is_same_v<S, attitude_state>) {
    set_head(state, run.leave_elements(t, head(state)));
    set_head(comp, vec3<double>{0, 0, 0});
  } else {
    state = run.leave_elements(t, state);
    comp = S{0, 0, 0};
  }
}

// divergence.hpp's test and cause for the seven components (|q| stays near 1, far below any
// bound, so only a non-finite q adds anything).
inline bool finite_within(const attitude_state& s, double bound) {
  for (double c : s)
    if (!std::isfinite(c) || std::abs(c) > bound) return false;
  return true;
}
inline outcome_kind divergence_kind(const attitude_state& s) {
  double sum = 0;
  for (double c : s) sum += c;
  return std::isfinite(sum) ? outcome_kind::norm_bound : outcome_kind::non_finite;
}

// A torque that reads the attitude (model/staged_attitude_torque.hpp): each stage shows it its q
// before the stage is evaluated, so that q feeds back into the rates.
template <class Torque>
concept reads_attitude = requires(const Torque& g, const quaternion<double>& q) { g.set_attitude(q); };

// The problem's own equations (Eq. 5, or Eq. 1 in the direct form) with q: the euler formulation,
// and the direct stretches of the VOP runs. Holds its own copy of the problem (member `problem`,
// which the runs pin, as rk::problem_system's).
template <class Problem>
struct direct_attitude_system {
  using value_type = double;
  using state_type = attitude_state;

  Problem problem;
  body_rates<double> rates;

  void operator()(const attitude_state& s, attitude_state& ds, const double& t) const {
    if constexpr (reads_attitude<typename Problem::torque_type>) problem.torque.set_attitude(quat(s));
    const vec3<double> y = head(s);
    vec3<double> dy;
    problem.rhs(t, y, dy);
    set_head(ds, dy);
    put_attitude_rate(s, rates(y), ds);
  }

  // The rates alone, as rk::problem_system: what the starting step of an adaptive run measures.
  struct rates_only {
    const Problem& problem;
    void operator()(const vec3<double>& y, vec3<double>& dy, const double& t) const { problem.rhs(t, y, dy); }
  };
  rates_only without_attitude() const { return {problem}; }
};

// The VOP elements with q: `run` is the run's vop_run_state (its element system and the Omega of
// a stage's elements in its frame).
template <class Run>
struct element_attitude_system {
  Run& run;
  const body_rates<double>& rates;

  void operator()(const attitude_state& s, attitude_state& ds, const double& t) {
    if constexpr (requires { run.torque().set_attitude(quat(s)); }) run.torque().set_attitude(quat(s));
    const vec3<double> y = head(s);
    vec3<double> dy;
    run.system()(y, dy, t);
    set_head(ds, dy);
    put_attitude_rate(s, rates(run.stage_Omega(y)), ds);
  }
};

// What an adaptive step with q measures (rk::embedded_rk's Measure): y alone, and the starting
// step on the rates' own system, so that the error, the starting step and hence every step are
// exactly those of rk::embedded_rk<Pair, vec3<double>> for the run without q.
struct rates_part {
  static vec3<double> part(const attitude_state& s) { return head(s); }
  template <class System>
  static auto system(System& sys) {
    return sys.without_attitude();
  }
};

template <class Pair>
using attitude_embedded_rk = rk::embedded_rk<Pair, attitude_state, double, rates_part>;

// rk::integrate_adaptive for the euler formulation with q (direct_attitude_system): the same
// driver (rk/adaptive_driver.hpp) with attitude_embedded_rk, so that the error, the starting step
// and hence every step are those of y alone. observer(step, t, t_lo, state) returns nothing.
template <class Pair, class System, class Observer>
rk::adaptive_result<double> integrate_adaptive_attitude(System& sys, attitude_state& x, double t0, double t_end,
                                                        const rk::adaptive_options<double>& o, Observer& observer) {
  rk::detail::adaptive_driver<Pair, System, attitude_state, double, Observer, rk::hairer_scale<double>,
                              attitude_embedded_rk<Pair>>
      driver(sys, x, t0, t_end, o, observer, rk::hairer_scale<double>{o.atol, o.rtol});
  return driver.run(x);
}

}  // namespace eulervop::detail
