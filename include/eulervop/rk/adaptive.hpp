// Adaptive explicit Runge-Kutta: embedded pairs, Hairer's error norm, a PI step-size controller
// and a driver that integrates to an end time.
//
//   rk::adaptive_options<double> o{.atol = 1e-10, .rtol = 1e-10};
//   auto r = rk::integrate_adaptive<rk::dop853_pair>(sys, x, 0.0, 100.0, o);   // x <- x(100)
//   // r.accepted, r.rejected, r.rhs_evals, r.stop
//
// Pairs (HNW I = Hairer, Norsett, Wanner, Solving ODEs I, 2nd ed., Section II.4-II.5, II.10):
//   rkf45_pair   Fehlberg 4(5), 6 stages, advances with the 5th-order weights (local
//                extrapolation); estimate = difference to the 4th-order weights, O(h^5).
//   dp45_pair    Dormand-Prince 5(4), 7 stages with FSAL: the 7th stage is f at the new state and
//                the next step's first, so 6 new evaluations per accepted step; estimate O(h^5).
//   dop853_pair  the 12-stage 8th-order method of DOP853 with its two embedded estimators,
//                err5 (a 5th-order difference) and err3 (3rd order), combined as in dop853.f:
//                err = err5^2 / sqrt(err5^2 + 0.01 err3^2), which behaves like O(h^8). FSAL: the
//                new state's derivative is evaluated once after acceptance (12 evaluations per
//                accepted step, 11 per rejected one).
// Every estimate is formed as h sum_j e_j (k_j - k_1) with sum_j e_j = 0, so it is exactly zero
// when all stages agree (a constant derivative, as for torque-free VOP elements): such a step is
// exact and the controller then takes the largest step allowed.
//
// Error norm (HNW I, II.4, Eq. 4.11): err = sqrt(mean_i (e_i / sc_i)^2); the default scale is
// sc_i = atol + rtol max(|x0_i|, |x1_i|) (hairer_scale); callers measure other quantities by
// passing their own scale (the VOP runs weight the phase, comparison_run.hpp).
//
// Controller: Gustafsson's PI controller as in Hairer & Wanner, Solving ODEs II, Section IV.2:
//   h_new = h min(fac_max, max(fac_min, safety err_n^(-alpha) err_(n-1)^beta)),
//   alpha = 0.7 / k, beta = 0.4 / k, k = (order of the estimate) + 1,
// safety 0.9, fac_min 0.2, fac_max 10; after a rejected step the next accepted step does not
// grow (HNW I, II.4). A rejected step is retried with h max(fac_min, safety err^(-1/k)).
// Starting step: HNW I, II.4 (the "hinit" of dopri5/dop853), capped at h_max; when the trial
// Euler step leaves the derivative exactly unchanged (a constant derivative) it is h_max.
//
// Time: the driver keeps t as an unevaluated sum t_hi + t_lo (TwoSum), so that after 1e6 steps
// the state is at the time the observer is told, not at a time off by sqrt(n) ulp(t); the last
// step ends at t_end exactly.
#pragma once

#include <eulervop/core/outcome.hpp>
#include <eulervop/rk/explicit_rk.hpp>
#include <eulervop/core/scalar.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <cstddef>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <type_traits>
#include <utility>

namespace eulervop::rk {

// ---- embedded pairs -----------------------------------------------------------------------------

namespace detail {
// e_j = b_j - bhat_j.
template <scalar T, std::size_t S>
std::array<T, S> difference(const std::array<T, S>& b, const std::array<T, S>& bhat) {
  std::array<T, S> e;
  for (std::size_t j = 0; j < S; ++j) e[j] = b[j] - bhat[j];
  return e;
}
}  // namespace detail

struct rkf45_pair {
  static constexpr method id = method::rkf45;
  static constexpr std::string_view name = "rkf45";
  static constexpr int order = 5;           // of the advancing solution
  static constexpr int estimate_order = 4;  // the estimate is O(h^(estimate_order + 1))
  static constexpr std::size_t stages = 6;
  static constexpr bool fsal = false;
  static constexpr bool two_estimates = false;
  static constexpr sparsity<stages> nonzero = rkf45_tableau::nonzero;
  static constexpr std::array<bool, stages> error_nonzero = {true, false, true, true, true, true};

