// The explicit Runge-Kutta methods of a fixed-step run as Butcher tableaux (method.hpp lists them).
//
// A tableau is a tag type (rk4_tableau, rkf45_tableau, dp45_tableau, rk8_tableau) with its
// method, name, declared order and number of stages, coefficients<T>(), which builds the Butcher
// coefficients in T from integers (T(1)/T(6)), never from double literals, and the pattern of its
// non-zero coefficients as a compile-time constant, from which the stage loop
// (detail/stage_loop.hpp) drops the zero terms.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/rk/detail/butcher_dop853.hpp>
#include <eulervop/rk/method.hpp>

#include <array>
#include <cstddef>
#include <initializer_list>
#include <string_view>
#include <utility>

namespace eulervop::rk {

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

struct rk4_tableau {
  static constexpr method id = method::rk4;
  static constexpr std::string_view name = method_name(id);
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
// error estimate of adaptive runs (embedded_pairs.hpp).
struct rkf45_tableau {
  static constexpr method id = method::rkf45;
  static constexpr std::string_view name = method_name(id);
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

// Dormand-Prince 5(4), 5th-order solution; the FSAL 7th stage is dropped (see method.hpp).
struct dp45_tableau {
  static constexpr method id = method::dp45;
  static constexpr std::string_view name = method_name(id);
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
  static constexpr std::string_view name = method_name(id);
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
constexpr decltype(auto) dispatch_method(method m, F&& f) {
  switch (m) {
    case method::rk4: return std::forward<F>(f)(rk4_tableau{});
    case method::rkf45: return std::forward<F>(f)(rkf45_tableau{});
    case method::dp45: return std::forward<F>(f)(dp45_tableau{});
    case method::rk8:
    case method::dop853: break;
  }
  return std::forward<F>(f)(rk8_tableau{});
}

// The order of the method (dop853: that of rk8, the solution it advances).
constexpr int declared_order(method m) {
  return dispatch_method(m, [](auto tag) { return decltype(tag)::order; });
}
// Stages of one fixed step (dop853: those of rk8).
constexpr std::size_t stage_count(method m) {
  return dispatch_method(m, [](auto tag) { return decltype(tag)::stages; });
}

}  // namespace eulervop::rk
