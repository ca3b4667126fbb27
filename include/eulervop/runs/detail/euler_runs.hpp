// The euler formulation of the comparison runs (comparison_run.hpp): the problem's own equations
// (Eq. 5, or Eq. 1 in the direct form) stepped by the Runge-Kutta drivers, at a fixed step
// (rk/fixed_step.hpp) or under error control with Hairer's norm of the Omega estimate
// (rk/adaptive_driver.hpp).
#pragma once

#include <eulervop/core/outcome.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/rk/adaptive_driver.hpp>
#include <eulervop/rk/fixed_step.hpp>
#include <eulervop/rk/problem_system.hpp>
#include <eulervop/runs/detail/sample_thinner.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <algorithm>
#include <chrono>
#include <cstddef>

namespace eulervop::detail {

// Euler at a fixed step.
template <class Problem>
void run_euler_fixed(run_result& out, const Problem& p, const fixed_run_settings& s, double bound) {
  const std::size_t expected = s.n_steps / std::max<std::size_t>(s.sample_every, 1) + 2;
  out.sample_steps.reserve(expected);
  out.Omega.reserve(expected);
  // The observer runs after every step and must stay inline (an out-of-line call spills every
  // register the step keeps): a countdown instead of step % sample_every, and the recording of a
  // sample out of line. The sample is taken by value: were the state's own address passed on,
  // the state would live in memory throughout the loop.
  const std::size_t every = std::max<std::size_t>(s.sample_every, 1);
  std::size_t until_sample = 0;
  const auto record = [&](std::size_t step, vec3<double> y) [[gnu::noinline]] {
    out.sample_steps.push_back(step);
    out.Omega.push_back(y);
    until_sample = every;
  };
  auto observer = [&](std::size_t step, double, const vec3<double>& y) {
    if (until_sample == 0 || step == s.n_steps) [[unlikely]]
      record(step, y);
    --until_sample;
  };
  rk::fixed_step_options<double> options;
  options.max_norm = bound;
  rk::problem_system<Problem> sys{p};
  vec3<double> x = p.initial_state();
  const auto start = std::chrono::steady_clock::now();
  const auto r = rk::integrate_fixed(out.method, sys, x, p.initial_time(), s.h, s.n_steps, observer, options);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.steps = r.steps;
  out.rhs_evals = r.rhs_evals;
  if (r.diverged()) out.status = {r.stop, r.failed_at};
}

// Euler under error control.
template <class Pair, class Problem>
void run_euler_adaptive(run_result& out, const Problem& p, const adaptive_run_settings& s, double bound) {
  using V = vec3<double>;
  const rk::problem_system<Problem> sys{p};
  sample_thinner samples(out, s.samples);
  std::size_t last_step = 0;
  double last_tau = p.initial_time(), last_lo = 0;
  V last_x = p.initial_state();
  auto observer = [&](std::size_t step, double tau, double lo, const V& x) {
    if (samples.wants(step)) [[unlikely]]
      samples.put(step, tau, lo, x);
    last_step = step;
    last_tau = tau;
    last_lo = lo;
    last_x = x;
  };
  rk::adaptive_options<double> o;
  o.atol = s.atol;
  o.rtol = s.rtol;
  o.h_max = s.h_max;
  o.max_norm = bound;
  V x = p.initial_state();
  const auto start = std::chrono::steady_clock::now();
  const auto r = rk::integrate_adaptive<Pair>(sys, x, p.initial_time(), s.tau_end, o, observer);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (samples.lacks_last(last_step)) samples.put(last_step, last_tau, last_lo, last_x);
  out.steps = r.accepted;
  out.rejected = r.rejected;
  out.rhs_evals = r.rhs_evals;
  if (r.stop != outcome_kind::success) out.status = {r.stop, r.failed_at ? *r.failed_at : last_tau};
}

}  // namespace eulervop::detail
