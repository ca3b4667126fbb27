// The VOP formulations of the comparison runs (comparison_run.hpp) at a fixed step.
//
// Breakpoints of a piecewise torque (model/torque.hpp), as in the euler formulation
// (euler_runs.hpp): the grid step that crosses one is done as sub-steps, to each breakpoint inside
// it and on to the grid point t0 + n h, so the samples stay on the grid. Every sub-step is an
// accepted step of the current representation (band entry and exit, phase reduction); the
// observer sees grid points only, and the sub-steps count in rhs_evals. The run's own copies of
// the torque (the element system's and the direct system's) are pinned to the interval of each
// step's start, so no stage evaluates a formula of the far side of a breakpoint (a step ending on
// one sees the formulas of its own side there).
//
// With Attitude, the stepped state is (elements or Omega, q) (detail/attitude.hpp): q rides on the
// same stages, driven by the stage's rates, and keeps its value and compensation when the
// representation changes.
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/model/torque.hpp>
#include <eulervop/rk/explicit_rk.hpp>
#include <eulervop/rk/problem_system.hpp>
#include <eulervop/runs/detail/attitude.hpp>
#include <eulervop/runs/detail/divergence.hpp>
#include <eulervop/runs/detail/run_torque.hpp>
#include <eulervop/runs/detail/vop_run_state.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace eulervop::detail {

// The VOP formulations at a fixed step: vop_run_state's representations stepped with one
// explicit_rk stepper (the same tableau and compensated summation as rk::integrate_fixed), so
// the method and step never change (a step across a breakpoint is split, see the header note).
template <class Tableau, bool Theta, class Problem, bool Attitude = false>
class vop_fixed_run {
 public:
  using V = vec3<double>;
  using S = std::conditional_t<Attitude, attitude_state, V>;  // the stepped state
  using Torque = typename Problem::torque_type;
  // Breakpoints matter only to a torque that varies (a constant one has none to honour).
  static constexpr bool piecewise = piecewise_torque<Torque> && !is_constant_torque_v<Torque>;

  vop_fixed_run(run_result& out, const Problem& p, const fixed_run_settings& s, double bound)
      : out_(out), s_(s), tau0_(p.initial_time()), bound_(bound), every_(std::max<std::size_t>(s.sample_every, 1)),
        run_(out, p.initial_state(), p.initial_time(), p.torque, s.bands, first_), euler_{direct_system(p, s)} {
    if constexpr (piecewise) {
      breaks_ = breakpoints_between(p, tau0_, tau0_ + s.h * static_cast<double>(s.n_steps));
      pin_at(tau0_);
    }
  }

  void operator()() {
    out_.sample_steps.reserve(s_.n_steps / every_ + 2);
    out_.Omega.reserve(s_.n_steps / every_ + 2);
    if constexpr (Attitude) out_.q.reserve(s_.n_steps / every_ + 2);
    S state = first_state(), comp{};
    sample(0, state);
    const auto start = std::chrono::steady_clock::now();
    // The loop reads its constants from locals, not through `this` (which it would reload).
    const double tau0 = tau0_, h = s_.h, bound = bound_;
    const std::size_t n_steps = s_.n_steps, every = every_;
    double t = tau0;
    std::size_t n = 0;
    S next{}, comp_next{};
    while (n < n_steps) {
      const double t_next = tau0 + h * static_cast<double>(n + 1);
      if constexpr (piecewise) {
        // A breakpoint inside the step or at its end: sub-steps, pinned per sub-step.
        if (next_break_ < breaks_.size() && !(breaks_[next_break_] > t_next)) [[unlikely]] {
          if (!steps_across(state, comp, t, t_next)) break;
          ++n;
          t = t_next;
          if (n % every == 0 || n == n_steps) sample(n, state);
          continue;
        }
      }
      comp_next = comp;
      if (!step(state, t, h, next, comp_next)) [[unlikely]] {
        leave_elements(t, state, comp);
        continue;
      }
      if (!finite_within(next, bound)) [[unlikely]] {
        out_.status = {divergence_kind(next), t_next};
        break;
      }
      state = next;
      comp = comp_next;
      ++n;
      t = t_next;
      after_step(t, state, comp);
      if (n % every == 0 || n == n_steps) [[unlikely]]
        sample(n, state);
    }
    out_.steps = n;
    out_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out_.rhs_evals = stepper_.rhs_evaluations();
    run_.finish(t);
  }

