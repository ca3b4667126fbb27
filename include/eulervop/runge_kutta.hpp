// Fixed-step explicit Runge-Kutta methods from Butcher tableaux (issue 3, section 3).
//
// Concepts, in the manner of Boost.Odeint:
//   - system:  sys(const State& x, State& dxdt, const T& t)   (no return value used)
//   - state:   a fixed-shape container of T. Supported out of the box: anything indexable with
//              size() and operator[] (std::array<T, N>, eulervop::vec3<T>, ...) and plain
//              aggregates whose fields are all T (through Boost.PFR), e.g.
//                template <class T> struct planar { T x, y; };
//              Other types: specialize eulervop::rk::state_traits<State>.
//   - tableau: a tag type (rk4_tableau, rkf45_tableau, dp45_tableau, rk8_tableau) with a name, the
//              declared order, the number of stages and coefficients<T>(), which builds the
//              Butcher coefficients in T from integers (T(1)/T(6)), never from double literals.
//
// The stepping loop is statically typed on the tableau, the state and the scalar: stage storage is
// a std::array<State, stages>, no heap allocation (for MPFR: none after construction) and no
// virtual call per step. The run-time choice of method is a switch that hands a generic lambda the
// concrete tableau tag (dispatch_method), once per run.
//
// Methods (stages = right-hand-side evaluations per step; FSAL is not used in fixed stepping):
//   rk4    classical Runge-Kutta, order 4, 4 stages.
//   rkf45  Fehlberg 4(5), advancing with its 5th-order weights (our reading of the paper's
//          "Runge-Kutta 4/5"), order 5, 6 stages. HNW I, Table II.5.1.
//   dp45   Dormand-Prince 5(4), advancing with the 5th-order solution, order 5, 6 stages. The
//          pair's 7th stage (FSAL, a7j = bj, b7 = 0) serves only the embedded 4th-order error
//          estimate, which a fixed-step run never uses, so it is not evaluated. HNW I, Table II.5.2.
//   rk8    the 8th-order 12-stage method of DOP853 (Hairer & Wanner). See
//          detail/butcher_dop853.hpp for which coefficients are exact and which carry the ~30
//          digits printed in dop853.f.
#pragma once

#include <eulervop/detail/butcher_dop853.hpp>

#include <boost/pfr.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string_view>
#include <type_traits>
#include <utility>

namespace eulervop::rk {

// ---- Butcher tableaux ---------------------------------------------------------------------------

// a is strictly lower triangular (explicit method); entries not set are zero.
template <class T, std::size_t S>
struct butcher_tableau {
  static constexpr std::size_t stages = S;
  std::array<std::array<T, S>, S> a{};
  std::array<T, S> b{};
  std::array<T, S> c{};
};

enum class method { rk4, rkf45, dp45, rk8 };

inline constexpr std::array<method, 4> all_methods = {method::rk4, method::rkf45, method::dp45,
                                                      method::rk8};

struct rk4_tableau {
  static constexpr method id = method::rk4;
  static constexpr std::string_view name = "rk4";
  static constexpr int order = 4;
  static constexpr std::size_t stages = 4;

  template <class T>
  static butcher_tableau<T, stages> coefficients() {
    butcher_tableau<T, stages> t;
    const auto q = [](int n, int d) { return T(n) / T(d); };
    t.c = {T(0), q(1, 2), q(1, 2), T(1)};
    t.a[1][0] = q(1, 2);
    t.a[2][1] = q(1, 2);
    t.a[3][2] = T(1);
    t.b = {q(1, 6), q(1, 3), q(1, 3), q(1, 6)};
    return t;
  }
};

// Fehlberg's 4(5) pair, advanced with the 5th-order weights. The 4th-order weights, unused here,
// are (25/216, 0, 1408/2565, 2197/4104, -1/5, 0).
struct rkf45_tableau {
  static constexpr method id = method::rkf45;
  static constexpr std::string_view name = "rkf45";
  static constexpr int order = 5;
  static constexpr std::size_t stages = 6;

