// Long hard case of the reference generator (CTest label "long"): a span of 1e4.
// Torque-free k = 0.5 (Omega0 = (0.5, 0, 1), ~1500 periods 4K) in quad against the exact
// Eq. 12 solution by Boost.Math jacobi_elliptic in MPFR at 256 bits (dn stabilised as
// sqrt(1 - k^2 sn^2), docs/design.md section 2).
#include <eulervop/reference/integrate.hpp>
#include <eulervop/core/scalar.hpp>

#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <limits>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;

TEST(LongHardReference, SpanOf1e4QuadAgreesWithExactEq12) {
  eulervop::euler_problem<quad> p;
  p.torque.G = {quad(0), quad(0), quad(0)};
  p.Omega0 = {quad(0.5), quad(0), quad(1)};  // c1 = 0.5, c2 = 1, u(0) = 0: exact in every type
  const auto t0 = std::chrono::steady_clock::now();
  eulervop::picard_stats stats;
  const auto q = eulervop::integrate_reference<quad>(p, quad(10000), {}, {}, &stats);
  const double tq = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  eulervop::mpfr_precision_scope scope(256);
  const mpfr_real k = mpfr_real(1) / 2;
  double worst = 0, worst_tau = 0, at_1e3 = 0;
  for (int i = 0; i <= 4000; ++i) {  // tau = 2.5 i, exact in both
    const mpfr_real tau = mpfr_real(i) * 5 / 2;
    mpfr_real cn, dn;
    const mpfr_real sn = boost::math::jacobi_elliptic(k, tau, &cn, &dn);
    const mpfr_real exact[3] = {cn / 2, sn / 2, sqrt(1 - k * k * sn * sn)};
    const auto Om = q(quad(i) * 5 / 2);
    mpfr_real s = 0;
    for (int c = 0; c < 3; ++c) s += (mpfr_real(Om[c]) - exact[c]) * (mpfr_real(Om[c]) - exact[c]);
    const double e = static_cast<double>(sqrt(s));
    if (i <= 400) at_1e3 = std::max(at_1e3, e);
    if (e > worst) {
      worst = e;
      worst_tau = 2.5 * i;
    }
  }
  const double eps = static_cast<double>(std::numeric_limits<quad>::epsilon());
  std::printf("torque-free k = 0.5 to tau 1e4: quad %.1f s (%zu segments); max |quad - exact| %.3e (%.3g eps) at tau "
              "%.6g; to tau 1e3: %.3e\n",
              tq, stats.segments, worst, worst / eps, worst_tau, at_1e3);
  EXPECT_LE(worst, 1e-28);
}

}  // namespace