  template <scalar T>
  static butcher_tableau<T, stages> coefficients() {
    return rkf45_tableau::coefficients<T>();
  }
  template <scalar T>
  static std::array<T, stages> error_weights() {
    return detail::difference(rkf45_tableau::coefficients<T>().b, rkf45_tableau::embedded_weights<T>());
  }
};

struct dp45_pair {
  static constexpr method id = method::dp45;
  static constexpr std::string_view name = "dp45";
  static constexpr int order = 5;
  static constexpr int estimate_order = 4;
  static constexpr std::size_t stages = 7;  // the 7th is f(t + h, x + h sum b_j k_j): FSAL
  static constexpr bool fsal = true;
  static constexpr bool two_estimates = false;
  static constexpr sparsity<stages> nonzero = [] {
    sparsity<stages> p = sparsity<stages>::dense({1, 6});
    p.a[6][1] = false;  // row 7 is b, and b_2 = 0
    return p;
  }();
  static constexpr std::array<bool, stages> error_nonzero = {true, false, true, true, true, true, true};

  template <scalar T>
  static butcher_tableau<T, stages> coefficients() {
    const auto six = dp45_tableau::coefficients<T>();
    butcher_tableau<T, stages> t;
    for (std::size_t i = 0; i < 6; ++i) {
      for (std::size_t j = 0; j < 6; ++j) t.a[i][j] = six.a[i][j];
      t.c[i] = six.c[i];
      t.a[6][i] = six.b[i];
      t.b[i] = six.b[i];
    }
    t.c[6] = T(1);
    t.b[6] = T(0);
    return t;
  }
  template <scalar T>
  static std::array<T, stages> error_weights() {
    return detail::difference(coefficients<T>().b, dp45_tableau::embedded_weights<T>());
  }
};

struct dop853_pair {
  static constexpr method id = method::dop853;
  static constexpr std::string_view name = "dop853";
  static constexpr int order = 8;
  static constexpr int estimate_order = 7;  // the combined estimate behaves like O(h^8)
  static constexpr std::size_t stages = 12;
  static constexpr bool fsal = true;  // one evaluation at the accepted state, reused as k_1
  static constexpr bool two_estimates = true;
  static constexpr sparsity<stages> nonzero = rk8_tableau::nonzero;
  // err5 uses stages 1, 6..12 (1-based); err3 = b - bhat3 uses 1, 6..12 too (bhat3 on 1, 9, 12).
  static constexpr std::array<bool, stages> error_nonzero = {true,  false, false, false, false, true,
                                                             true,  true,  true,  true,  true,  true};

