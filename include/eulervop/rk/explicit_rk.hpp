// Explicit Runge-Kutta methods from Butcher tableaux, at a fixed step.
//
// Concepts, in the manner of Boost.Odeint:
//   - system:  sys(const State& x, State& dxdt, const T& t)   (no return value used)
//   - state:   a fixed-shape container of T. Supported out of the box: anything indexable with
//              size() and operator[] (std::array<T, N>, eulervop::vec3<T>, ...) and plain
//              aggregates whose fields are all T (through Boost.PFR), e.g.
//                template <class T> struct planar { T x, y; };
//              Other types: specialize eulervop::rk::state_traits<State>.
//   - tableau: a tag type (rk4_tableau, rkf45_tableau, dp45_tableau, rk8_tableau) with a name, the
//              declared order, the number of stages, coefficients<T>(), which builds the Butcher
//              coefficients in T from integers (T(1)/T(6)), never from double literals, and the
//              pattern of its non-zero coefficients as a compile-time constant.
//
// The stepping loop is statically typed on the tableau, the state and the scalar, and unrolled
// over the stages at compile time: zero coefficients cost nothing, and for a trivially copyable
// state (std::array<double, 3>) the stage derivatives live on the stack, where the compiler keeps
// them in registers. No heap allocation (for MPFR, whose values allocate, the stage storage is
// made once, at construction) and no virtual call per step. The run-time choice of method is a
// switch that hands a generic lambda the concrete tableau tag (dispatch_method), once per run.
//
// Methods (stages = right-hand-side evaluations per step; FSAL is not used in fixed stepping):
//   rk4     classical Runge-Kutta, order 4, 4 stages.
//   rkf45   Fehlberg 4(5), advancing with its 5th-order weights (our reading of the paper's
//           "Runge-Kutta 4/5"), order 5, 6 stages. HNW I, Table II.5.1.
//   dp45    Dormand-Prince 5(4), advancing with the 5th-order solution, order 5, 6 stages. The
//           pair's 7th stage (FSAL, a7j = bj, b7 = 0) serves only the embedded 4th-order error
//           estimate, which a fixed-step run never uses, so it is not evaluated. HNW I, Table II.5.2.
//   rk8     the 8th-order 12-stage method of DOP853 (Hairer & Wanner). See
//           detail/butcher_dop853.hpp for which coefficients are exact and which carry the ~30
//           digits printed in dop853.f.
//   dop853  rk8 with DOP853's embedded 5th- and 3rd-order error estimators: an adaptive method
//           (adaptive_runge_kutta.hpp). At a fixed step it is rk8.
// HNW I = E. Hairer, S. P. Norsett, G. Wanner, Solving Ordinary Differential Equations I, 2nd ed.
#pragma once

#include <eulervop/rk/detail/butcher_dop853.hpp>
#include <eulervop/core/outcome.hpp>
#include <eulervop/core/scalar.hpp>

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
template <scalar T, std::size_t S>
struct butcher_tableau {
  static constexpr std::size_t stages = S;
  std::array<std::array<T, S>, S> a{};
  std::array<T, S> b{};
  std::array<T, S> c{};
};

// Which coefficients of a tableau are non-zero, known at compile time so that the unrolled stage
// loop skips the zeros. tests/test_runge_kutta.cpp checks every pattern against the coefficients.
template <std::size_t S>
struct sparsity {
  std::array<std::array<bool, S>, S> a{};
  std::array<bool, S> b{};

  // Every entry below the diagonal and every weight non-zero, except the listed weights.
  static constexpr sparsity dense(std::initializer_list<std::size_t> zero_weights = {}) {
    sparsity p;
    for (std::size_t i = 0; i < S; ++i) {
      for (std::size_t j = 0; j < i; ++j) p.a[i][j] = true;
      p.b[i] = true;
    }
    for (std::size_t j : zero_weights) p.b[j] = false;
    return p;
  }
};