  template <class T>
  static butcher_tableau<T, stages> coefficients() {
    butcher_tableau<T, stages> t;
    const auto q = [](int n, int d) { return T(n) / T(d); };
    t.c = {T(0), q(1, 4), q(3, 8), q(12, 13), T(1), q(1, 2)};
    t.a[1][0] = q(1, 4);
    t.a[2][0] = q(3, 32);
    t.a[2][1] = q(9, 32);
    t.a[3][0] = q(1932, 2197);
    t.a[3][1] = q(-7200, 2197);
    t.a[3][2] = q(7296, 2197);
    t.a[4][0] = q(439, 216);
    t.a[4][1] = T(-8);
    t.a[4][2] = q(3680, 513);
    t.a[4][3] = q(-845, 4104);
    t.a[5][0] = q(-8, 27);
    t.a[5][1] = T(2);
    t.a[5][2] = q(-3544, 2565);
    t.a[5][3] = q(1859, 4104);
    t.a[5][4] = q(-11, 40);
    t.b = {q(16, 135), T(0), q(6656, 12825), q(28561, 56430), q(-9, 50), q(2, 55)};
    return t;
  }
};

// Dormand-Prince 5(4), 5th-order solution; the FSAL 7th stage is dropped (see the header note).
// The 4th-order weights, unused here, are
// (5179/57600, 0, 7571/16695, 393/640, -92097/339200, 187/2100, 1/40).
struct dp45_tableau {
  static constexpr method id = method::dp45;
  static constexpr std::string_view name = "dp45";
  static constexpr int order = 5;
  static constexpr std::size_t stages = 6;

  template <class T>
  static butcher_tableau<T, stages> coefficients() {
    butcher_tableau<T, stages> t;
    const auto q = [](int n, int d) { return T(n) / T(d); };
    t.c = {T(0), q(1, 5), q(3, 10), q(4, 5), q(8, 9), T(1)};
    t.a[1][0] = q(1, 5);
    t.a[2][0] = q(3, 40);
    t.a[2][1] = q(9, 40);
    t.a[3][0] = q(44, 45);
    t.a[3][1] = q(-56, 15);
    t.a[3][2] = q(32, 9);
    t.a[4][0] = q(19372, 6561);
    t.a[4][1] = q(-25360, 2187);
    t.a[4][2] = q(64448, 6561);
    t.a[4][3] = q(-212, 729);
    t.a[5][0] = q(9017, 3168);
    t.a[5][1] = q(-355, 33);
    t.a[5][2] = q(46732, 5247);
    t.a[5][3] = q(49, 176);
    t.a[5][4] = q(-5103, 18656);
    t.b = {q(35, 384), T(0), q(500, 1113), q(125, 192), q(-2187, 6784), q(11, 84)};
    return t;
  }
};

// DOP853's 8th-order method (12 stages; the 13th evaluation of dop853.f is FSAL/error estimate).
struct rk8_tableau {
  static constexpr method id = method::rk8;
  static constexpr std::string_view name = "rk8";
  static constexpr int order = 8;
  static constexpr std::size_t stages = 12;