  template <scalar T>
  static butcher_tableau<T, stages> coefficients() {
    return rk8_tableau::coefficients<T>();
  }
  // er_j of dop853.f (its 5th-order difference; they sum to zero), as decimal strings parsed in T.
  template <scalar T>
  static std::array<T, stages> error_weights() {
    const auto d = [](const char* text) { return detail::decimal<T>(text); };
    std::array<T, stages> e{};
    e[0] = d("0.1312004499419488073250102996e-01");
    e[5] = d("-0.1225156446376204440720569753e+01");
    e[6] = d("-0.4957589496572501915214079952e+00");
    e[7] = d("0.1664377182454986536961530415e+01");
    e[8] = d("-0.3503288487499736816886487290e+00");
    e[9] = d("0.3341791187130174790297318841e+00");
    e[10] = d("0.8192320648511571246570742613e-01");
    e[11] = d("-0.2235530786388629525884427845e-01");
    return e;
  }
  // b_j - bhh_j: the 3rd-order estimate of dop853.f, whose bhh = (31/127, 12675/17272, 3/136) on
  // stages 1, 9 and 12 (1-based) are the rationals behind its printed decimals and sum to 1.
  template <scalar T>
  static std::array<T, stages> second_error_weights() {
    std::array<T, stages> e = rk8_tableau::coefficients<T>().b;
    e[0] -= T(31) / T(127);
    e[8] -= T(12675) / T(17272);
    e[11] -= T(3) / T(136);
    return e;
  }
};

// Calls f(Pair{}) for an adaptive method (rkf45, dp45, dop853); rk4 and rk8 have no embedded
// pair (std::invalid_argument).
template <class F>
decltype(auto) dispatch_pair(method m, F&& f) {
  switch (m) {
    case method::rkf45: return std::forward<F>(f)(rkf45_pair{});
    case method::dp45: return std::forward<F>(f)(dp45_pair{});
    case method::dop853: break;
    case method::rk4:
    case method::rk8: throw std::invalid_argument("rk::dispatch_pair: the method has no embedded error estimate");
  }
  return std::forward<F>(f)(dop853_pair{});
}

// ---- error norm and controller ------------------------------------------------------------------

// sc_i = atol + rtol max(|x0_i|, |x1_i|) (HNW I, Eq. II.4.10).
template <scalar T>
struct hairer_scale {
  T atol, rtol;
  template <class State>
  void operator()(const State& x0, const State& x1, State& sc) const {
    using std::abs;
    using std::max;
    state_traits<State>::for_each_index(x0, [&](auto i) __attribute__((always_inline)) {
      auto& s = state_traits<State>::get(sc, i);
      s = max(abs(state_traits<State>::get(x0, i)), abs(state_traits<State>::get(x1, i)));
      s *= rtol;
      s += atol;
    });
  }
};

// sqrt(mean_i (e_i / sc_i)^2) in double (the controller needs no more).
template <class State>
double rms_norm(const State& e, const State& sc) {
  double sum = 0;
  std::size_t n = 0;
  state_traits<State>::for_each_index(e, [&](auto i) __attribute__((always_inline)) {
    const double r = static_cast<double>(state_traits<State>::get(e, i)) /
                     static_cast<double>(state_traits<State>::get(sc, i));
    sum += r * r;
    ++n;
  });
  return std::sqrt(sum / static_cast<double>(n));
}

namespace detail {
// log2(x) and 2^x to about 1e-6, branch-free and inline: a step-size factor needs two or three
// digits (the safety factor is 0.9), and libm's pow (two calls per step, ~15 ns each) would cost
// more than a step of Eq. 5 with rk4. Deterministic, like the rest: the same inputs give the
// same step sequence.
[[gnu::always_inline]] inline double approx_log2(double x) {  // x > 0, finite
  const auto bits = std::bit_cast<std::uint64_t>(x);
  const int e = static_cast<int>((bits >> 52) & 0x7ff) - 1023;
  const double m = std::bit_cast<double>((bits & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL);  // [1, 2)
  // log2(m) = 2 atanh(s) / ln 2 with s = (m - 1)/(m + 1) in [0, 1/3): odd series to s^9
  // (truncation below (1/3)^11 / 11 * 2.9 = 1.5e-6).
  const double s = (m - 1) / (m + 1), z = s * s;
  const double p = 2.0 / std::numbers::ln2 * (1 + z * (1.0 / 3 + z * (1.0 / 5 + z * (1.0 / 7 + z / 9))));
  return e + s * p;
}
[[gnu::always_inline]] inline double approx_exp2(double x) {  // |x| < 1000
  constexpr double shifter = 0x1.8p52;  // x + shifter - shifter rounds x to an integer
  const double n = (x + shifter) - shifter;
  const double f = (x - n) * std::numbers::ln2;  // |f| <= ln2 / 2: Taylor to f^6, below 3e-7
  const double p = 1 + f * (1 + f * (1.0 / 2 + f * (1.0 / 6 + f * (1.0 / 24 + f * (1.0 / 120 + f / 720)))));
  const auto scale = static_cast<std::uint64_t>(static_cast<std::int64_t>(n) + 1023) << 52;  // 2^n
  return p * std::bit_cast<double>(scale);
}
}  // namespace detail

// The PI step-size controller (see the header note). k = estimate order + 1.
class pi_controller {
 public:
  static constexpr double safety = 0.9, fac_min = 0.2, fac_max = 10;

  explicit pi_controller(int k) : k_(k), alpha_(0.7 / k), beta_(0.4 / k) {}