enum class method { rk4, rkf45, dp45, rk8, dop853 };

// The methods of a fixed-step run, and those with an embedded error estimate (adaptive runs).
inline constexpr std::array<method, 4> fixed_step_methods = {method::rk4, method::rkf45, method::dp45,
                                                             method::rk8};
inline constexpr std::array<method, 3> adaptive_methods = {method::rkf45, method::dp45, method::dop853};
inline constexpr std::array<method, 5> all_methods = {method::rk4, method::rkf45, method::dp45, method::rk8,
                                                      method::dop853};

struct rk4_tableau {
  static constexpr method id = method::rk4;
  static constexpr std::string_view name = "rk4";
  static constexpr int order = 4;
  static constexpr std::size_t stages = 4;
  static constexpr sparsity<stages> nonzero = [] {
    sparsity<stages> p;
    p.a[1][0] = p.a[2][1] = p.a[3][2] = true;
    p.b = {true, true, true, true};
    return p;
  }();

  template <scalar T>
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

// Fehlberg's 4(5) pair, advanced with the 5th-order weights. The 4th-order weights serve the
// error estimate of adaptive runs (adaptive_runge_kutta.hpp).
struct rkf45_tableau {
  static constexpr method id = method::rkf45;
  static constexpr std::string_view name = "rkf45";
  static constexpr int order = 5;
  static constexpr std::size_t stages = 6;
  static constexpr sparsity<stages> nonzero = sparsity<stages>::dense({1});

  template <scalar T>
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
  // The 4th-order weights (25/216, 0, 1408/2565, 2197/4104, -1/5, 0).
  template <scalar T>
  static std::array<T, stages> embedded_weights() {
    const auto q = [](int n, int d) { return T(n) / T(d); };
    return {q(25, 216), T(0), q(1408, 2565), q(2197, 4104), q(-1, 5), T(0)};
  }
};

// Dormand-Prince 5(4), 5th-order solution; the FSAL 7th stage is dropped (see the header note).
struct dp45_tableau {
  static constexpr method id = method::dp45;
  static constexpr std::string_view name = "dp45";
  static constexpr int order = 5;
  static constexpr std::size_t stages = 6;
  static constexpr sparsity<stages> nonzero = sparsity<stages>::dense({1});

  template <scalar T>
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
  // The 4th-order weights of the 7-stage pair (the 7th stage is f at the new state):
  // (5179/57600, 0, 7571/16695, 393/640, -92097/339200, 187/2100, 1/40).
  template <scalar T>
  static std::array<T, stages + 1> embedded_weights() {
    const auto q = [](int n, int d) { return T(n) / T(d); };
    return {q(5179, 57600), T(0), q(7571, 16695), q(393, 640), q(-92097, 339200), q(187, 2100), q(1, 40)};
  }
};

// DOP853's 8th-order method (12 stages; the 13th evaluation of dop853.f is FSAL/error estimate).
struct rk8_tableau {
  static constexpr method id = method::rk8;
  static constexpr std::string_view name = "rk8";
  static constexpr int order = 8;
  static constexpr std::size_t stages = 12;
  // Row 1 (of 0..11) uses stage 0; row 2 stages 0, 1; rows 3.. skip stages 1 and 2 (and row 3
  // stage 1, rows 4.. stage 2 too). The weights b2..b5 (1-based) are zero.
  static constexpr sparsity<stages> nonzero = [] {
    sparsity<stages> p;
    p.a[1][0] = true;
    p.a[2][0] = p.a[2][1] = true;
    p.a[3][0] = p.a[3][2] = true;
    p.a[4][0] = p.a[4][2] = p.a[4][3] = true;
    for (std::size_t i = 5; i < stages; ++i) {
      p.a[i][0] = true;
      for (std::size_t j = 3; j < i; ++j) p.a[i][j] = true;
    }
    p.b = {true, false, false, false, false, true, true, true, true, true, true, true};
    return p;
  }();

