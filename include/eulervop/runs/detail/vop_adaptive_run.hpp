// The VOP formulations of the comparison runs (comparison_run.hpp) under error control, with the
// embedded pairs of rk/embedded_pairs.hpp (rkf45, dp45, dop853) and the PI controller.
//
// Error measure of the element steps: the elements' estimate in scaled elements: (dc1, dc2, c1 du)
// over (atol + rtol c1, atol + rtol c2, atol + rtol c1), c1 and c2 at their larger value before
// and after the step. c1 du bounds the displacement of Omega that a phase error du causes:
// |dOmega/du| = c1 sqrt(1 - k^2 sn^4) lies in [c1 kc, c1] (Eq. 12). So the three components are
// in units of Omega, relative to the size of the components they move (Omega1, Omega2 ~ c1,
// Omega3 ~ c2), as Hairer's scale is for Eq. 5. For theta, du = dtheta 2K / pi. The direct
// stretches use Hairer's norm of the Omega estimate, as the euler formulation does.
// Without torque every VOP stage agrees, the estimate is exactly zero, and the run takes its
// maximum step everywhere, exactly as the fixed-step runs stay exact to rounding.
//
// Breakpoints of a piecewise torque (model/torque.hpp), as in the euler formulation
// (euler_runs.hpp): the run integrates interval by interval, stepping exactly onto each breakpoint
// (the step that would pass it is shortened to end there), and restarts there: the run's own
// copies of the torque (the element system's and the direct system's) pinned to the interval
// that starts at the breakpoint, the derivative re-evaluated, the controller reset and the step
// estimated afresh (a formula that changes there changes the solution's smoothness too).
//
// With Attitude, the stepped state is (elements or Omega, q) (detail/attitude.hpp): q rides on the
// same stages and keeps its value and compensation when the representation changes; the error
// estimate and the starting step measure the elements or Omega alone, as above, so the steps are
// those of the run without q.
#pragma once

#include <eulervop/core/outcome.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/torque.hpp>
#include <eulervop/rk/detail/compensated_sum.hpp>
#include <eulervop/rk/embedded_rk.hpp>
#include <eulervop/rk/error_norm.hpp>
#include <eulervop/rk/initial_step.hpp>
#include <eulervop/rk/pi_controller.hpp>
#include <eulervop/rk/problem_system.hpp>
#include <eulervop/runs/detail/attitude.hpp>
#include <eulervop/runs/detail/divergence.hpp>
#include <eulervop/runs/detail/run_torque.hpp>
#include <eulervop/runs/detail/sample_thinner.hpp>
#include <eulervop/runs/detail/vop_run_state.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>
#include <vector>

namespace eulervop::detail {

// The error scale of the element steps: the scaled elements of the header note.
template <bool Theta, class Torque>
struct element_scale {
  using V = vec3<double>;
  double atol, rtol;
  const vop_run_state<Theta, Torque>* run;
  void operator()(const V& y0, const V& y1, V& sc) const {
    const double c1 = std::max(std::abs(y0[0]), std::abs(y1[0]));
    sc[0] = atol + rtol * c1;
    sc[1] = atol + rtol * std::max(std::abs(y0[1]), std::abs(y1[1]));
    const double w = run->phase_weight(c1);
    sc[2] = w > 0 ? sc[0] / w : std::numeric_limits<double>::infinity();
  }
};

// The VOP formulations under error control: vop_run_state's representations stepped with one
// embedded pair, whose PI controller carries over between them (the derivative is re-evaluated
// after a change; it restarts at a breakpoint, see the header note).
template <class Pair, bool Theta, class Problem, bool Attitude = false>
class vop_adaptive_run {
 public:
  using V = vec3<double>;
  using S = std::conditional_t<Attitude, attitude_state, V>;  // the stepped state
  using Torque = typename Problem::torque_type;
  // Breakpoints matter only to a torque that varies (a constant one has none to honour).
  static constexpr bool piecewise = piecewise_torque<Torque> && !is_constant_torque_v<Torque>;

  vop_adaptive_run(run_result& out, const Problem& p, const adaptive_run_settings& s, double bound)
      : out_(out), s_(s), tau0_(p.initial_time()), bound_(bound), span_(s.tau_end - p.initial_time()),
        h_max_(s.h_max > 0 ? std::min(s.h_max, span_) : span_),
        run_(out, p.initial_state(), p.initial_time(), p.torque, s.bands, first_), euler_{direct_system(p, s)},
        omega_scale_{s.atol, s.rtol}, element_scale_{s.atol, s.rtol, &run_}, samples_(out, s.samples) {
    if constexpr (piecewise) {
      breaks_ = breakpoints_between(p, tau0_, s.tau_end);
      pin_at(tau0_);
    }
  }

