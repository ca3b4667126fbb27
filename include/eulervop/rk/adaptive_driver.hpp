// The adaptive driver: integrates to an end time with one embedded pair (embedded_pairs.hpp)
// under error control, in the manner of Boost.Odeint's controlled steppers.
//
//   rk::adaptive_options<double> o{.atol = 1e-10, .rtol = 1e-10};
//   auto r = rk::integrate_adaptive<rk::dop853_pair>(sys, x, 0.0, 100.0, o);   // x <- x(100)
//   // r.accepted, r.rejected, r.rhs_evals, r.stop
//
// Each attempt is one step of the embedded stepper (embedded_rk.hpp), measured by the error norm
// (error_norm.hpp, Hairer's scale unless the caller passes its own); the PI controller
// (pi_controller.hpp) sizes the next step or the retry, and the run starts with HNW's starting
// step (initial_step.hpp). The time is kept as an unevaluated sum t_hi + t_lo
// (detail/compensated_sum.hpp); the last step ends at t_end exactly.
#pragma once

#include <eulervop/core/outcome.hpp>
#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/rk/detail/compensated_sum.hpp>
#include <eulervop/rk/embedded_rk.hpp>
#include <eulervop/rk/error_norm.hpp>
#include <eulervop/rk/initial_step.hpp>
#include <eulervop/rk/pi_controller.hpp>
#include <eulervop/rk/state_traits.hpp>

#include <cstddef>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>

namespace eulervop::rk {

template <scalar T>
struct adaptive_options {
  T atol{};
  T rtol{};
  std::optional<T> h_max;         // default: the whole span
  std::optional<T> h_init;        // default: HNW's starting step
  std::optional<T> max_norm;      // divergence when the max-norm exceeds this
  std::size_t max_steps = 0;      // 0: no limit; otherwise stop (outcome_kind::step_limit)
};

template <scalar T>
struct adaptive_result {
  std::size_t accepted = 0;
  std::size_t rejected = 0;
  std::size_t rhs_evals = 0;
  // success (t_end reached), non_finite (the state or the step size became non-finite),
  // norm_bound (an accepted state beyond options.max_norm), step_underflow (the step fell below
  // 16 ulp of t: the problem is too stiff or singular), step_limit (options.max_steps accepted
  // steps) or observer_stop.
  outcome_kind stop = outcome_kind::success;
  T t{};                        // the time of the returned state (t_hi of the compensated time)
  std::optional<T> failed_at;   // where a run that did not complete stopped
};

namespace detail {
template <class Observer, scalar T, class State>
bool notify_adaptive(Observer& obs, std::size_t step, const T& t, const T& t_lo, const State& x) {
  if constexpr (std::is_same_v<std::invoke_result_t<Observer&, std::size_t, const T&, const T&, const State&>, void>) {
    obs(step, t, t_lo, x);
    return true;
  } else {
    return static_cast<bool>(obs(step, t, t_lo, x));
  }
}

struct no_adaptive_observer {
  template <scalar T, class State>
  void operator()(std::size_t, const T&, const T&, const State&) const {}
};

// One run of integrate_adaptive. The state, its compensation and the time stay in locals of
// run() and pass by reference into the force-inlined steps: kept as members (or behind the
// caller's reference) they would go through memory at every step. Stepper is embedded_rk, or a
// stepper of the same interface that measures only part of the state (runs/detail/attitude.hpp):
// it measures the error, so it also gives the starting step (starting_step).
template <class Pair, class System, class State, scalar T, class Observer, class Scale,
          class Stepper = embedded_rk<Pair, State, T>>
class adaptive_driver {
 public:
  adaptive_driver(System& sys, const State& shape, const T& t0, const T& t_end, const adaptive_options<T>& o,
                  Observer& observer, const Scale& scale)
      : sys_(sys), t0_(t0), t_end_(t_end), o_(o), observer_(observer), scale_(scale), stepper_(shape) {}

  // x <- the state at r.t, the last accepted one.
  [[gnu::always_inline]] adaptive_result<T> run(State& x) {
    State cur = x, next = x, comp = x, comp_next = x;
    state_traits<State>::for_each_index(comp, [&](auto i) { state_traits<State>::get(comp, i) = T(0); });
    clock at{t0_, T(0)};
    if (!notify_adaptive(observer_, std::size_t{0}, static_cast<const T&>(at.t), static_cast<const T&>(at.t_lo),
                         static_cast<const State&>(cur)))
      r_.stop = outcome_kind::observer_stop;
    else if (t_end_ - t0_ > 0)
      integrate(cur, next, comp, comp_next, at);
    r_.t = at.t;
    r_.rhs_evals = stepper_.rhs_evaluations() + extra_evals_;
    if (r_.stop != outcome_kind::success && r_.stop != outcome_kind::observer_stop && !r_.failed_at) r_.failed_at = at.t;
    using std::swap;
    swap(x, cur);
    return r_;
  }

