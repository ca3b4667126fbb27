// Long accuracy run (CTest label "long"; opt in with EULERVOP_LONG_TESTS=1):
// the paper's scene (Section 3) to tau = 136 in quad against mpfr:256, and the honesty of the
// --verify estimate, whose stricter setting for quad is MPFR at 113 + 64 bits.
#include <eulervop/reference/integrate.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;

template <class T>
std::vector<std::array<std::string, 3>> paper_samples(double tau_end, double* seconds) {
  const int samples = static_cast<int>(tau_end * 16);
  eulervop::euler_problem<T> p;
  p.torque.G = {T(1), T(1), T(1)};
  p.Omega0 = {*eulervop::from_text<T>("0.5"), T(0), T(1)};  // c1 = 0.5, c2 = 1, u = 0 (Eq. 18)
  const auto t0 = std::chrono::steady_clock::now();
  const auto traj = eulervop::integrate_reference<T>(p, T(tau_end));
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<std::array<std::string, 3>> out(samples + 1);
  for (int i = 0; i <= samples; ++i) {
    const auto om = traj(T(i) / 16);
    for (int c = 0; c < 3; ++c) out[i][c] = eulervop::to_text(om[c]);
  }
  return out;
}

// Eq. 20 in MPFR at 400 bits between two sample sets.
double max_eq20(const std::vector<std::array<std::string, 3>>& a,
                const std::vector<std::array<std::string, 3>>& b) {
  eulervop::mpfr_precision_scope scope(400);
  mpfr_real worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    mpfr_real e = 0;
    for (int c = 0; c < 3; ++c) {
      const mpfr_real d = mpfr_real(a[i][c]) - mpfr_real(b[i][c]);
      e += d * d;
    }
    worst = std::max(worst, mpfr_real(sqrt(e)));
  }
  return static_cast<double>(worst);
}

TEST(LongPaperScene, QuadAgreesWithMpfr256AndVerifyIsHonest) {
  // Sample times tau_i = i / 16 (2177 of them) are exact in every type, so both sides are
  // evaluated at the same tau (a rounded tau would move Omega by |Omega'| tau eps ~ 1e-28).
  double tq = 0, tv = 0, tm = 0;
  const auto q = paper_samples<quad>(136.0, &tq);
  std::vector<std::array<std::string, 3>> v, m;
  {
    eulervop::mpfr_precision_scope s(113 + 64);
    v = paper_samples<mpfr_real>(136.0, &tv);
  }
  {
    eulervop::mpfr_precision_scope s(256);
    m = paper_samples<mpfr_real>(136.0, &tm);
  }
  const double truth = max_eq20(q, m);
  const double estimate = max_eq20(q, v);
  std::printf("paper scene to tau=136: quad %.2fs, mpfr:177 %.2fs, mpfr:256 %.2fs\n", tq, tv, tm);
  std::printf("max |quad - mpfr:256| = %.3e, verify estimate |quad - mpfr:177| = %.3e\n", truth, estimate);
  EXPECT_LE(truth, 1e-27);
  EXPECT_LE(estimate, 100 * truth);
  EXPECT_GE(estimate, truth / 100);
}

}  // namespace
