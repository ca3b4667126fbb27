// The euler formulation of the comparison runs (comparison_run.hpp): the problem's own equations
// (Eq. 5, or Eq. 1 in the direct form) stepped by the Runge-Kutta drivers, at a fixed step
// (rk/fixed_step.hpp) or under error control with Hairer's norm of the Omega estimate
// (rk/adaptive_driver.hpp).
//
// With an attitude (settings.hpp), the state is (y, q), seven components (detail/attitude.hpp):
// the fixed-step driver steps it as it is; under error control a copy of the adaptive driver
// measures the error on y alone, so the rates' steps are those of the run without q.
//
// Breakpoints of the torque (docs/design.md, "Breakpoints"): an adaptive run steps onto each, a
// fixed-step run does the step that crosses one as two steps, to the breakpoint and on to the
// grid point t0 + n h, so its samples stay on the grid. No step evaluates a torque formula on
// the far side of a breakpoint.
#pragma once

#include <eulervop/core/outcome.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/rk/adaptive_driver.hpp>
#include <eulervop/rk/fixed_step.hpp>
#include <eulervop/rk/problem_system.hpp>
#include <eulervop/runs/detail/attitude.hpp>
#include <eulervop/runs/detail/run_torque.hpp>
#include <eulervop/runs/detail/sample_thinner.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace eulervop::detail {

// n_steps fixed steps of h from t0 on the grid t0 + n h, across the torque's breakpoints
// `breaks` (inside the span, increasing): whole grid steps up to the one that crosses a
// breakpoint, which is done as a step to each breakpoint inside it and one on to the grid point.
// The observer sees grid points only, with their grid index; the sub-steps count in rhs_evals.
// State: vec3<double>, or attitude_state with the attitude.
template <class System, class State, class Observer>
rk::fixed_step_result<double> fixed_steps_across(rk::method m, System& sys, State& x, double t0, double h,
                                                 std::size_t n_steps, const std::vector<double>& breaks,
                                                 Observer& observer, const rk::fixed_step_options<double>& o) {
  rk::fixed_step_result<double> total;
  const auto grid = [&](std::size_t n) { return t0 + h * static_cast<double>(n); };
  std::size_t done = 0, next = 0;
  observer(std::size_t{0}, t0, static_cast<const State&>(x));
  // Steps from (t, x): `count` of length `step`. False when the run stopped.
  const auto steps = [&](double t, double step, std::size_t count, std::size_t index0) {
    pin_torque_at(sys.problem, t);
    const auto r = rk::integrate_fixed(
        m, sys, x, t, step, count,
        [&](std::size_t k, double tk, const State& y) {
          if (k > 0 && index0 != SIZE_MAX) observer(index0 + k, tk, y);
        },
        o);
    total.rhs_evals += r.rhs_evals;
    if (index0 != SIZE_MAX) done = index0 + r.steps;
    if (r.stop == outcome_kind::success) return true;
    total.stop = r.stop;
    total.failed_at = r.failed_at;
    return false;
  };
  while (done < n_steps) {
    while (next < breaks.size() && !(breaks[next] > grid(done))) ++next;  // on the grid: nothing to split
    // The grid step that crosses the next breakpoint: the largest n with grid(n) < b.
    std::size_t cross = n_steps;
    if (next < breaks.size()) {
      cross = static_cast<std::size_t>(std::max(0.0, std::floor((breaks[next] - t0) / h)));
      while (cross > done && !(grid(cross) < breaks[next])) --cross;
      while (cross + 1 < n_steps && grid(cross + 1) < breaks[next]) ++cross;
      cross = std::min(cross, n_steps);
    }
    if (cross > done && !steps(grid(done), h, cross - done, done)) break;
    if (cross >= n_steps) break;
    // The crossing step, through every breakpoint inside it, then on to the grid point.
    double t = grid(cross);
    const double t_end = grid(cross + 1);
    bool stopped = false;
    for (; next < breaks.size() && breaks[next] < t_end && !stopped; ++next) {
      stopped = !steps(t, breaks[next] - t, 1, SIZE_MAX);
      t = breaks[next];
    }
    if (stopped || !steps(t, t_end - t, 1, SIZE_MAX)) break;
    done = cross + 1;
    observer(done, t_end, static_cast<const State&>(x));
  }
  total.steps = done;
  total.t = grid(done);
  return total;
}

