// Tests of the adaptive Runge-Kutta methods: include/eulervop/rk/ embedded_pairs.hpp,
// embedded_rk.hpp, error_norm.hpp, pi_controller.hpp and adaptive_driver.hpp.
//
// Reference values and their provenance:
//   - rotation x1' = -x2, x2' = x1: exact solution (cos t, sin t).
//   - normalized Euler equations (Eq. 5), the paper's scene G = (1,1,1), Omega(0) = (0.5, 0, 1):
//     the quad Chebyshev-Picard reference (eulervop::oracle, about 1e-31 here; its own accuracy
//     is tested in test_chebyshev_picard.cpp).
//   - x' = x^2, x(0) = 1: blows up at t = 1 exactly.
//   - x' = (1, 2, 3): exact x = x0 + t (1, 2, 3).
// Bounds: weight sums in multiples of epsilon<T>() (or the ~1e-30 of the dop853.f decimals where
// they enter); observed orders within 0.3 of the declared ones; tolerance proportionality: the
// global error of a pair whose estimate is O(h^(q+1)) and which advances with the higher order
// scales like tol^1 (error per step controlled, local extrapolation; HNW I, II.4), so the fitted
// slope of log(error) against log(tol) must lie in [0.8, 1.2].
#include "rk_test_systems.hpp"
#include "slope_test_support.hpp"
#include "type_test_names.hpp"

#include <eulervop/core/scalar.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/oracle.hpp>
#include <eulervop/rk/adaptive_driver.hpp>
#include <eulervop/rk/embedded_pairs.hpp>
#include <eulervop/rk/embedded_rk.hpp>
#include <eulervop/rk/error_norm.hpp>
#include <eulervop/rk/method.hpp>
#include <eulervop/rk/pi_controller.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace {

using eulervop::epsilon;
using eulervop::mpfr_precision_scope;
using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;
namespace rk = eulervop::rk;
using eulervop::rk_test::euler_system;
using eulervop::rk_test::rotation;

using all_pairs = ::testing::Types<rk::rkf45_pair, rk::dp45_pair, rk::dop853_pair>;

// ---- coefficients ---------------------------------------------------------------------------------

template <class Pair>
struct EmbeddedPair : ::testing::Test {};
TYPED_TEST_SUITE(EmbeddedPair, all_pairs, method_test_names);

// Every estimate is h sum e_j (k_j - k_1) with sum e_j = 0, which is what makes it vanish for a
// constant derivative. In T: rational weights to stages epsilon<T>(); DOP853's er_j are the
// dop853.f decimals (28 digits) and its b the ~30-digit decimals, so their sums hold to 1e-27.
TYPED_TEST(EmbeddedPair, ErrorWeightsSumToZeroInEveryPrecision) {
  using Pair = TypeParam;
  auto check = [](auto zero) {
    using T = decltype(zero);
    using std::abs;
    const T tol = Pair::id == rk::method::dop853 ? std::max<T>(T(Pair::stages) * epsilon<T>(), rk::detail::decimal<T>("1e-27"))
                                                  : T(Pair::stages) * epsilon<T>();
    T s = 0, mag = 0;
    for (const T& e : Pair::template error_weights<T>()) {
      s += e;
      mag += abs(e);
    }
    EXPECT_LE(abs(s) / mag, tol) << Pair::name;
    if constexpr (Pair::two_estimates) {
      T s2 = 0, mag2 = 0;
      for (const T& e : Pair::template second_error_weights<T>()) {
        s2 += e;
        mag2 += abs(e);
      }
      EXPECT_LE(abs(s2) / mag2, tol) << Pair::name << " (3rd-order estimate)";
    }
    // The error weights are zero exactly where error_nonzero says.
    const auto e = Pair::template error_weights<T>();
    for (std::size_t j = 0; j < Pair::stages; ++j) EXPECT_EQ(e[j] != 0, Pair::error_nonzero[j]) << j;
  };
  check(double{});
  check(quad{});
  mpfr_precision_scope scope(200);
  check(mpfr_real{});
}

// The non-zero pattern the stage loop relies on matches the coefficients. rkf45 and dop853 reuse
// the patterns of their tableaux (checked in test_runge_kutta.cpp); dp45's seven-stage pattern
// with the FSAL row is its own.
TEST(EmbeddedPair, Dp45SparsityPatternMatchesTheCoefficients) {
  using Pair = rk::dp45_pair;
  const auto tab = Pair::coefficients<double>();
  for (std::size_t i = 0; i < Pair::stages; ++i) {
    for (std::size_t j = 0; j < Pair::stages; ++j) EXPECT_EQ(tab.a[i][j] != 0, Pair::nonzero.a[i][j]) << i << "," << j;
    EXPECT_EQ(tab.b[i] != 0, Pair::nonzero.b[i]) << i;
  }
}