  template <class T>
  static butcher_tableau<T, stages> coefficients() {
    butcher_tableau<T, stages> t;
    detail::fill_dop853<butcher_tableau<T, stages>, T>(t);
    return t;
  }
};

// Calls f(Tag{}) with the concrete tableau tag of m and returns its result; every branch must
// return the same type. This is the only run-time branch on the method.
template <class F>
decltype(auto) dispatch_method(method m, F&& f) {
  switch (m) {
    case method::rk4: return std::forward<F>(f)(rk4_tableau{});
    case method::rkf45: return std::forward<F>(f)(rkf45_tableau{});
    case method::dp45: return std::forward<F>(f)(dp45_tableau{});
    case method::rk8: break;
  }
  return std::forward<F>(f)(rk8_tableau{});
}

constexpr std::string_view method_name(method m) {
  switch (m) {
    case method::rk4: return rk4_tableau::name;
    case method::rkf45: return rkf45_tableau::name;
    case method::dp45: return dp45_tableau::name;
    case method::rk8: return rk8_tableau::name;
  }
  return "?";
}
constexpr int declared_order(method m) {
  switch (m) {
    case method::rk4: return rk4_tableau::order;
    case method::rkf45: return rkf45_tableau::order;
    case method::dp45: return dp45_tableau::order;
    case method::rk8: return rk8_tableau::order;
  }
  return 0;
}
constexpr std::size_t stage_count(method m) {
  switch (m) {
    case method::rk4: return rk4_tableau::stages;
    case method::rkf45: return rkf45_tableau::stages;
    case method::dp45: return dp45_tableau::stages;
    case method::rk8: return rk8_tableau::stages;
  }
  return 0;
}

// "rk4", "rkf45", "dp45", "rk8" (exact, lower case); nullopt otherwise.
constexpr std::optional<method> method_from_name(std::string_view text) {
  for (method m : all_methods)
    if (method_name(m) == text) return m;
  return std::nullopt;
}

// ---- state access -------------------------------------------------------------------------------

namespace detail {
template <class S>
concept indexable_state = requires(S& s, std::size_t i) {
  s.size();
  s[i];
};
}  // namespace detail

// How the stepper walks a state. for_each_index(s, f) calls f(i) for every component index i
// (a std::size_t, or a std::integral_constant for aggregates); get(s, i) returns a reference to
// that component. Specialize for other state types.
template <class State>
struct state_traits {
  template <class F>
  static void for_each_index(const State& s, F&& f) {
    if constexpr (detail::indexable_state<State>) {
      const std::size_t n = s.size();
      for (std::size_t i = 0; i < n; ++i) f(i);
    } else {
      static_assert(std::is_aggregate_v<State>,
                    "state must be indexable, an aggregate of scalars, or have a state_traits "
                    "specialization");
      [&]<std::size_t... I>(std::index_sequence<I...>) {
        (f(std::integral_constant<std::size_t, I>{}), ...);
      }(std::make_index_sequence<boost::pfr::tuple_size_v<State>>{});
    }
  }
  template <class S, class Index>
  static decltype(auto) get(S& s, Index i) {
    if constexpr (detail::indexable_state<State>) {
      return (s[i]);
    } else {
      return (boost::pfr::get<Index::value>(s));
    }
  }
};

namespace detail {
template <class State>
struct first_index {
  using type = std::conditional_t<indexable_state<State>, std::size_t,
                                  std::integral_constant<std::size_t, 0>>;
};
}  // namespace detail

// The scalar type of a state's components.
template <class State>
using state_value_t = std::remove_cvref_t<decltype(state_traits<State>::get(
    std::declval<State&>(), std::declval<typename detail::first_index<State>::type>()))>;

template <class T>
bool is_finite_value(const T& v) {
  using std::isfinite;
  return static_cast<bool>(isfinite(v));  // unqualified: ADL finds boost::multiprecision::isfinite
}

// True when every component is finite.
template <class State>
bool all_finite(const State& x) {
  bool ok = true;
  state_traits<State>::for_each_index(x, [&](auto i) {
    ok = ok && is_finite_value(state_traits<State>::get(x, i));
  });
  return ok;
}

namespace detail {
// True when some component lies outside [lo, hi]. NaN is never outside.
template <class State, class T>
bool outside_band(const State& x, const T& lo, const T& hi) {
  bool out = false;
  state_traits<State>::for_each_index(x, [&](auto i) {
    const auto& v = state_traits<State>::get(x, i);
    out = out || v > hi || v < lo;
  });
  return out;
}
}  // namespace detail

// True when some component has |x_i| > bound, i.e. the max-norm exceeds bound.
template <class State, class T>
bool exceeds_max_norm(const State& x, const T& bound) {
  const T lo = -bound;
  return detail::outside_band(x, lo, bound);
}

// ---- the stepper --------------------------------------------------------------------------------

// One explicit Runge-Kutta method, fixed step, generic over state, scalar and system.
// For MPFR, construct it inside the mpfr_precision_scope of the run: the coefficients and the
// stage storage take the thread's precision at construction.
template <class Tableau, class State, class T = state_value_t<State>>
class explicit_rk {
 public:
  using tableau_type = Tableau;
  using state_type = State;
  using value_type = T;
  static constexpr std::size_t stages = Tableau::stages;
  static constexpr int order = Tableau::order;
  static constexpr std::string_view name = Tableau::name;

