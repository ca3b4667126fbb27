// The fixed-step driver: n steps of one explicit Runge-Kutta method (explicit_rk.hpp) from
// (t0, x), with an observer, compensated summation of the state, and a stop at the first step
// whose result is not finite or beyond a bound.
#pragma once

#include <eulervop/core/outcome.hpp>
#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/rk/explicit_rk.hpp>
#include <eulervop/rk/state_traits.hpp>
#include <eulervop/rk/tableaux.hpp>

#include <cstddef>
#include <optional>
#include <type_traits>
#include <utility>

namespace eulervop::rk {

template <scalar T>
struct fixed_step_options {
  // Declare divergence when the max-norm of the state exceeds this bound.
  std::optional<T> max_norm;
};

template <scalar T>
struct fixed_step_result {
  std::size_t steps = 0;      // accepted steps; the returned state is at t = t0 + steps*h
  std::size_t rhs_evals = 0;  // right-hand-side evaluations, including those of a rejected step
  // success (all n_steps taken), observer_stop, non_finite (a step produced Inf or NaN) or
  // norm_bound (a step produced a state beyond options.max_norm: "explodes").
  outcome_kind stop = outcome_kind::success;
  std::optional<T> failed_at;  // non_finite, norm_bound: the end time of the step that did it
  T t{};  // time of the returned state

  bool diverged() const { return stop == outcome_kind::non_finite || stop == outcome_kind::norm_bound; }
};

// An observer that does nothing.
struct no_observer {
  template <scalar T, class State>
  void operator()(std::size_t, const T&, const State&) const {}
};

namespace detail {
template <class Observer, scalar T, class State>
bool notify(Observer& obs, std::size_t step, const T& t, const State& x) {
  if constexpr (std::is_same_v<std::invoke_result_t<Observer&, std::size_t, const T&, const State&>,
                               void>) {
    obs(step, t, x);
    return true;
  } else {
    return static_cast<bool>(obs(step, t, x));
  }
}
}  // namespace detail

// Integrates n_steps fixed steps of size h from (t0, x) with the method Tableau.
//   - observer(step, t, x) is called with step = 0 at the start, then after every accepted step
//     with its index 1..n. It may return void, or bool (false stops the run).
//   - A step whose result is non-finite, or beyond options.max_norm, is not accepted: x keeps the
//     last good state (never NaN), stop says which and failed_at = the end time of that step.
//   - Times are t0 + n*h (no accumulated sum), and the state is summed with compensation.
// On return x holds the state at result.t.
template <class Tableau, class System, class State, scalar T, class Observer = no_observer>
fixed_step_result<T> integrate_fixed(System&& sys, State& x, const T& t0, const T& h,
                                     std::size_t n_steps, Observer&& observer = {},
                                     const fixed_step_options<T>& options = {}) {
  explicit_rk<Tableau, State, T> stepper(x);
  // The loop works on local copies and writes x back once: a state written through the
  // caller's reference every step goes through memory, and reloading it (a 16-byte load across
  // two 8-byte stores) stalls store forwarding, which tripled the cost of a step of Eq. 5.
  State cur = x;
  State next = x;
  State comp = x;  // compensation of the summed state, starts at zero
  state_traits<State>::for_each_index(comp, [&](auto i) { state_traits<State>::get(comp, i) = T(0); });
  State comp_next = comp;
  fixed_step_result<T> r;
  r.t = t0;
  T t = t0;
  T t_next = t0;
  const bool bounded = options.max_norm.has_value();
  const T hi = bounded ? *options.max_norm : T(0);
  const T lo = -hi;
  std::size_t n = 0;
  const auto finish = [&](outcome_kind stop) {
    r.steps = n;
    r.t = t;
    r.rhs_evals = stepper.rhs_evaluations();
    r.stop = stop;
    using std::swap;
    swap(x, cur);
    return r;
  };
  if (!detail::notify(observer, std::size_t{0}, static_cast<const T&>(t), static_cast<const State&>(cur)))
    return finish(outcome_kind::observer_stop);
  for (; n < n_steps;) {
    comp_next = comp;
    stepper.do_step(sys, static_cast<const State&>(cur), static_cast<const T&>(t), h, next, comp_next);
    t_next = h;
    if constexpr (std::is_floating_point_v<T>)
      t_next *= static_cast<T>(n + 1);  // exact below 2^53 steps
    else
      t_next *= static_cast<unsigned long long>(n + 1);  // in place, no MPFR temporary
    t_next += t0;
    const bool finite = all_finite(next);
    if (!finite || (bounded && detail::outside_band(next, lo, hi))) [[unlikely]] {
      r.failed_at = t_next;
      return finish(finite ? outcome_kind::norm_bound : outcome_kind::non_finite);
    }
    using std::swap;
    swap(cur, next);
    swap(comp, comp_next);
    swap(t, t_next);
    ++n;
    if (!detail::notify(observer, n, static_cast<const T&>(t), static_cast<const State&>(cur)))
      return finish(outcome_kind::observer_stop);
  }
  return finish(outcome_kind::success);
}

// Run-time method choice: one dispatch, then the statically typed loop above.
template <class System, class State, scalar T, class Observer = no_observer>
fixed_step_result<T> integrate_fixed(method m, System&& sys, State& x, const T& t0, const T& h,
                                     std::size_t n_steps, Observer&& observer = {},
                                     const fixed_step_options<T>& options = {}) {
  return dispatch_method(m, [&](auto tag) {
    return integrate_fixed<decltype(tag)>(sys, x, t0, h, n_steps, observer, options);
  });
}

}  // namespace eulervop::rk