// dp45's 7th row is the 5th-order weights and c_7 = 1: its stage is f at the new state (FSAL).
TEST(EmbeddedPair, Dp45SeventhStageIsTheNewState) {
  const auto t = rk::dp45_pair::coefficients<quad>();
  for (std::size_t j = 0; j < 7; ++j) EXPECT_EQ(t.a[6][j], t.b[j]) << j;
  EXPECT_EQ(t.c[6], quad(1));
  EXPECT_EQ(t.b[6], quad(0));
}

// The estimate of one step from the same state falls like h^(estimate_order + 1): halving h
// divides it by 2^5 (rkf45, dp45) or, for DOP853's combined estimate err5^2 / sqrt(err5^2 +
// 0.01 err3^2) ~ h^12 / h^4, by 2^8. In quad, on the rotation, atol = 1, rtol = 0 (the plain
// RMS of the estimate).
TYPED_TEST(EmbeddedPair, EstimateHasItsDeclaredOrder) {
  using Pair = TypeParam;
  using S = std::array<quad, 2>;
  const S x{quad("0.6"), quad("0.8")};
  const rk::hairer_scale<quad> plain{quad(1), quad(0)};
  auto estimate = [&](const quad& h) {
    rk::embedded_rk<Pair, S> stepper(x);
    rotation sys;
    stepper.prime(sys, x, quad(0));
    S out = x, comp{0, 0}, comp_out{0, 0};
    return stepper.attempt(sys, x, quad(0), h, out, comp, comp_out, plain);
  };
  const quad h0 = Pair::id == rk::method::dop853 ? quad("0.05") : quad("0.02");
  const double e1 = estimate(h0), e2 = estimate(h0 / 2), e4 = estimate(h0 / 4);
  const double p1 = std::log2(e1 / e2), p2 = std::log2(e2 / e4);
  std::printf("  %-6s estimate %.3e %.3e %.3e  order %.3f %.3f (expected %d)\n", std::string(Pair::name).c_str(), e1,
              e2, e4, p1, p2, Pair::estimate_order + 1);
  EXPECT_NEAR(p1, Pair::estimate_order + 1, 0.3);
  EXPECT_NEAR(p2, Pair::estimate_order + 1, 0.3);
}

// ---- the controller -----------------------------------------------------------------------------

// The fast log2/exp2 of the controller against libm, over the range a controller sees.
// A step factor needs two or three digits; the controller's log2 and 2^x give six.
TEST(PiController, FastLogAndExpAreAccurateToSixDigits) {
  double worst_log = 0, worst_exp = 0;
  for (double x = 1e-30; x < 1e30; x *= 1.37) {
    worst_log = std::max(worst_log, std::abs(rk::detail::approx_log2(x) - std::log2(x)));
  }
  for (double y = -60; y < 60; y += 0.0137) {
    worst_exp = std::max(worst_exp, std::abs(rk::detail::approx_exp2(y) / std::exp2(y) - 1));
  }
  std::printf("  log2 absolute error %.2e, exp2 relative error %.2e\n", worst_log, worst_exp);
  EXPECT_LE(worst_log, 3e-6);
  EXPECT_LE(worst_exp, 1e-6);
}

TEST(PiController, FactorsStayInTheirBoundsAndDoNotGrowAfterARejection) {
  rk::pi_controller c(5);
  EXPECT_EQ(c.accepted(0.0), rk::pi_controller::fac_max);  // no measurable error: the largest
  // err = 1 after err = 0 (remembered as 1e-4): 0.9 (1e-4)^beta, beta = 0.4/5.
  EXPECT_NEAR(c.accepted(1.0), 0.9 * std::pow(1e-4, 0.4 / 5), 1e-6);
  for (double err : {1e-12, 1e-3, 0.5, 1.0}) {
    const double f = c.accepted(err);
    EXPECT_GE(f, rk::pi_controller::fac_min);
    EXPECT_LE(f, rk::pi_controller::fac_max);
  }
  const double r = c.rejected(30.0);
  EXPECT_GE(r, rk::pi_controller::fac_min);
  EXPECT_LT(r, 1.0);
  EXPECT_EQ(c.rejected(std::numeric_limits<double>::quiet_NaN()), rk::pi_controller::fac_min);
  EXPECT_LE(c.accepted(1e-9), 1.0) << "the step after a rejection must not grow";
  EXPECT_GT(c.accepted(1e-9), 1.0) << "and the one after that may";
}