  void operator()() {
    S state = first_state(), comp{};
    step_clock at{tau0_, 0, 0};
    sample(at, state);
    const auto start = std::chrono::steady_clock::now();
    prime(state, at.t);
    double h = first_step(state, at.t);
    // The end of the current interval: the next breakpoint, or tau_end.
    double end = s_.tau_end;
    if constexpr (piecewise)
      if (!breaks_.empty()) end = breaks_[0];
    while (span_ > 0) {
      const double left = (end - at.t) - at.t_lo;
      if (!(left > 0)) break;
      const bool last = h >= left;
      const attempt_result r = advance(state, comp, at, h, last ? left : h, last, end);
      if (r == attempt_result::stopped) break;
      if (r == attempt_result::accepted && last) {
        if constexpr (piecewise) {
          if (next_break_ < breaks_.size()) {  // on a breakpoint: restart in the next interval
            while (next_break_ < breaks_.size() && !(breaks_[next_break_] > at.t)) ++next_break_;
            end = next_break_ < breaks_.size() ? breaks_[next_break_] : s_.tau_end;
            restart(state, at.t, h);
            continue;
          }
        }
        break;
      }
    }
    out_.steps = at.n;
    out_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (samples_.lacks_last(at.n)) sample(at, state);
    out_.rhs_evals = stepper_.rhs_evaluations() + extra_evals_;
    run_.finish(at.t);
  }

 private:
  // The time reached, t + t_lo, after n accepted steps. Apart from the state and its
  // compensation (elements or Omega), whose addresses the stepper takes: kept together, all
  // five would live in memory.
  struct step_clock {
    double t, t_lo;
    std::size_t n;
  };
  enum class attempt_result { accepted, retry, stopped };

  // One attempt of a step of h_try (the last one if `last`): accepted (state and clock advanced,
  // h the next step), retry (h shorter, or the representation changed) or stopped (out_.status).
  // `end` is the end of the current interval (tau_end, or a breakpoint), which a last step reaches
  // exactly.
  attempt_result advance(S& state, S& comp, step_clock& at, double& h, double h_try,
                                                bool last, double end) {
    if (!(h_try > 16 * std::numeric_limits<double>::epsilon() * std::abs(at.t)) || !std::isfinite(h_try)) {
      out_.status = {std::isfinite(h_try) ? outcome_kind::step_underflow : outcome_kind::non_finite, at.t};
      return attempt_result::stopped;
    }
    S next{}, comp_next = comp;
    double err = 0;
    if (!attempt(state, comp, at.t, h_try, next, comp_next, err)) [[unlikely]] {
      leave_elements(state, comp, at.t);
      return attempt_result::retry;
    }
    const bool finite = std::isfinite(next[0] + next[1] + next[2]);
    if (!(err <= 1) || !finite) [[unlikely]] {
      ++out_.rejected;
      h = h_try * controller_.rejected(finite ? err : std::numeric_limits<double>::infinity());
      return attempt_result::retry;
    }
    if (!finite_within(next, bound_)) [[unlikely]] {
      out_.status = {divergence_kind(next), at.t + h_try};
      return attempt_result::stopped;
    }
    state = next;
    comp = comp_next;
    if (last) {
      at.t = end;
      at.t_lo = 0;
    } else {
      rk::detail::advance_time(at.t, at.t_lo, h_try);
    }
    ++at.n;
    h = std::min(h_try * controller_.accepted(err), h_max_);
    accept(state, comp, at);
    return attempt_result::accepted;
  }