  // `shape` only gives the stage storage its shape (it matters for resizable states).
  explicit explicit_rk(const State& shape = State{})
      : tab_(Tableau::template coefficients<T>()), tmp_(shape), out_(shape) {
    k_.fill(shape);
    for (std::size_t i = 0; i < stages; ++i) {
      for (std::size_t j = 0; j < stages; ++j) nz_a_[i][j] = tab_.a[i][j] != 0;
      nz_b_[i] = tab_.b[i] != 0;
    }
  }

  const butcher_tableau<T, stages>& coefficients() const { return tab_; }

  // Right-hand-side evaluations since construction (= stages x steps).
  std::size_t rhs_evaluations() const { return evals_; }

  // out = one step of size h from (t, x). out must not alias x.
  template <class System>
  void do_step(System& sys, const State& x, const T& t, const T& h, State& out) {
    using traits = state_traits<State>;
    compute_stages(sys, x, t, h);
    traits::for_each_index(x, [&](auto idx) {
      auto& y = traits::get(out, idx);
      increment(idx, h, y);
      y += traits::get(x, idx);
    });
  }

  // The same step with compensated summation of the state (TwoSum, Knuth TAOCP 4.2.2): `comp`
  // carries the rounding error of x + increment from step to step, so over n steps the state
  // loses O(eps) instead of O(sqrt(n) eps). Long fixed-step runs (1e5 steps) need it: without
  // it a torque-free VOP phase u = c2 tau drifts by ~sqrt(n) ulp(u) although each increment is
  // exact to rounding.
  template <class System>
  void do_step(System& sys, const State& x, const T& t, const T& h, State& out, State& comp) {
    using traits = state_traits<State>;
    compute_stages(sys, x, t, h);
    traits::for_each_index(x, [&](auto idx) {
      auto& y = traits::get(out, idx);
      const auto& x0 = traits::get(x, idx);
      auto& c = traits::get(comp, idx);
      increment(idx, h, inc_);
      inc_ += c;
      y = x0 + inc_;
      bb_ = y - x0;
      c = x0 - (y - bb_);
      c += inc_ - bb_;
    });
  }

  // In-place variant: x <- one step from (t, x). Uses an internal buffer.
  template <class System>
  void do_step(System& sys, State& x, const T& t, const T& h) {
    do_step(sys, static_cast<const State&>(x), t, h, out_);
    using std::swap;
    swap(x, out_);
  }

 private:
  // k_[0..stages) at (t, x).
  template <class System>
  void compute_stages(System& sys, const State& x, const T& t, const T& h) {
    using traits = state_traits<State>;
    sys(x, k_[0], t);
    for (std::size_t s = 1; s < stages; ++s) {
      traits::for_each_index(x, [&](auto idx) {
        auto& y = traits::get(tmp_, idx);
        y = zero_;
        for (std::size_t j = 0; j < s; ++j)
          if (nz_a_[s][j]) y += tab_.a[s][j] * traits::get(k_[j], idx);
        y *= h;
        y += traits::get(x, idx);
      });
      ts_ = tab_.c[s] * h;
      ts_ += t;
      sys(static_cast<const State&>(tmp_), k_[s], static_cast<const T&>(ts_));
    }
    evals_ += stages;
  }

  // y = h sum_j b_j k_j[idx], formed as h (k_1 + sum_{j>1} b_j (k_j - k_1)). The two are equal
  // because sum_j b_j = 1 (consistency), but the second is exact when all stages agree: a
  // constant derivative (torque-free VOP: u' = c2) then advances by exactly h k_1 instead of
  // h k_1 (sum_j b_j rounded), which would drift systematically over 1e5 steps.
  template <class Index>
  void increment(Index idx, const T& h, T& y) {
    using traits = state_traits<State>;
    const T& k1 = traits::get(k_[0], idx);
    y = zero_;
    for (std::size_t j = 1; j < stages; ++j)
      if (nz_b_[j]) {
        dk_ = traits::get(k_[j], idx);
        dk_ -= k1;
        y += tab_.b[j] * dk_;
      }
    y += k1;
    y *= h;
  }