// ---- the driver -----------------------------------------------------------------------------------

template <class Pair>
struct AdaptiveDriver : ::testing::Test {};
TYPED_TEST_SUITE(AdaptiveDriver, all_pairs, method_test_names);

// A constant derivative: every estimate is exactly zero, every step but the last is h_max, the
// result is exact, and nothing is rejected.
TYPED_TEST(AdaptiveDriver, ConstantDerivativeTakesTheMaximumStepEverywhere) {
  using Pair = TypeParam;
  auto sys = [](const vec3<double>&, vec3<double>& dx, double) { dx = {1, 2, 3}; };
  vec3<double> x{0.5, -1, 2};
  rk::adaptive_options<double> o;
  o.atol = o.rtol = 1e-12;
  o.h_max = 0.75;
  std::vector<double> times;
  const auto r = rk::integrate_adaptive<Pair>(sys, x, 0.0, 100.0, o,
                                              [&](std::size_t, double t, double, const vec3<double>&) { times.push_back(t); });
  EXPECT_EQ(r.stop, eulervop::outcome_kind::success);
  EXPECT_EQ(r.rejected, 0u);
  ASSERT_EQ(r.accepted, 134u);  // 133 steps of 0.75, then 0.25
  for (std::size_t i = 1; i + 1 < times.size(); ++i) EXPECT_EQ(times[i] - times[i - 1], 0.75) << i;
  EXPECT_EQ(times.back(), 100.0);
  EXPECT_EQ(x[0], 100.5);
  EXPECT_EQ(x[1], 199.0);
  EXPECT_EQ(x[2], 302.0);
}

// Every evaluation is counted: the first derivative and the starting-step trial (2), then
// stages - 1 new ones per attempted step, plus the derivative at each accepted state for the
// pairs without a stage there (rkf45, dop853); dp45's 7th stage is that derivative.
TYPED_TEST(AdaptiveDriver, RhsEvaluationsAreCountedExactly) {
  using Pair = TypeParam;
  std::size_t calls = 0;
  const auto euler = euler_system<double>({1, 1, 1});
  auto counting = [&](const vec3<double>& x, vec3<double>& dx, double t) {
    ++calls;
    euler(x, dx, t);
  };
  vec3<double> x{0.5, 0, 1};
  rk::adaptive_options<double> o;
  o.atol = o.rtol = 1e-7;
  const auto r = rk::integrate_adaptive<Pair>(counting, x, 0.0, 20.0, o);
  ASSERT_EQ(r.stop, eulervop::outcome_kind::success);
  EXPECT_EQ(r.rhs_evals, calls);
  const std::size_t attempts = r.accepted + r.rejected;
  const std::size_t expected = Pair::stages == 7 ? 2 + 6 * attempts : 2 + (Pair::stages - 1) * attempts + r.accepted;
  EXPECT_EQ(calls, expected) << Pair::name << " accepted " << r.accepted << " rejected " << r.rejected;
}

// The global error on the paper's scene (tau in [0, 20], spin-up included) falls in proportion
// to the tolerance (see the header note).
TYPED_TEST(AdaptiveDriver, GlobalErrorIsProportionalToTheTolerance) {
  using Pair = TypeParam;
  const eulervop::oracle::reference<quad> ref(eulervop::oracle::problem<quad>({1, 1, 1}, {quad("0.5"), 0, 1}), quad(20));
  const auto sys = euler_system<double>({1, 1, 1});
  std::vector<double> log_tol, log_err;
  for (double tol : {1e-5, 1e-7, 1e-9, 1e-11}) {
    vec3<double> x{0.5, 0, 1};
    double worst = 0;
    rk::adaptive_options<double> o;
    o.atol = o.rtol = tol;
    const auto r = rk::integrate_adaptive<Pair>(sys, x, 0.0, 20.0, o, [&](std::size_t, double t, double lo, const vec3<double>& y) {
      worst = std::max(worst, ref.error(quad(t) + quad(lo), y));
    });
    ASSERT_EQ(r.stop, eulervop::outcome_kind::success);
    std::printf("  %-6s tol %.0e: %6zu steps (%zu rejected), max error %.3e\n", std::string(Pair::name).c_str(), tol,
                r.accepted, r.rejected, worst);
    log_tol.push_back(std::log10(tol));
    log_err.push_back(std::log10(worst));
  }
  const double slope = slope_test::least_squares_slope(log_tol, log_err);
  std::printf("  %-6s slope of log(error) on log(tol): %.3f\n", std::string(Pair::name).c_str(), slope);
  EXPECT_GE(slope, 0.8);
  EXPECT_LE(slope, 1.2);
  for (std::size_t i = 1; i < log_err.size(); ++i) EXPECT_LT(log_err[i], log_err[i - 1]) << "errors must fall";
}

