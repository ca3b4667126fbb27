// The embedded Runge-Kutta pairs of the adaptive runs (HNW I = Hairer, Norsett, Wanner, Solving
// ODEs I, 2nd ed., Section II.4-II.5, II.10):
//   rkf45_pair   Fehlberg 4(5), 6 stages, advances with the 5th-order weights (local
//                extrapolation); estimate = difference to the 4th-order weights, O(h^5).
//   dp45_pair    Dormand-Prince 5(4), 7 stages with FSAL: the 7th stage is f at the new state and
//                the next step's first, so 6 new evaluations per accepted step; estimate O(h^5).
//   dop853_pair  the 12-stage 8th-order method of DOP853 with its two embedded estimators,
//                err5 (a 5th-order difference) and err3 (3rd order), combined as in dop853.f:
//                err = err5^2 / sqrt(err5^2 + 0.01 err3^2), which behaves like O(h^8). FSAL: the
//                new state's derivative is evaluated once after acceptance (12 evaluations per
//                accepted step, 11 per rejected one).
// A pair is a tag type like a tableau (tableaux.hpp), with the weights e_j of its error estimate
// h sum_j e_j (k_j - k_1), sum_j e_j = 0 (embedded_rk.hpp), and their non-zero pattern.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/rk/detail/butcher_dop853.hpp>
#include <eulervop/rk/method.hpp>
#include <eulervop/rk/tableaux.hpp>

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string_view>
#include <utility>

namespace eulervop::rk {

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
  static constexpr std::string_view name = method_name(id);
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
  static constexpr std::string_view name = method_name(id);
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
  static constexpr std::string_view name = method_name(id);
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

}  // namespace eulervop::rk