// Euler at a fixed step; with Attitude, on (y, q) (s.attitude must hold it).
template <class Problem, bool Attitude = false>
void run_euler_fixed(run_result& out, const Problem& p, const fixed_run_settings& s, double bound) {
  using S = std::conditional_t<Attitude, attitude_state, vec3<double>>;
  const std::size_t expected = s.n_steps / std::max<std::size_t>(s.sample_every, 1) + 2;
  out.sample_steps.reserve(expected);
  out.Omega.reserve(expected);
  if constexpr (Attitude) out.q.reserve(expected);
  // The observer runs after every step and must stay inline (an out-of-line call spills every
  // register the step keeps): a countdown instead of step % sample_every, and the recording of a
  // sample out of line. The sample is taken by value: were the state's own address passed on,
  // the state would live in memory throughout the loop.
  const std::size_t every = std::max<std::size_t>(s.sample_every, 1);
  std::size_t until_sample = 0;
  const auto record = [&](std::size_t step, S y) [[gnu::noinline]] {
    out.sample_steps.push_back(step);
    if constexpr (Attitude) {
      out.Omega.push_back(head(y));
      out.q.push_back(quat(y));
    } else {
      out.Omega.push_back(y);
    }
    until_sample = every;
  };
  auto observer = [&](std::size_t step, double, const S& y) {
    if (until_sample == 0 || step == s.n_steps) [[unlikely]]
      record(step, y);
    --until_sample;
  };
  rk::fixed_step_options<double> options;
  options.max_norm = bound;
  auto sys = [&] {
    if constexpr (Attitude) return direct_attitude_system<Problem>{p, s.attitude->rates};
    else return rk::problem_system<Problem>{p};
  }();
  S x = [&] {
    if constexpr (Attitude) return join(p.initial_state(), s.attitude->q0);
    else return p.initial_state();
  }();
  const double t0 = p.initial_time();
  const std::vector<double> breaks = breakpoints_between(p, t0, t0 + s.h * static_cast<double>(s.n_steps));
  const auto start = std::chrono::steady_clock::now();
  const auto r = breaks.empty() ? rk::integrate_fixed(out.method, sys, x, t0, s.h, s.n_steps, observer, options)
                                : fixed_steps_across(out.method, sys, x, t0, s.h, s.n_steps, breaks, observer, options);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.steps = r.steps;
  out.rhs_evals = r.rhs_evals;
  if (r.diverged()) out.status = {r.stop, r.failed_at};
}

inline rk::adaptive_options<double> euler_adaptive_options(const adaptive_run_settings& s, double bound) {
  rk::adaptive_options<double> o;
  o.atol = s.atol;
  o.rtol = s.rtol;
  if (s.h_max > 0) o.h_max = s.h_max;  // 0: no limit but the span, as in the VOP runs
  o.max_norm = bound;
  return o;
}

// Euler under error control, stepping onto every breakpoint: the span is integrated interval by
// interval, each from its start with the controller's starting step (a formula that changes
// there changes the solution's smoothness too). With Attitude, on (y, q) with the error of y
// alone (detail/attitude.hpp; s.attitude must hold it).
template <class Pair, class Problem, bool Attitude = false>
void run_euler_adaptive(run_result& out, const Problem& p, const adaptive_run_settings& s, double bound) {
  using V = std::conditional_t<Attitude, attitude_state, vec3<double>>;
  const auto sys = [&] {
    if constexpr (Attitude) return direct_attitude_system<Problem>{p, s.attitude->rates};
    else return rk::problem_system<Problem>{p};
  }();
  sample_thinner samples(out, s.samples);
  std::size_t last_step = 0, offset = 0;
  double last_tau = p.initial_time(), last_lo = 0;
  const auto start_state = [&] {
    if constexpr (Attitude) return join(p.initial_state(), s.attitude->q0);
    else return p.initial_state();
  };
  V last_x = start_state();
  const auto put = [&](std::size_t step, double tau, double lo, const V& x) {
    if constexpr (Attitude) samples.put(step, tau, lo, head(x), quat(x));
    else samples.put(step, tau, lo, x);
  };
  auto observer = [&](std::size_t k, double tau, double lo, const V& x) {
    if (k == 0 && offset > 0) return;  // an interval's start: the previous one's end
    const std::size_t step = offset + k;
    if (samples.wants(step)) [[unlikely]]
      put(step, tau, lo, x);
    last_step = step;
    last_tau = tau;
    last_lo = lo;
    last_x = x;
  };
  const rk::adaptive_options<double> o = euler_adaptive_options(s, bound);
  V x = start_state();
  std::vector<double> ends = breakpoints_between(p, p.initial_time(), s.tau_end);
  ends.push_back(s.tau_end);
  const auto start = std::chrono::steady_clock::now();
  double t = p.initial_time();
  rk::adaptive_result<double> total;
  for (const double end : ends) {
    pin_torque_at(sys.problem, t);
    const auto r = [&] {
      if constexpr (Attitude) return integrate_adaptive_attitude<Pair>(sys, x, t, end, o, observer);
      else return rk::integrate_adaptive<Pair>(sys, x, t, end, o, observer);
    }();
    offset += r.accepted;
    total.accepted += r.accepted;
    total.rejected += r.rejected;
    total.rhs_evals += r.rhs_evals;
    total.stop = r.stop;
    total.failed_at = r.failed_at;
    if (r.stop != outcome_kind::success) break;
    t = end;
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (samples.lacks_last(last_step)) put(last_step, last_tau, last_lo, last_x);
  out.steps = total.accepted;
  out.rejected = total.rejected;
  out.rhs_evals = total.rhs_evals;
  if (total.stop != outcome_kind::success) out.status = {total.stop, total.failed_at ? *total.failed_at : last_tau};
}

}  // namespace eulervop::detail