  // The factor for the next step after an accepted step with error norm err <= 1 (err = 0: the
  // largest). Remembers err (at least 1e-4, as dopri5 does) for the next step's integral term.
  [[gnu::always_inline]] double accepted(double err) {
    double fac = fac_max;
    double log_err = floor_log_err;
    if (err > 0) {
      const double l = detail::approx_log2(err);
      fac = safety * detail::approx_exp2(beta_ * log_prev_ - alpha_ * l);
      log_err = std::max(l, floor_log_err);
    }
    fac = std::clamp(fac, fac_min, fac_max);
    if (rejected_last_) fac = std::min(fac, 1.0);
    rejected_last_ = false;
    log_prev_ = log_err;
    return fac;
  }
  // The factor for the retry after a rejected step (err > 1, or not finite: fac_min).
  [[gnu::always_inline]] double rejected(double err) {
    rejected_last_ = true;
    if (!(err < std::numeric_limits<double>::infinity())) return fac_min;
    return std::clamp(safety * detail::approx_exp2(-detail::approx_log2(err) / k_), fac_min, 1.0);
  }
  // Forget the history (after the state changed representation).
  void reset() {
    log_prev_ = floor_log_err;
    rejected_last_ = false;
  }

 private:
  static constexpr double floor_log_err = -13.287712379549449;  // log2(1e-4)
  int k_;
  double alpha_, beta_;
  double log_prev_ = floor_log_err;
  bool rejected_last_ = false;
};

// ---- the embedded stepper -----------------------------------------------------------------------

// One embedded pair, attempt by attempt. The caller owns acceptance:
//   prime(sys, x, t)                       k_1 = f(t, x) (at the start, and after x changed other
//                                          than by an accepted step)
//   attempt(sys, x, t, h, out, comp, comp_out, scale)
//                                          out = x + increment (compensated: comp -> comp_out);
//                                          returns the error norm (NaN if a stage was not finite)
//   accept(sys, out, t + h)                FSAL: k_1 of the next step
// For MPFR, construct it inside the run's mpfr_precision_scope.
template <class Pair, class State, scalar T = state_value_t<State>>
class embedded_rk {
 public:
  using pair_type = Pair;
  static constexpr std::size_t stages = Pair::stages;

  explicit embedded_rk(const State& shape = State{})
      : tab_(Pair::template coefficients<T>()),
        e_(Pair::template error_weights<T>()),
        work_(shape),
        k1_(shape),
        k_last_(shape),
        sc_(shape),
        err_(shape),
        err2_(shape) {
    if constexpr (Pair::two_estimates) e2_ = Pair::template second_error_weights<T>();
  }

  std::size_t rhs_evaluations() const { return evals_; }

  template <class System>
  [[gnu::always_inline]] void prime(System& sys, const State& x, const T& t) {
    sys(x, k1_, t);
    ++evals_;
  }

  template <class System, class Scale>
  [[gnu::always_inline]] double attempt(System& sys, const State& x, const T& t, const T& h, State& out,
                                        const State& comp, State& comp_out, Scale&& scale) {
    if constexpr (detail::work_on_stack<State, T>) {
      work_type w;
      State err, err2, sc;
      return attempt_in(w, err, err2, sc, sys, x, t, h, out, comp, comp_out, scale);
    } else {
      return attempt_in(work_, err_, err2_, sc_, sys, x, t, h, out, comp, comp_out, scale);
    }
  }

  template <class System>
  [[gnu::always_inline]] void accept(System& sys, const State& out, const T& t_new) {
    if constexpr (Pair::fsal && stages == 7) {
      // dp45: the 7th stage was f at x + h sum b_j k_j, the new state before compensation.
      k1_ = k_last_;
      (void)sys, (void)out, (void)t_new;
    } else {
      sys(out, k1_, t_new);
      ++evals_;
    }
  }

  // The derivative at the current state (valid after prime or accept).
  const State& derivative() const { return k1_; }

 private:
  using work_type = detail::stage_work<State, T, stages>;