 private:
  // One step of h of the current representation from (t, state). False when an element step left
  // the elements' domain: the caller redoes it with Eq. 5.
  bool step(const S& state, double t, double h, S& next, S& comp_next) {
    if (run_.in_elements()) {
      if constexpr (Attitude) {
        element_attitude_system<vop_run_state<Theta, Torque>> sys{run_, euler_.rates};
        stepper_.do_step(sys, state, t, h, next, comp_next);
        return run_.element_step_in_domain(head(next));
      } else {
        stepper_.do_step(run_.system(), state, t, h, next, comp_next);
        return run_.element_step_in_domain(next);
      }
    }
    stepper_.do_step(euler_, state, t, h, next, comp_next);
    return true;
  }
  void sample(std::size_t n, S state) {
    out_.sample_steps.push_back(n);
    if constexpr (Attitude) {
      out_.Omega.push_back(run_.Omega(head(state)));
      out_.q.push_back(quat(state));
    } else {
      out_.Omega.push_back(run_.Omega(state));
    }
  }
  // The starting state: the representation vop_run_state chose (and q0).
  S first_state() const {
    if constexpr (Attitude) return join(first_, s_.attitude->q0);
    else return first_;
  }
  // An element step left the elements' domain: the state at t becomes Omega (compensation zero;
  // q and its compensation stay).
  void leave_elements(double t, S& state, S& comp) { leave_elements_of(run_, t, state, comp); }
  // vop_run_state::after_step on the elements or Omega (q unchanged).
  void after_step(double t, S& state, S& comp) {
    if constexpr (Attitude) {
      V y = head(state), c = head(comp);
      run_.after_step(t, y, c);
      set_head(state, y);
      set_head(comp, c);
    } else {
      run_.after_step(t, state, comp);
    }
  }
  static auto direct_system(const Problem& p, const fixed_run_settings& s) {
    if constexpr (Attitude) return direct_attitude_system<Problem>{p, s.attitude->rates};
    else return rk::problem_system<Problem>{p};
  }

  // The grid step from t to the grid point t_end that holds breakpoints (inside it, or at its
  // end): one sub-step to each breakpoint, re-pinning after it, then one on to t_end. False when
  // the run stopped (out_.status set).
  [[gnu::noinline]] bool steps_across(S& state, S& comp, double t, double t_end) {
    while (next_break_ < breaks_.size() && !(breaks_[next_break_] > t_end)) {
      const double b = breaks_[next_break_];
      if (b > t) {  // a repeated breakpoint gives no step
        if (!sub_step(state, comp, t, b)) return false;
        t = b;
      }
      ++next_break_;
      pin_at(b);  // the interval that starts at b
    }
    return !(t_end > t) || sub_step(state, comp, t, t_end);
  }
  // One accepted step from a to b (redone with Eq. 5 if the elements left their domain).
  bool sub_step(S& state, S& comp, double a, double b) {
    S next{}, comp_next{};
    for (;;) {
      comp_next = comp;
      if (step(state, a, b - a, next, comp_next)) break;
      leave_elements(a, state, comp);
    }
    if (!finite_within(next, bound_)) {
      out_.status = {divergence_kind(next), b};
      return false;
    }
    state = next;
    comp = comp_next;
    after_step(b, state, comp);
    return true;
  }
  // Pins the run's own copies of the torque (element and direct systems) to the interval of t.
  void pin_at(double t) {
    if constexpr (piecewise) {
      const auto i = run_.torque().interval_at(t);
      run_.torque().pin(i);
      euler_.problem.torque.pin(i);
    }
  }

  run_result& out_;
  const fixed_run_settings& s_;
  double tau0_, bound_;
  std::size_t every_;  // sample_every, at least 1
  V first_{};          // the starting state, in the representation vop_run_state chose
  vop_run_state<Theta, Torque> run_;
  rk::explicit_rk<Tableau, S> stepper_;
  // Eq. 5 (with q: and the body rates, which the element steps use too)
  std::conditional_t<Attitude, direct_attitude_system<Problem>, rk::problem_system<Problem>> euler_;
  std::vector<double> breaks_;  // the torque's breakpoints inside the span (piecewise only)
  std::size_t next_break_ = 0;  // the first breakpoint after the current time
};

}  // namespace eulervop::detail