  template <scalar T>
  static butcher_tableau<T, stages> coefficients() {
    butcher_tableau<T, stages> t;
    detail::fill_dop853<butcher_tableau<T, stages>, T>(t);
    return t;
  }
};

// Calls f(Tag{}) with the concrete tableau tag of m and returns its result; every branch must
// return the same type. This is the only run-time branch on the method. dop853 at a fixed step
// is rk8.
template <class F>
decltype(auto) dispatch_method(method m, F&& f) {
  switch (m) {
    case method::rk4: return std::forward<F>(f)(rk4_tableau{});
    case method::rkf45: return std::forward<F>(f)(rkf45_tableau{});
    case method::dp45: return std::forward<F>(f)(dp45_tableau{});
    case method::rk8:
    case method::dop853: break;
  }
  return std::forward<F>(f)(rk8_tableau{});
}

constexpr std::string_view method_name(method m) {
  switch (m) {
    case method::rk4: return rk4_tableau::name;
    case method::rkf45: return rkf45_tableau::name;
    case method::dp45: return dp45_tableau::name;
    case method::rk8: return rk8_tableau::name;
    case method::dop853: return "dop853";
  }
  return "?";
}
constexpr int declared_order(method m) {
  switch (m) {
    case method::rk4: return rk4_tableau::order;
    case method::rkf45: return rkf45_tableau::order;
    case method::dp45: return dp45_tableau::order;
    case method::rk8:
    case method::dop853: return rk8_tableau::order;
  }
  return 0;
}
// Stages of one fixed step (dop853: those of rk8).
constexpr std::size_t stage_count(method m) {
  switch (m) {
    case method::rk4: return rk4_tableau::stages;
    case method::rkf45: return rkf45_tableau::stages;
    case method::dp45: return dp45_tableau::stages;
    case method::rk8:
    case method::dop853: return rk8_tableau::stages;
  }
  return 0;
}
// True for the methods with an embedded error estimate.
constexpr bool is_adaptive(method m) { return m == method::rkf45 || m == method::dp45 || m == method::dop853; }
// True for the methods of a fixed-step run (dop853 is run adaptively; at a fixed step it is rk8).
constexpr bool is_fixed_step(method m) { return m != method::dop853; }

// "rk4", "rkf45", "dp45", "rk8", "dop853" (exact, lower case); nullopt otherwise.
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
  [[gnu::always_inline]] static void for_each_index(const State& s, F&& f) {
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

template <scalar T>
bool is_finite_value(const T& v) {
  using std::isfinite;
  return static_cast<bool>(isfinite(v));  // unqualified: ADL finds boost::multiprecision::isfinite
}

// True when every component is finite.
template <class State>
bool all_finite(const State& x) {
  bool ok = true;
  state_traits<State>::for_each_index(x, [&](auto i) __attribute__((always_inline)) {
    ok = ok && is_finite_value(state_traits<State>::get(x, i));
  });
  return ok;
}

namespace detail {
// True when some component lies outside [lo, hi]. NaN is never outside.
template <class State, scalar T>
bool outside_band(const State& x, const T& lo, const T& hi) {
  bool out = false;
  state_traits<State>::for_each_index(x, [&](auto i) __attribute__((always_inline)) {
    const auto& v = state_traits<State>::get(x, i);
    out = out || v > hi || v < lo;
  });
  return out;
}
}  // namespace detail

// True when some component has |x_i| > bound, i.e. the max-norm exceeds bound.
template <class State, scalar T>
bool exceeds_max_norm(const State& x, const T& bound) {
  const T lo = -bound;
  return detail::outside_band(x, lo, bound);
}

// ---- the stage loop -----------------------------------------------------------------------------

namespace detail {

// Calls f(std::integral_constant<std::size_t, I>{}) for I = First, ..., Last - 1.
template <std::size_t First, std::size_t Last, class F>
[[gnu::always_inline]] constexpr void static_for(F&& f) {
  if constexpr (First < Last) {
    f(std::integral_constant<std::size_t, First>{});
    static_for<First + 1, Last>(f);
  }
}

// The first j < End with mask[j] set (End if none).
template <std::size_t S>
constexpr std::size_t first_set(const std::array<bool, S>& mask, std::size_t begin, std::size_t end) {
  for (std::size_t j = begin; j < end; ++j)
    if (mask[j]) return j;
  return end;
}

// Where one step keeps its stage derivatives and temporaries. A trivially copyable state and
// scalar (double, std::array<double, N>) gets a fresh work area on the stack for every step:
// the compiler then sees that nothing else can touch it and keeps it in registers. Other types
// (MPFR values allocate) use one kept for the stepper's lifetime.
template <class State, scalar T, std::size_t S>
struct stage_work {
  std::array<State, S> k;  // stage derivatives
  State tmp;               // stage input
  T ts{}, acc{}, dk{}, inc{}, bb{};
  stage_work() = default;
  explicit stage_work(const State& shape) : tmp(shape) { k.fill(shape); }
};

template <class State, scalar T>
inline constexpr bool work_on_stack = std::is_trivially_copyable_v<State> && std::is_trivially_copyable_v<T>;

// k[0..S) at (t, x) for the tableau `tab` with non-zero pattern `nz`:
//   k_s = f(t + c_s h, x + h sum_{j<s} a_sj k_j),
// the sum in increasing j and formed in place (no MPFR temporary). Only stages From..S-1 are
// evaluated; k[0..From) must hold already (FSAL).
template <std::size_t S, const sparsity<S>& nz, std::size_t From = 0, class System, class State, scalar T>
[[gnu::always_inline]] inline void compute_stages(System& sys, const butcher_tableau<T, S>& tab, const State& x, const T& t, const T& h,
                    stage_work<State, T, S>& w) {
  using traits = state_traits<State>;
  if constexpr (From == 0) sys(x, w.k[0], t);
  static_for<(From > 1 ? From : 1), S>([&](auto s) __attribute__((always_inline)) {
    constexpr std::size_t first = first_set<S>(nz.a[s], 0, s);
    traits::for_each_index(x, [&](auto i) __attribute__((always_inline)) {
      auto& y = traits::get(w.tmp, i);
      if constexpr (first == s) {
        y = traits::get(x, i);
      } else {
        y = tab.a[s][first] * traits::get(w.k[first], i);
        static_for<first + 1, s>([&](auto j) __attribute__((always_inline)) {
          if constexpr (nz.a[s][j]) y += tab.a[s][j] * traits::get(w.k[j], i);
        });
        y *= h;
        y += traits::get(x, i);
      }
    });
    w.ts = tab.c[s] * h;
    w.ts += t;
    sys(static_cast<const State&>(w.tmp), w.k[s], static_cast<const T&>(w.ts));
  });
}

// y = h sum_j b_j k_j[i], formed as h (k_1 + sum_{j>1} b_j (k_j - k_1)). The two are equal
// because sum_j b_j = 1 (consistency), but the second is exact when all stages agree: a
// constant derivative (torque-free VOP: u' = c2) then advances by exactly h k_1 instead of
// h k_1 (sum_j b_j rounded), which would drift systematically over 1e5 steps.
template <std::size_t S, const sparsity<S>& nz, class State, scalar T, class Index>
[[gnu::always_inline]] inline void weighted_increment(const std::array<T, S>& b, Index i, const T& h, stage_work<State, T, S>& w, T& y) {
  using traits = state_traits<State>;
  const T& k1 = traits::get(w.k[0], i);
  constexpr std::size_t first = first_set<S>(nz.b, 1, S);
  if constexpr (first == S) {
    y = k1;
  } else {
    w.dk = traits::get(w.k[first], i);
    w.dk -= k1;
    y = b[first] * w.dk;
    static_for<first + 1, S>([&](auto j) __attribute__((always_inline)) {
      if constexpr (nz.b[j]) {
        w.dk = traits::get(w.k[j], i);
        w.dk -= k1;
        y += b[j] * w.dk;
      }
    });
    y += k1;
  }
  y *= h;
}

}  // namespace detail

// ---- the stepper --------------------------------------------------------------------------------

// One explicit Runge-Kutta method, fixed step, generic over state, scalar and system.
// For MPFR, construct it inside the mpfr_precision_scope of the run: the coefficients and the
// stage storage take the thread's precision at construction.
template <class Tableau, class State, scalar T = state_value_t<State>>
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
      : tab_(Tableau::template coefficients<T>()), work_(shape), out_(shape) {}

  const butcher_tableau<T, stages>& coefficients() const { return tab_; }

  // Right-hand-side evaluations since construction (= stages x steps).
  std::size_t rhs_evaluations() const { return evals_; }

  // out = one step of size h from (t, x). out must not alias x.
  template <class System>
  [[gnu::always_inline]] void do_step(System& sys, const State& x, const T& t, const T& h, State& out) {
    if constexpr (detail::work_on_stack<State, T>) {
      work_type w;
      step(w, sys, x, t, h, out, nullptr);
    } else {
      step(work_, sys, x, t, h, out, nullptr);
    }
  }

  // The same step with compensated summation of the state (TwoSum, Knuth TAOCP 4.2.2): `comp`
  // carries the rounding error of x + increment from step to step, so over n steps the state
  // loses O(eps) instead of O(sqrt(n) eps). Long fixed-step runs (1e5 steps) need it: without
  // it a torque-free VOP phase u = c2 tau drifts by ~sqrt(n) ulp(u) although each increment is
  // exact to rounding.
  template <class System>
  [[gnu::always_inline]] void do_step(System& sys, const State& x, const T& t, const T& h, State& out, State& comp) {
    if constexpr (detail::work_on_stack<State, T>) {
      work_type w;
      step(w, sys, x, t, h, out, &comp);
    } else {
      step(work_, sys, x, t, h, out, &comp);
    }
  }

  // In-place variant: x <- one step from (t, x). Uses an internal buffer.
  template <class System>
  void do_step(System& sys, State& x, const T& t, const T& h) {
    do_step(sys, static_cast<const State&>(x), t, h, out_);
    using std::swap;
    swap(x, out_);
  }

 private:
  using work_type = detail::stage_work<State, T, stages>;

  // The step in the work area w: the stages, then out = x + increment (compensated when comp
  // is given). Inlined into do_step so that a work area on the stack stays in registers.
  template <class System>
  [[gnu::always_inline]] void step(work_type& w, System& sys, const State& x, const T& t, const T& h, State& out,
                                   State* comp) {
    using traits = state_traits<State>;
    detail::compute_stages<stages, Tableau::nonzero>(sys, tab_, x, t, h, w);
    evals_ += stages;
    traits::for_each_index(x, [&](auto idx) __attribute__((always_inline)) {
      auto& y = traits::get(out, idx);
      if (comp) {
        detail::weighted_increment<stages, Tableau::nonzero>(tab_.b, idx, h, w, w.inc);
        compensated_add(traits::get(x, idx), w, traits::get(*comp, idx), y);
      } else {
        detail::weighted_increment<stages, Tableau::nonzero>(tab_.b, idx, h, w, y);
        y += traits::get(x, idx);
      }
    });
  }

  // y = x0 + (w.inc + c), with c updated to the rounding error of that sum (TwoSum).
  static void compensated_add(const T& x0, work_type& w, T& c, T& y) {
    w.inc += c;
    y = x0 + w.inc;
    w.bb = y - x0;
    c = x0 - (y - w.bb);
    c += w.inc - w.bb;
  }

  butcher_tableau<T, stages> tab_;
  work_type work_;  // used only when the state cannot live on the stack (see stage_work)
  State out_;
  std::size_t evals_ = 0;
};

// ---- the fixed-step driver ----------------------------------------------------------------------

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
