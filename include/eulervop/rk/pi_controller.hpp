// The step-size controller of the adaptive runs: Gustafsson's PI controller as in Hairer &
// Wanner, Solving ODEs II, Section IV.2:
//   h_new = h min(fac_max, max(fac_min, safety err_n^(-alpha) err_(n-1)^beta)),
//   alpha = 0.7 / k, beta = 0.4 / k, k = (order of the estimate) + 1,
// safety 0.9, fac_min 0.2, fac_max 10; after a rejected step the next accepted step does not
// grow (HNW I, II.4). A rejected step is retried with h max(fac_min, safety err^(-1/k)).
// HNW I = E. Hairer, S. P. Norsett, G. Wanner, Solving Ordinary Differential Equations I, 2nd ed.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <numbers>

namespace eulervop::rk {

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

}  // namespace eulervop::rk