  // The embedded step of h of the current representation from (t, state) (error norm in err).
  // False when an element step left the elements' domain.
  bool attempt(const S& state, const S& comp, double t, double h, S& next, S& comp_next,
                                      double& err) {
    if (run_.in_elements()) {
      if constexpr (Attitude) {
        auto sys = elements();
        err = stepper_.attempt(sys, state, t, h, next, comp, comp_next, element_scale_);
        return run_.element_step_in_domain(head(next));
      } else {
        err = stepper_.attempt(run_.system(), state, t, h, next, comp, comp_next, element_scale_);
        return run_.element_step_in_domain(next);
      }
    }
    err = stepper_.attempt(euler_, state, t, h, next, comp, comp_next, omega_scale_);
    return true;
  }
  // After an accepted step: band entry or exit (a new representation is primed afresh), the
  // derivative at the new state (FSAL), the sample.
  void accept(S& state, S& comp, const step_clock& at) {
    const bool was_elements = run_.in_elements();
    if (after_step(at.t, state, comp)) [[unlikely]] {
      controller_.reset();
      prime(state, at.t);
    } else if (was_elements) {
      if constexpr (Attitude) {
        auto sys = elements();
        stepper_.accept(sys, state, at.t);
      } else {
        stepper_.accept(run_.system(), state, at.t);
      }
    } else {
      stepper_.accept(euler_, state, at.t);
    }
    if (samples_.wants(at.n)) [[unlikely]]
      sample(at, state);
  }
  // A stage left the elements' domain: the step is redone directly from its start (t, state).
  // With q: q and its compensation stay.
  void leave_elements(S& state, S& comp, double t) {
    leave_elements_of(run_, t, state, comp);
    controller_.reset();
    prime(state, t);
  }
  // vop_run_state::after_step on the elements or Omega (q unchanged).
  bool after_step(double t, S& state, S& comp) {
    if constexpr (Attitude) {
      V y = head(state), c = head(comp);
      const bool changed = run_.after_step(t, y, c);
      set_head(state, y);
      set_head(comp, c);
      return changed;
    } else {
      return run_.after_step(t, state, comp);
    }
  }
  void sample(const step_clock& at, const S& state) {
    if constexpr (Attitude) samples_.put(at.n, at.t, at.t_lo, run_.Omega(head(state)), quat(state));
    else samples_.put(at.n, at.t, at.t_lo, run_.Omega(state));
  }
  // The starting state: the representation vop_run_state chose (and q0).
  S first_state() const {
    if constexpr (Attitude) return join(first_, s_.attitude->q0);
    else return first_;
  }
  // The element system with q (attitude runs).
  element_attitude_system<vop_run_state<Theta, Torque>> elements()
    requires Attitude
  {
    return {run_, euler_.rates};
  }
  static auto direct_system(const Problem& p, const adaptive_run_settings& s) {
    if constexpr (Attitude) return direct_attitude_system<Problem>{p, s.attitude->rates};
    else return rk::problem_system<Problem>{p};
  }
  // On the breakpoint t: the next interval's formulas, the derivative, controller and step afresh.
  [[gnu::noinline]] void restart(const S& state, double t, double& h) {
    pin_at(t);
    controller_.reset();
    prime(state, t);
    h = first_step(state, t);
  }
  // Pins the run's own copies of the torque (element and direct systems) to the interval of t.
  void pin_at(double t) {
    if constexpr (piecewise) {
      const auto i = run_.torque().interval_at(t);
      run_.torque().pin(i);
      euler_.problem.torque.pin(i);
    }
  }
  void prime(const S& state, double t) {
    if constexpr (Attitude) {
      if (run_.in_elements()) {
        auto sys = elements();
        stepper_.prime(sys, state, t);
      } else {
        stepper_.prime(euler_, state, t);
      }
    } else {
      if (run_.in_elements()) stepper_.prime(run_.system(), state, t);
      else stepper_.prime(euler_, state, t);
    }
  }
  // HNW's starting step; with q, that of the elements or Omega alone (q does not choose steps).
  double first_step(const S& state, double t) {
    if constexpr (Attitude) {
      const V y = head(state), dy = head(stepper_.derivative());
      if (run_.in_elements())
        return rk::initial_step<Pair>(run_.system(), y, t, dy, h_max_, element_scale_, extra_evals_);
      auto rates = euler_.without_attitude();
      return rk::initial_step<Pair>(rates, y, t, dy, h_max_, omega_scale_, extra_evals_);
    } else {
      if (run_.in_elements())
        return rk::initial_step<Pair>(run_.system(), state, t, stepper_.derivative(), h_max_, element_scale_,
                                      extra_evals_);
      return rk::initial_step<Pair>(euler_, state, t, stepper_.derivative(), h_max_, omega_scale_, extra_evals_);
    }
  }

  run_result& out_;
  const adaptive_run_settings& s_;
  double tau0_, bound_;
  double span_, h_max_;  // tau_end - tau0; the largest step
  V first_{};            // the starting state, in the representation vop_run_state chose
  vop_run_state<Theta, Torque> run_;
  std::conditional_t<Attitude, attitude_embedded_rk<Pair>, rk::embedded_rk<Pair, V>> stepper_;
  rk::pi_controller controller_{Pair::estimate_order + 1};
  // Eq. 5 (with q: and the body rates, which the element steps use too)
  std::conditional_t<Attitude, direct_attitude_system<Problem>, rk::problem_system<Problem>> euler_;
  rk::hairer_scale<double> omega_scale_;
  element_scale<Theta, Torque> element_scale_;
  sample_thinner samples_;
  std::size_t extra_evals_ = 0;  // those of the starting-step estimates
  std::vector<double> breaks_;   // the torque's breakpoints inside the span (piecewise only)
  std::size_t next_break_ = 0;   // the breakpoint that ends the current interval
};

}  // namespace eulervop::detail