  template <class System, class Scale>
  [[gnu::always_inline]] double attempt_in(work_type& w, State& err, State& err2, State& sc, System& sys,
                                           const State& x, const T& t, const T& h, State& out, const State& comp,
                                           State& comp_out, Scale& scale) {
    using traits = state_traits<State>;
    w.k[0] = k1_;
    detail::compute_stages<stages, Pair::nonzero, 1>(sys, tab_, x, t, h, w);
    evals_ += stages - 1;
    if constexpr (Pair::fsal && stages == 7) k_last_ = w.k[stages - 1];
    traits::for_each_index(x, [&](auto i) __attribute__((always_inline)) {
      detail::weighted_increment<stages, Pair::nonzero>(tab_.b, i, h, w, w.inc);
      w.inc += traits::get(comp, i);
      auto& y = traits::get(out, i);
      const auto& x0 = traits::get(x, i);
      y = x0 + w.inc;
      w.bb = y - x0;
      auto& c = traits::get(comp_out, i);
      c = x0 - (y - w.bb);
      c += w.inc - w.bb;
      error_sum(w, e_, i, h, traits::get(err, i));
      if constexpr (Pair::two_estimates) error_sum(w, e2_, i, h, traits::get(err2, i));
    });
    scale(x, out, sc);
    const double n1 = rms_norm(err, sc);
    if constexpr (Pair::two_estimates) {
      // dop853.f: err5^2 / sqrt(err5^2 + 0.01 err3^2) (0 when both vanish).
      const double n3 = rms_norm(err2, sc);
      const double den = std::sqrt(n1 * n1 + 0.01 * n3 * n3);
      return den > 0 ? n1 * n1 / den : (std::isnan(den) ? den : 0.0);
    } else {
      return n1;
    }
  }

  // y = h sum_{j>=2} e_j (k_j - k_1)[i]: zero when all stages agree, since sum_j e_j = 0.
  template <class Index>
  [[gnu::always_inline]] static void error_sum(work_type& w, const std::array<T, stages>& e, Index i, const T& h,
                                               T& y) {
    using traits = state_traits<State>;
    const T& k1 = traits::get(w.k[0], i);
    y = T(0);
    detail::static_for<1, stages>([&](auto j) __attribute__((always_inline)) {
      if constexpr (Pair::error_nonzero[j]) {
        w.dk = traits::get(w.k[j], i);
        w.dk -= k1;
        y += e[j] * w.dk;
      }
    });
    y *= h;
  }