 private:
  struct clock {
    T t, t_lo;  // the time reached, t + t_lo
  };
  enum class step_result { accepted, rejected, stopped };

  // Steps until t_end or a stop (r_.stop).
  [[gnu::always_inline]] void integrate(State& cur, State& next, State& comp, State& comp_next, clock& at) {
    h_max_ = o_.h_max ? *o_.h_max : T(t_end_ - t0_);
    stepper_.prime(sys_, cur, at.t);
    T h = o_.h_init ? *o_.h_init : stepper_.starting_step(sys_, cur, at.t, h_max_, scale_, extra_evals_);
    for (;;) {
      // The remaining span, from the compensated time; the last step lands on t_end.
      const T left = (t_end_ - at.t) - at.t_lo;
      if (!(left > 0)) return;
      const bool last = h >= left;
      const step_result s = try_step(cur, next, comp, comp_next, at, h, last ? left : h, last);
      if (s == step_result::stopped || (s == step_result::accepted && last)) return;
    }
  }

  // One attempt of a step of h_try from (at, cur): accepted (cur, comp and at advanced),
  // rejected, or stopped; h becomes the next step to try.
  [[gnu::always_inline]] step_result try_step(State& cur, State& next, State& comp, State& comp_next, clock& at,
                                              T& h, T h_try, bool last) {
    using std::abs;
    if (!(h_try > T(16) * std::numeric_limits<T>::epsilon() * abs(at.t)) || !is_finite_value(h_try))
      return stop(is_finite_value(h_try) ? outcome_kind::step_underflow : outcome_kind::non_finite);
    comp_next = comp;
    const double err = stepper_.attempt(sys_, cur, at.t, h_try, next, comp, comp_next, scale_);
    if (!(err <= 1) || !all_finite(next)) [[unlikely]] {
      ++r_.rejected;
      h = h_try * T(controller_.rejected(all_finite(next) ? err : std::numeric_limits<double>::infinity()));
      return step_result::rejected;
    }
    if (o_.max_norm && exceeds_max_norm(next, *o_.max_norm)) [[unlikely]] {
      r_.failed_at = T(at.t + h_try);
      return stop(outcome_kind::norm_bound);
    }
    using std::swap;
    swap(cur, next);
    swap(comp, comp_next);
    if (last) {
      at.t = t_end_;
      at.t_lo = T(0);
    } else {
      advance_time(at.t, at.t_lo, h_try);
    }
    ++r_.accepted;
    h = h_try * T(controller_.accepted(err));
    if (h > h_max_) h = h_max_;
    return after_accept(cur, at, last);
  }

  // After an accepted step: the derivative at the new state (FSAL), the observer, the step limit.
  [[gnu::always_inline]] step_result after_accept(const State& cur, const clock& at, bool last) {
    stepper_.accept(sys_, cur, at.t);
    if (!all_finite(stepper_.derivative())) [[unlikely]]
      return stop(outcome_kind::non_finite);
    if (!notify_adaptive(observer_, r_.accepted, static_cast<const T&>(at.t), static_cast<const T&>(at.t_lo), cur))
      return stop(outcome_kind::observer_stop);
    if (!last && o_.max_steps && r_.accepted >= o_.max_steps) return stop(outcome_kind::step_limit);
    return step_result::accepted;
  }

  [[gnu::always_inline]] step_result stop(outcome_kind why) {
    r_.stop = why;
    return step_result::stopped;
  }

  System& sys_;
  const T& t0_;
  const T& t_end_;
  const adaptive_options<T>& o_;
  Observer& observer_;
  Scale scale_;
  Stepper stepper_;
  pi_controller controller_{Pair::estimate_order + 1};
  T h_max_{};
  std::size_t extra_evals_ = 0;  // those of the starting-step estimate
  adaptive_result<T> r_;
};
}  // namespace detail

// Integrates from (t0, x) to t_end with the pair `Pair` under error control.
//   - observer(step, t, t_lo, x): step = 0 at the start, then after each accepted step with its
//     index; t + t_lo is the state's time to twice the working precision. It may return void, or
//     bool (false stops the run).
//   - A run that cannot continue (non-finite state, beyond options.max_norm, step underflow)
//     keeps x at the last accepted state and says why and where (failed_at).
template <class Pair, class System, class State, scalar T, class Observer = detail::no_adaptive_observer,
          class Scale = hairer_scale<T>>
adaptive_result<T> integrate_adaptive(System&& sys, State& x, const T& t0, const T& t_end,
                                      const adaptive_options<T>& o, Observer&& observer = {}, Scale scale = {}) {
  if constexpr (std::is_same_v<Scale, hairer_scale<T>>) scale = hairer_scale<T>{o.atol, o.rtol};
  detail::adaptive_driver<Pair, std::remove_reference_t<System>, State, T, std::remove_reference_t<Observer>, Scale>
      driver(sys, x, t0, t_end, o, observer, scale);
  return driver.run(x);
}

}  // namespace eulervop::rk