  butcher_tableau<T, stages> tab_;
  std::array<std::array<bool, stages>, stages> nz_a_{};
  std::array<bool, stages> nz_b_{};
  std::array<State, stages> k_;
  State tmp_;
  State out_;
  T ts_{};
  T inc_{}, bb_{}, dk_{};
  T zero_{0};
  std::size_t evals_ = 0;
};

// ---- the fixed-step driver ----------------------------------------------------------------------

enum class stop_reason {
  completed,    // all n_steps taken
  non_finite,   // a step produced Inf or NaN
  norm_bound,   // a step produced a state beyond options.max_norm ("explodes")
  observer,     // the observer returned false
};

template <class T>
struct fixed_step_options {
  // Declare divergence when the max-norm of the state exceeds this bound.
  std::optional<T> max_norm;
};

template <class T>
struct fixed_step_result {
  std::size_t steps = 0;      // accepted steps; the returned state is at t = t0 + steps*h
  std::size_t rhs_evals = 0;  // right-hand-side evaluations, including those of a rejected step
  bool diverged = false;      // stop == non_finite or norm_bound
  std::optional<T> diverged_at;  // end time of the step that produced the bad state
  stop_reason stop = stop_reason::completed;
  T t{};  // time of the returned state
};

// An observer that does nothing.
struct no_observer {
  template <class T, class State>
  void operator()(std::size_t, const T&, const State&) const {}
};

namespace detail {
template <class Observer, class T, class State>
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
//     last good state (never NaN), diverged = true and diverged_at = the end time of that step.
//   - Times are t0 + n*h (no accumulated sum), and the state is summed with compensation.
// On return x holds the state at result.t.
template <class Tableau, class System, class State, class T, class Observer = no_observer>
fixed_step_result<T> integrate_fixed(System&& sys, State& x, const T& t0, const T& h,
                                     std::size_t n_steps, Observer&& observer = {},
                                     const fixed_step_options<T>& options = {}) {
  explicit_rk<Tableau, State, T> stepper(x);
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
  if (!detail::notify(observer, std::size_t{0}, static_cast<const T&>(t),
                      static_cast<const State&>(x))) {
    r.stop = stop_reason::observer;
    return r;
  }
  for (std::size_t n = 0; n < n_steps; ++n) {
    comp_next = comp;
    stepper.do_step(sys, static_cast<const State&>(x), static_cast<const T&>(t), h, next, comp_next);
    r.rhs_evals = stepper.rhs_evaluations();
    t_next = h;
    if constexpr (std::is_floating_point_v<T>)
      t_next *= static_cast<T>(n + 1);  // exact below 2^53 steps
    else
      t_next *= static_cast<unsigned long long>(n + 1);  // in place, no MPFR temporary
    t_next += t0;
    const bool finite = all_finite(next);
    if (!finite || (bounded && detail::outside_band(next, lo, hi))) {
      r.diverged = true;
      r.diverged_at = t_next;
      r.stop = finite ? stop_reason::norm_bound : stop_reason::non_finite;
      return r;
    }
    using std::swap;
    swap(x, next);
    swap(comp, comp_next);
    swap(t, t_next);
    r.steps = n + 1;
    r.t = t;
    if (!detail::notify(observer, n + 1, static_cast<const T&>(t), static_cast<const State&>(x))) {
      r.stop = stop_reason::observer;
      return r;
    }
  }
  return r;
}

// Run-time method choice: one dispatch, then the statically typed loop above.
template <class System, class State, class T, class Observer = no_observer>
fixed_step_result<T> integrate_fixed(method m, System&& sys, State& x, const T& t0, const T& h,
                                     std::size_t n_steps, Observer&& observer = {},
                                     const fixed_step_options<T>& options = {}) {
  return dispatch_method(m, [&](auto tag) {
    return integrate_fixed<decltype(tag)>(sys, x, t0, h, n_steps, observer, options);
  });
}

}  // namespace eulervop::rk