  butcher_tableau<T, stages> tab_;
  std::array<T, stages> e_, e2_{};
  work_type work_;           // used only when the state cannot live on the stack
  State k1_, k_last_;        // the derivative at the current state; dp45's 7th stage
  State sc_, err_, err2_;    // likewise
  std::size_t evals_ = 0;
};

// ---- the driver ---------------------------------------------------------------------------------

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
// t_hi + t_lo <- t_hi + t_lo + h (TwoSum).
template <scalar T>
void advance_time(T& hi, T& lo, const T& h) {
  const T s = hi + h;
  const T bb = s - hi;
  T err = (hi - (s - bb)) + (h - bb);
  err += lo;
  hi = s + err;
  lo = err - (hi - s);
}

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
}  // namespace detail

// HNW's starting step (HNW I, II.4, "Starting step size"), capped at h_max. Uses two
// evaluations of the system, counted in *evals.
template <class Pair, class System, class State, scalar T, class Scale>
T initial_step(System& sys, const State& x0, const T& t0, const State& f0, const T& h_max, Scale& scale,
               std::size_t& evals) {
  using std::abs;
  using std::pow;
  State sc = x0, x1 = x0, f1 = f0, d = f0;
  scale(x0, x0, sc);
  const double d0 = rms_norm(x0, sc), d1 = rms_norm(f0, sc);
  T h0 = (d0 < 1e-5 || d1 < 1e-5) ? T(1e-6) : T(0.01 * d0 / d1);
  if (h0 > h_max) h0 = h_max;
  state_traits<State>::for_each_index(x0, [&](auto i) {
    state_traits<State>::get(x1, i) = state_traits<State>::get(x0, i) + h0 * state_traits<State>::get(f0, i);
  });
  sys(x1, f1, T(t0 + h0));
  ++evals;
  bool unchanged = true;
  state_traits<State>::for_each_index(x0, [&](auto i) {
    auto& di = state_traits<State>::get(d, i);
    di = state_traits<State>::get(f1, i) - state_traits<State>::get(f0, i);
    unchanged = unchanged && di == 0;
  });
  if (unchanged) return h_max;  // a constant derivative: every step is exact
  const double d2 = rms_norm(d, sc) / static_cast<double>(h0);
  const double dm = std::max(d1, d2);
  const double k = Pair::estimate_order + 1;
  T h1 = dm <= 1e-15 ? std::max(T(1e-6), T(h0 * 1e-3)) : T(std::pow(0.01 / dm, 1.0 / k));
  T h = std::min(T(100 * h0), h1);
  if (h > h_max) h = h_max;
  return h;
}

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
  using std::abs;
  using std::swap;
  if constexpr (std::is_same_v<Scale, hairer_scale<T>>) scale = hairer_scale<T>{o.atol, o.rtol};
  embedded_rk<Pair, State, T> stepper(x);
  pi_controller controller(Pair::estimate_order + 1);
  adaptive_result<T> r;
  // Local copies, written back once (see integrate_fixed: a state kept behind a reference goes
  // through memory every step). Nothing below takes their address.
  State cur = x, next = x, comp = x, comp_next = x;
  state_traits<State>::for_each_index(comp, [&](auto i) { state_traits<State>::get(comp, i) = T(0); });
  T t = t0, t_lo = T(0);
  std::size_t extra = 0;  // evaluations of the starting-step estimate
  outcome_kind stop = outcome_kind::success;
  if (!detail::notify_adaptive(observer, std::size_t{0}, static_cast<const T&>(t), static_cast<const T&>(t_lo),
                               static_cast<const State&>(cur))) {
    stop = outcome_kind::observer_stop;
  } else if (t_end - t0 > 0) {
    const T h_max = o.h_max ? *o.h_max : T(t_end - t0);
    stepper.prime(sys, cur, t);
    T h = o.h_init ? *o.h_init : initial_step<Pair>(sys, cur, t, stepper.derivative(), h_max, scale, extra);
    for (;;) {
      // The remaining span, from the compensated time; the last step lands on t_end.
      const T left = (t_end - t) - t_lo;
      if (!(left > 0)) break;
      const bool last = h >= left;
      const T h_try = last ? left : h;
      if (!(h_try > T(16) * std::numeric_limits<T>::epsilon() * abs(t)) || !is_finite_value(h_try)) {
        stop = is_finite_value(h_try) ? outcome_kind::step_underflow : outcome_kind::non_finite;
        break;
      }
      comp_next = comp;
      const double err = stepper.attempt(sys, cur, t, h_try, next, comp, comp_next, scale);
      if (!(err <= 1) || !all_finite(next)) [[unlikely]] {
        ++r.rejected;
        h = h_try * T(controller.rejected(all_finite(next) ? err : std::numeric_limits<double>::infinity()));
        continue;
      }
      if (o.max_norm && exceeds_max_norm(next, *o.max_norm)) [[unlikely]] {
        r.failed_at = T(t + h_try);
        stop = outcome_kind::norm_bound;
        break;
      }
      swap(cur, next);
      swap(comp, comp_next);
      if (last) {
        t = t_end;
        t_lo = T(0);
      } else {
        detail::advance_time(t, t_lo, h_try);
      }
      ++r.accepted;
      h = h_try * T(controller.accepted(err));
      if (h > h_max) h = h_max;
      stepper.accept(sys, cur, t);
      if (!all_finite(stepper.derivative())) [[unlikely]] {
        stop = outcome_kind::non_finite;
        break;
      }
      if (!detail::notify_adaptive(observer, r.accepted, static_cast<const T&>(t), static_cast<const T&>(t_lo),
                                   static_cast<const State&>(cur))) {
        stop = outcome_kind::observer_stop;
        break;
      }
      if (last) break;
      if (o.max_steps && r.accepted >= o.max_steps) {
        stop = outcome_kind::step_limit;
        break;
      }
    }
  }
  r.stop = stop;
  r.t = t;
  r.rhs_evals = stepper.rhs_evaluations() + extra;
  if (stop != outcome_kind::success && stop != outcome_kind::observer_stop && !r.failed_at) r.failed_at = t;
  swap(x, cur);
  return r;
}

}  // namespace eulervop::rk