// The last step lands on t_end exactly although t is a sum of a million steps.
TEST(AdaptiveDriverTime, LastStepLandsOnTheEndAndTimeIsCompensated) {
  auto sys = [](const std::array<double, 1>&, std::array<double, 1>& dx, double t) { dx[0] = std::cos(t); };
  std::array<double, 1> x{0};
  rk::adaptive_options<double> o;
  o.atol = o.rtol = 1e-6;
  o.h_max = 1e-4;  // 1e6 steps
  double last_t = 0, last_lo = 1;
  const auto r = rk::integrate_adaptive<rk::dp45_pair>(sys, x, 0.0, 100.0, o, [&](std::size_t, double t, double lo, const auto&) {
    last_t = t;
    last_lo = lo;
  });
  EXPECT_EQ(r.stop, eulervop::outcome_kind::success);
  EXPECT_EQ(last_t, 100.0);
  EXPECT_EQ(last_lo, 0.0);
  EXPECT_GE(r.accepted, 1000000u);
  // x(100) = sin(100): the compensated time keeps the phase; uncompensated, the sum of 1e6 steps
  // of 1e-4 drifts by ~1e-12 and the step sizes no longer add up to the span.
  EXPECT_NEAR(x[0], std::sin(100.0), 1e-9);
}

// x' = x^2 blows up at t = 1: the run stops there and says so, keeping a finite state.
TEST(AdaptiveDriverFailure, BlowUpStopsNearTheSingularity) {
  for (rk::method m : rk::adaptive_methods) {
    rk::dispatch_pair(m, [&](auto pair) {
      using Pair = decltype(pair);
      auto sys = [](const std::array<double, 1>& x, std::array<double, 1>& dx, double) { dx[0] = x[0] * x[0]; };
      std::array<double, 1> x{1};
      rk::adaptive_options<double> o;
      o.atol = o.rtol = 1e-8;
      const auto r = rk::integrate_adaptive<Pair>(sys, x, 0.0, 2.0, o);
      std::printf("  %-6s stop %d at t = %.12f after %zu steps, x = %.3e\n", std::string(Pair::name).c_str(),
                  static_cast<int>(r.stop), r.failed_at.value_or(-1), r.accepted, x[0]);
      EXPECT_NE(r.stop, eulervop::outcome_kind::success);
      ASSERT_TRUE(r.failed_at.has_value());
      EXPECT_NEAR(*r.failed_at, 1.0, 1e-3);
      EXPECT_TRUE(std::isfinite(x[0]));
      EXPECT_GT(x[0], 1e3);
    });
  }
  // With a bound, the run stops where |x| passes it (x = 1/(1-t)).
  auto sys = [](const std::array<double, 1>& x, std::array<double, 1>& dx, double) { dx[0] = x[0] * x[0]; };
  std::array<double, 1> x{1};
  rk::adaptive_options<double> o;
  o.atol = o.rtol = 1e-10;
  o.max_norm = 1e4;
  const auto r = rk::integrate_adaptive<rk::dop853_pair>(sys, x, 0.0, 2.0, o);
  EXPECT_EQ(r.stop, eulervop::outcome_kind::norm_bound);
  ASSERT_TRUE(r.failed_at.has_value());
  EXPECT_NEAR(*r.failed_at, 1 - 1e-4, 1e-4);
  EXPECT_LE(x[0], 1e4);
}

// Generic over the scalar: quad runs the same code (and the estimate is exact there too).
TEST(AdaptiveDriverScalar, QuadRunReachesQuadAccuracyOnTheRotation) {
  using S = std::array<quad, 2>;
  S x{1, 0};
  rk::adaptive_options<quad> o;
  o.atol = o.rtol = quad("1e-28");
  const auto r = rk::integrate_adaptive<rk::dop853_pair>(rotation{}, x, quad(0), quad(10), o);
  ASSERT_EQ(r.stop, eulervop::outcome_kind::success);
  const double e = static_cast<double>(fabs(x[0] - cos(quad(10))) + fabs(x[1] - sin(quad(10))));
  std::printf("  dop853 in quad, tol 1e-28: %zu steps, error %.2e\n", r.accepted, e);
  EXPECT_LE(e, 1e-26);  // tol times the ~100x global-to-local factor of a 10-unit run
}

}  // namespace
