// Chebyshev-Picard reference integrator: basis exactness, torque-free accuracy against the exact
// solution (Eq. 12), dense output, compensated accumulation and failure reporting.
#include <eulervop/reference/integrate.hpp>

#include "type_test_names.hpp"

#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;

template <class T>
class ChebyshevBasis : public ::testing::Test {};
using BasisTypes = ::testing::Types<double, quad>;
TYPED_TEST_SUITE(ChebyshevBasis, BasisTypes, scalar_test_names);

// The Picard matrix integrates polynomials of degree <= N exactly: F = s^5 + 3 s^2 at the nodes
// must give (s^6 - 1)/6 + (s^3 + 1) (exact antiderivative vanishing at s = -1).
TYPED_TEST(ChebyshevBasis, IntegratesPolynomialsExactly) {
  using T = TypeParam;
  for (std::size_t N : {8u, 16u, 41u}) {
    eulervop::detail::chebyshev_basis<T> b(N);
    const std::size_t n1 = N + 1;
    std::vector<T> F(n1);
    for (std::size_t j = 0; j < n1; ++j) {
      const T s = b.nodes[j];
      F[j] = s * s * s * s * s + 3 * s * s;
    }
    T worst = 0;
    for (std::size_t j = 0; j < n1; ++j) {
      T acc = 0;
      for (std::size_t k = 0; k < n1; ++k) acc += b.integral[j * n1 + k] * F[k];
      const T s = b.nodes[j];
      const T exact = (s * s * s * s * s * s - 1) / 6 + (s * s * s + 1);
      using std::abs;
      worst = std::max<T>(worst, abs(acc - exact));
    }
    // Bound: N+1 products of O(1) terms, each rounded: a few N eps (measured: < 2 N eps).
    EXPECT_LE(worst, T(4 * N) * std::numeric_limits<T>::epsilon()) << "N=" << N;
  }
}

// Torque-free motion with Omega(0) = (k, 0, 1), so c1 = k, c2 = 1, u = tau (Eqs. 7, 11, 12):
// Omega = (k cn(tau), k sn(tau), dn(tau)), modulus k. Exact values come from Boost.Math's
// jacobi_elliptic in MPFR at bits_ref bits, with dn = sqrt(1 - k^2 sn^2) (Boost's dn is a ratio
// that degrades near odd multiples of K: docs/design.md section 2).
template <class T>
double torque_free_max_error(const std::string& k_text, double tau_end, int samples,
                             unsigned bits_ref, eulervop::picard_stats* st,
                             const eulervop::picard_settings& settings = {}) {
  const T k = *eulervop::from_text<T>(k_text);
  eulervop::euler_problem<T> p;
  p.torque.G = {T(0), T(0), T(0)};
  p.Omega0 = {k, T(0), T(1)};
  const auto traj = eulervop::integrate_reference<T>(p, T(tau_end), settings, {}, st);
  std::vector<vec3<std::string>> got(samples + 1);
  for (int i = 0; i <= samples; ++i) {
    const auto om = traj(T(tau_end) * i / samples);  // tau_end*i/samples is exact for the spans used
    for (int c = 0; c < 3; ++c) got[i][c] = eulervop::to_text(om[c]);
  }
  const std::string k_exact = eulervop::to_text(k);
  eulervop::mpfr_precision_scope scope(bits_ref);
  const mpfr_real kr(k_exact);
  mpfr_real worst = 0;
  for (int i = 0; i <= samples; ++i) {
    const mpfr_real u = mpfr_real(tau_end) * i / samples;
    mpfr_real cn, dn;
    const mpfr_real sn = boost::math::jacobi_elliptic(kr, u, &cn, &dn);
    dn = sqrt(1 - kr * kr * sn * sn);
    const mpfr_real exact[3] = {kr * cn, kr * sn, dn};
    for (int c = 0; c < 3; ++c) worst = std::max(worst, mpfr_real(abs(mpfr_real(got[i][c]) - exact[c])));
  }
  return static_cast<double>(worst);
}

TEST(TorqueFree, QuadMatchesExactSolutionOnLongSpan) {
  for (const char* k : {"0.5", "0.99"}) {
    eulervop::picard_stats st;
    const double err = torque_free_max_error<quad>(k, 1000.0, 1000, 256, &st);
    RecordProperty(std::string("quad_max_error_k") + k, std::to_string(err));
    std::printf("quad k=%s: max error %.3e over tau in [0,1000], %zu segments\n", k, err, st.segments);
    EXPECT_LE(err, 1e-28) << "k=" << k;  // measured: docs/reference.md, "How good it is"
  }
}

// A tolerance looser than the precision is what the run's global error reaches (each segment's
// truncation is held to a sixteenth of it), and the residual updates in double-double that such
// a tolerance allows do not cost accuracy. At 1e-40 they follow the first residual in T where
// its correction does not settle the segment (measured: 253 updates over 205 segments). At 1e-50
// the first residual in T runs on three limbs (picard_matrices.hpp, S_fx_first) and the
// correction of the full one after it settles every segment, so none is needed there. Exact
// values as above, at 400 bits.
TEST(TorqueFree, Mpfr256MeetsALooserToleranceWithResidualUpdates) {
  for (const double tol : {1e-40, 1e-50}) {
    eulervop::picard_stats st;
    double err = 0;
    {
      eulervop::mpfr_precision_scope scope(256);
      err = torque_free_max_error<mpfr_real>("0.99", 200.0, 200, 400, &st, {.tolerance = tol});
    }
    std::printf("mpfr:256 tol %.0e k=0.99: max error %.3e over tau in [0,200], %zu segments, %zu updates\n", tol,
                err, st.segments, st.residual_updates);
    EXPECT_LE(err, tol);
    if (tol > 1e-45) EXPECT_GT(st.residual_updates, 0u) << "the update path was not taken";
  }
}

TEST(TorqueFree, Mpfr256MatchesExactSolutionOnLongSpan) {
  for (const char* k : {"0.5", "0.99"}) {
    eulervop::picard_stats st;
    double err = 0;
    {
      eulervop::mpfr_precision_scope scope(256);
      err = torque_free_max_error<mpfr_real>(k, 1000.0, 200, 400, &st);
    }
    std::printf("mpfr:256 k=%s: max error %.3e over tau in [0,1000], %zu segments\n", k, err, st.segments);
    EXPECT_LE(err, 1e-65) << "k=" << k;  // measured: docs/reference.md, "How good it is"
  }
}

TEST(TorqueFree, DoubleIsAccurateToRounding) {
  eulervop::picard_stats st;
  const double err = torque_free_max_error<double>("0.5", 100.0, 400, 200, &st);
  // Phase error accumulates about linearly: ~ eps per unit tau of rotation at this rate.
  EXPECT_LE(err, 400 * std::numeric_limits<double>::epsilon() * 100);
}

// Dense output is continuous across segment boundaries and reproduces the segment ends.
TEST(DenseOutput, ContinuousAcrossSegments) {
  eulervop::euler_problem<quad> p;
  p.torque.G = {quad(1), quad(1), quad(1)};
  p.Omega0 = {quad(0.5), quad(0), quad(1)};
  const auto traj = eulervop::integrate_reference<quad>(p, quad(10));
  ASSERT_GT(traj.segments(), 10u);
  const auto& segs = traj.segment_list();
  quad worst = 0;
  for (std::size_t i = 0; i + 1 < segs.size(); ++i) {
    // End of segment i from its own interpolant (the last node) against the start of i+1.
    const auto& a = segs[i];
    for (int c = 0; c < 3; ++c) {
      const quad left = a.base[c] + (a.base_lo[c] + a.values.back()[c]);
      const quad right = segs[i + 1].base[c] + segs[i + 1].base_lo[c];
      worst = std::max(worst, quad(fabs(left - right)));
    }
  }
  // |Omega| <= 20 here; the two sides differ by the rounding of the TwoSum carry only.
  EXPECT_LE(worst, 20 * 4 * std::numeric_limits<quad>::epsilon());
  // Between nodes the interpolant is smooth across the boundary too: evaluate just either side.
  for (std::size_t i = 0; i + 1 < segs.size(); i += 7) {
    const quad t = segs[i].tau_end, d = quad("1e-20");
    const auto l = traj(t - d), r = traj(t + d);
    for (int c = 0; c < 3; ++c) EXPECT_LE(fabs(l[c] - r[c]), quad("1e-18")) << "segment " << i;
  }
  EXPECT_THROW(traj(quad(10.5)), std::out_of_range);
  EXPECT_THROW(traj(quad(-0.1)), std::out_of_range);
  EXPECT_NO_THROW(traj(quad(10)));
}

// Failures carry the tau where they happened.
TEST(Failures, ReportedWithTau) {
  eulervop::euler_problem<double> p;
  p.torque.G = {1, 1, 1};
  p.Omega0 = {0.5, 0, 1};
  eulervop::picard_settings s;
  s.max_segments = 5;
  try {
    eulervop::integrate_reference<double>(p, 100.0, s);
    FAIL() << "expected numerical_failure";
  } catch (const eulervop::numerical_failure& e) {
    EXPECT_GT(e.tau(), 0.0);
    EXPECT_LT(e.tau(), 100.0);
    EXPECT_NE(std::string(e.what()).find("tau="), std::string::npos);
  }
  p.Omega0 = {std::nan(""), 0, 1};
  EXPECT_THROW(eulervop::integrate_reference<double>(p, 1.0), eulervop::numerical_failure);
}

// Same problem, same settings: bit-identical output (determinism).
TEST(Determinism, RepeatedRunsAreIdentical) {
  eulervop::euler_problem<quad> p;
  p.torque.G = {quad(1), quad(1), quad(1)};
  p.Omega0 = {quad(0.5), quad(0), quad(1)};
  const auto a = eulervop::integrate_reference<quad>(p, quad(5));
  const auto b = eulervop::integrate_reference<quad>(p, quad(5));
  ASSERT_EQ(a.segments(), b.segments());
  for (int i = 0; i <= 50; ++i) {
    const quad t = quad(5) * i / 50;
    EXPECT_EQ(eulervop::to_text(a(t)[0]), eulervop::to_text(b(t)[0]));
  }
}

// Streaming samples (constant memory) equal the dense trajectory's values bit for bit, also at
// segment boundaries (where both take the segment that starts there) and at the span's end;
// samples out of order or beyond the span are refused.
// The samples streamed from each segment as it is accepted are the dense output's: the first
// segment_sampler::series_after of a segment bit for bit (the same barycentric formula), the
// later ones, from the segment's Chebyshev series, to within 8 units in the last place of |y|
// (both forms are within a few units of the exact interpolant: tests/test_segment_series.cpp).
TEST(StreamingSamples, EqualDenseOutput) {
  eulervop::euler_problem<quad> p;
  p.torque.G = {quad(1), quad(1), quad(1)};
  p.Omega0 = {quad(0.5), quad(0), quad(1)};
  const auto dense = eulervop::integrate_reference<quad>(p, quad(5));
  std::vector<quad> taus;
  for (int i = 0; i <= 400; ++i) taus.push_back(quad(5) * i / 400);
  for (std::size_t s = 1; s < dense.segments(); s += 3) taus.push_back(dense.segment_list()[s].tau_begin);
  std::sort(taus.begin(), taus.end());
  std::size_t count = 0, exact = 0, series = 0;
  const auto& segs = dense.segment_list();
  std::vector<std::size_t> in_segment(segs.size(), 0);
  eulervop::integrate_reference_samples<quad>(p, quad(5), taus, [&](std::size_t i, const quad& tau, const vec3<quad>& Om) {
    ASSERT_EQ(i, count++);
    const vec3<quad> want = dense(tau);
    const auto seg = std::upper_bound(segs.begin(), segs.end(), tau, [](const quad& t, const auto& sg) {
      return t < sg.tau_begin;
    }) - segs.begin() - 1;
    if (++in_segment[static_cast<std::size_t>(seg)] <= eulervop::segment_sampler<quad>::series_after) {
      ++exact;
      for (int c = 0; c < 3; ++c) EXPECT_EQ(eulervop::to_text(Om[c]), eulervop::to_text(want[c])) << "tau=" << tau;
      return;
    }
    ++series;
    const quad size = sqrt(want[0] * want[0] + want[1] * want[1] + want[2] * want[2]);
    for (int c = 0; c < 3; ++c)
      EXPECT_LE(abs(Om[c] - want[c]), 8 * std::numeric_limits<quad>::epsilon() * size) << "tau=" << tau;
  });
  EXPECT_EQ(count, taus.size());
  EXPECT_GT(exact, 0u);
  EXPECT_GT(series, 100u);  // both forms are exercised

  const auto ignore = [](std::size_t, const quad&, const vec3<quad>&) {};
  EXPECT_THROW(eulervop::integrate_reference_samples<quad>(p, quad(5), {quad(2), quad(1)}, ignore),
               std::invalid_argument);
  EXPECT_THROW(eulervop::integrate_reference_samples<quad>(p, quad(5), {quad(1), quad(6)}, ignore),
               std::out_of_range);
}

}  // namespace

// The correction's stop on a predicted change (reference/detail/picard_correction.hpp,
// correction_stop::predicted). One segment's correction equation, delta = r + hl S [f(X + delta)
// - f(X)], with the paper's torque: X a rotation of size 50 at the nodes (hl |J| about 1.25, as
// the paper scene's long segments), r a smooth residual of 1e-3 or 1e-16. Solved twice with the
// same absolute floor (1e-10 |r|): to a measured change below it, and with the predicted stop.
// Derived bound: the predicted stop leaves at most its target (2 q diff <= floor, geometric
// contraction by q < 1/4), the measured one at most q floor <= floor / 4, so the two differ by at
// most 1.25 floor. The predicted stop must also take fewer sweeps, or it is not exercised.
TEST(Correction, PredictedStopStaysWithinItsTarget) {
  using P = eulervop::euler_problem<quad>;
  P problem;
  problem.torque.G = {quad(1), quad(1), quad(1)};
  problem.Omega0 = {quad(0.5), quad(0), quad(1)};
  const std::size_t N = 41, n1 = N + 1;
  const eulervop::detail::picard_matrices<quad> m(N, 113);
  const double hl = 0.025;
  for (const double amplitude : {1e-3, 1e-16}) {
    const double floor = 1e-10 * amplitude;
    std::array<std::array<std::vector<double>, 3>, 2> solved;
    std::array<std::size_t, 2> sweeps{};
    for (int k = 0; k < 2; ++k) {
      eulervop::detail::picard_workspace<P> w(n1);
      w.field = eulervop::detail::field_of<P>(problem);
      for (std::size_t j = 0; j < n1; ++j) {
        const double s = static_cast<double>(m.basis.nodes[j]);
        w.Xd[0][j] = 30 * std::cos(2 * s);
        w.Xd[1][j] = 30 * std::sin(2 * s);
        w.Xd[2][j] = 40;
        for (int i = 0; i < 3; ++i) w.r[i][j] = j == 0 ? 0.0 : amplitude * std::sin(3 * s + i);
      }
      eulervop::picard_stats st;
      using eulervop::detail::correction_stop;
      const auto stop = k == 0 ? correction_stop::measured : correction_stop::predicted;
      ASSERT_TRUE(eulervop::detail::solve_correction(m, w, hl, floor, stop, st).ok());
      solved[k] = w.delta;
      sweeps[k] = st.double_sweeps;
    }
    double worst = 0, size = 0;
    for (int i = 0; i < 3; ++i)
      for (std::size_t j = 0; j < n1; ++j) {
        worst = std::max(worst, std::abs(solved[1][i][j] - solved[0][i][j]));
        size = std::max(size, std::abs(solved[0][i][j]));
      }
    EXPECT_LE(worst, 1.25 * floor) << "amplitude " << amplitude;
    EXPECT_GT(size, 100 * floor) << "amplitude " << amplitude;  // the correction is not trivial
    EXPECT_LT(sweeps[1], sweeps[0]) << "amplitude " << amplitude;
  }
}

// The warm start evaluates its Clenshaw recurrences eight nodes side by side and its coefficients
// four rows side by side: each must give the bits of one clenshaw<double> per node on the
// coefficients summed row by row (the order of operations it documents). A segment of degree 41
// through smooth values, extrapolated to a segment 1.3 times as long.
TEST(WarmStart, SideBySideIsClenshawsBits) {
  const std::size_t N = 41, n1 = N + 1;
  const eulervop::detail::picard_matrices<quad> m(N, 113);
  eulervop::chebyshev_segment<quad, 3> prev;
  prev.half_length = quad(0.05);
  prev.values.resize(n1);
  for (std::size_t j = 0; j < n1; ++j)
    for (int i = 0; i < 3; ++i) prev.values[j][i] = sin(quad(0.3 + i) * (m.basis.nodes[j] + 1)) / (i + 1);
  const quad hl_new = prev.half_length * quad(1.3);
  eulervop::detail::warm_start<quad, 3> start(N);
  std::array<std::vector<double>, 3> warm;
  for (auto& v : warm) v.resize(n1);
  start(m, &prev, hl_new, warm);
  const double ratio = static_cast<double>(hl_new / prev.half_length);
  for (int i = 0; i < 3; ++i) {
    std::vector<double> b(n1 + 1, 0.0);
    double cmax = 0;
    for (std::size_t k = 0; k < n1; ++k) {
      for (std::size_t j = 0; j < n1; ++j) b[k] += m.C_d[k * n1 + j] * static_cast<double>(prev.values[j][i]);
      cmax = std::max(cmax, std::abs(b[k]));
    }
    for (std::size_t k = 1; k < n1; ++k)
      if (std::abs(b[k]) < 1e-15 * cmax) b[k] = 0;
    const double p1 = eulervop::detail::clenshaw<double>(b.data(), n1, 1, 1.0);
    for (std::size_t j = 0; j < n1; ++j) {
      const double s = 1.0 + ratio * (static_cast<double>(m.basis.nodes[j]) + 1.0);
      const double expected = eulervop::detail::clenshaw<double>(b.data(), n1, 1, s) - p1;
      EXPECT_EQ(std::memcmp(&expected, &warm[i][j], sizeof expected), 0) << "component " << i << " node " << j;
    }
  }
  EXPECT_NE(warm[0][n1 - 1], 0.0);  // the extrapolation ran (not the cold start's zeros)
}

// The sweeps compiled for AVX (where the processor has it) against the baseline build of the same
// source: AVX brings no fused multiply-add, so each sweep must give the same bits. A workspace as
// in PredictedStopStaysWithinItsTarget, ten sweeps each, every delta and g compared bit for bit.
TEST(Correction, AvxSweepsAreTheBaselinesBits) {
#if EULERVOP_SWEEP_AVX
  if (!eulervop::detail::sweeps_use_avx()) GTEST_SKIP() << "no AVX on this processor";
  using P = eulervop::euler_problem<quad>;
  P problem;
  problem.torque.G = {quad(1), quad(1), quad(1)};
  const std::size_t N = 41, n1 = N + 1;
  const eulervop::detail::picard_matrices<quad> m(N, 113);
  std::array<eulervop::detail::picard_workspace<P>, 2> w{eulervop::detail::picard_workspace<P>(n1),
                                                         eulervop::detail::picard_workspace<P>(n1)};
  for (auto& v : w) {
    v.field = eulervop::detail::field_of<P>(problem);
    for (std::size_t j = 0; j < n1; ++j) {
      const double s = static_cast<double>(m.basis.nodes[j]);
      v.Xd[0][j] = 30 * std::cos(2 * s);
      v.Xd[1][j] = 30 * std::sin(2 * s);
      v.Xd[2][j] = 40;
      for (int i = 0; i < 3; ++i) v.r[i][j] = v.delta[i][j] = j == 0 ? 0.0 : 1e-3 * std::sin(3 * s + i);
    }
    eulervop::detail::increments(v);
  }
  for (int sweep = 0; sweep < 10; ++sweep) {
    double dmax[2] = {0, 0};
    const double diff0 = eulervop::detail::correction_sweep(m, w[0], 0.025, dmax[0]);
    const double diff1 = eulervop::detail::correction_sweep_avx(m, w[1], 0.025, dmax[1]);
    ASSERT_EQ(std::memcmp(&diff0, &diff1, sizeof diff0), 0) << "sweep " << sweep;
    ASSERT_EQ(std::memcmp(&dmax[0], &dmax[1], sizeof dmax[0]), 0) << "sweep " << sweep;
    for (int i = 0; i < 3; ++i) {
      ASSERT_EQ(std::memcmp(w[0].delta[i].data(), w[1].delta[i].data(), n1 * sizeof(double)), 0) << sweep;
      ASSERT_EQ(std::memcmp(w[0].g[i].data(), w[1].g[i].data(), n1 * sizeof(double)), 0) << sweep;
    }
  }
#else
  GTEST_SKIP() << "the sweeps have no AVX build here";
#endif
}

// The double-double product computes four rows side by side in blocks, the rows before the
// blocks one by one (also those of a block that first_row cuts): both must give the bits of Dot2's
// sum for each row. The Picard matrix at degree 41 (42 rows: row 1 alone, then blocks from row
// 2) times a vector of mixed magnitudes; rows 3 to 5 come one by one with first_row = 3 and
// from a block with first_row = 2.
TEST(DoubleDoubleMatrix, BlocksAreTheRowsBits) {
  const std::size_t N = 41, n1 = N + 1;
  eulervop::detail::picard_matrices<quad> m(N, 113);
  std::vector<double> x_hi(n1), x_lo(n1);
  for (std::size_t k = 0; k < n1; ++k) {
    x_hi[k] = std::ldexp(std::sin(1.0 + 7.0 * k), static_cast<int>(k % 9) - 4);
    x_lo[k] = x_hi[k] * 0x1p-60 * std::cos(3.0 * k);
  }
  std::array<std::vector<double>, 2> y_hi{std::vector<double>(n1), std::vector<double>(n1)}, y_lo = y_hi;
  m.S_dd.multiply(x_hi.data(), x_lo.data(), y_hi[0].data(), y_lo[0].data(), 2);
  m.S_dd.multiply(x_hi.data(), x_lo.data(), y_hi[1].data(), y_lo[1].data(), 3);
  for (std::size_t r = 3; r < n1; ++r) {
    EXPECT_EQ(std::memcmp(&y_hi[0][r], &y_hi[1][r], sizeof(double)), 0) << "row " << r;
    EXPECT_EQ(std::memcmp(&y_lo[0][r], &y_lo[1][r], sizeof(double)), 0) << "row " << r;
  }
  // And the sum is the product's: Dot2's bound (Ogita, Rump & Oishi 2005, Theorem 4.4) in
  // double-double is gamma_n^2 sum |a x|, (42 u)^2 < 2^-95 for u = 2^-53, plus 2^-106 sum |a x|
  // for the entries split into double-double and as much for the sum in quad it is checked with.
  for (std::size_t r = 2; r < n1; ++r) {
    quad exact = 0, size = 0;
    for (std::size_t k = 0; k < n1; ++k) {
      const quad a = m.basis.integral[r * n1 + k], x = quad(x_hi[k]) + quad(x_lo[k]);
      exact += a * x;
      size += abs(a * x);
    }
    const quad got = quad(y_hi[0][r]) + quad(y_lo[0][r]);
    EXPECT_LE(static_cast<double>(abs(got - exact)), std::ldexp(static_cast<double>(size), -94)) << "row " << r;
  }
}

// The workspace's double-to-binary128 conversion from bit patterns against the compiler's: the
// same bits for normal doubles across the exponent range and both signs, and the edge cases it
// hands to the compiler (zeros, subnormals, infinities).
TEST(Workspace, ExactBinary128IsTheConversion) {
  using W = eulervop::detail::picard_workspace<eulervop::euler_problem<quad>>;
  std::vector<double> values = {0.0, -0.0, 0x1p-1074, -0x1p-1074, 0x1.fffffffffffffp-1023, 0x1p-1022,
                                std::numeric_limits<double>::max(), std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity()};
  for (int e = -1022; e <= 1023; e += 7)
    for (const double m : {1.0, 1.5, 1.9999999999999998, 1.2345678901234567})
      for (const double sign : {1.0, -1.0}) values.push_back(sign * std::ldexp(m, e));
  for (const double d : values) {
    const __float128 got = W::exact_binary128(d), expected = static_cast<__float128>(d);
    EXPECT_EQ(std::memcmp(&got, &expected, sizeof got), 0) << d;
  }
}

// log|x| of a binary128 from its bit pattern (reference/detail/length_control.hpp) against the
// library way it replaces, log(double(frexp(|x|))) + e ln 2: the same bits on random patterns of
// both signs over the whole exponent range, and on significands that round up to 1.
TEST(LengthControl, LogAbsFromBitsIsFrexps) {
  std::mt19937_64 rng(1128);
  const unsigned __int128 one = 1;
  for (int k = 0; k < 100000; ++k) {
    unsigned __int128 fraction = ((static_cast<unsigned __int128>(rng()) << 64) | rng()) & ((one << 112) - 1);
    if (k % 10 == 0) fraction |= ((one << 112) - 1) & ~((one << 58) - 1);  // rounds up to 2^113
    const auto exponent = static_cast<unsigned __int128>(1 + rng() % 0x7ffe);
    const unsigned __int128 bits = (static_cast<unsigned __int128>(rng() & 1) << 127) | (exponent << 112) | fraction;
    __float128 v;
    std::memcpy(&v, &bits, sizeof v);
    int e = 0;
    const double expected = std::log(static_cast<double>(frexpq(fabsq(v), &e))) + e * 0.69314718055994531;
    const double got = eulervop::detail::log_abs(quad(v));
    ASSERT_EQ(std::memcmp(&got, &expected, sizeof got), 0) << static_cast<double>(v);
  }
}

// A binary128 split into double-double from its bit pattern (core/error_free.hpp) against the
// soft-float way it replaces, hi = double(v), lo = double(v - hi): the same bits for both zeros,
// for significands whose 60 low bits are zero (lo = +0), for ties at the 53rd bit (round to even
// up and down), and for random patterns over the exponent range it takes (|e| <= 900).
TEST(DoubleDouble, SplitFromBitsIsTheSoftFloatSplit) {
  const auto soft = [](const __float128& v) {
    const double hi = static_cast<double>(v);
    return eulervop::double_double{hi, static_cast<double>(v - static_cast<__float128>(hi))};
  };
  const auto from_bits = [](unsigned __int128 bits) {
    __float128 v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  };
  const unsigned __int128 one = 1;
  std::vector<unsigned __int128> patterns = {0, one << 127};
  std::mt19937_64 rng(20261128);
  for (int k = 0; k < 200000; ++k) {
    const unsigned __int128 fraction = ((static_cast<unsigned __int128>(rng()) << 64) | rng()) & ((one << 112) - 1);
    const auto exponent = static_cast<unsigned __int128>(16383 - 900 + static_cast<int>(rng() % 1801));
    const unsigned __int128 sign = static_cast<unsigned __int128>(rng() & 1) << 127;
    patterns.push_back(sign | (exponent << 112) | fraction);
    patterns.push_back(sign | (exponent << 112) | (fraction & ~((one << 60) - 1)));  // rest 0
    patterns.push_back(sign | (exponent << 112) | (fraction & ~((one << 60) - 1)) | (one << 59));  // a tie
  }
  for (const unsigned __int128 bits : patterns) {
    const __float128 v = from_bits(bits);
    eulervop::double_double got;
    ASSERT_TRUE(eulervop::detail::binary128_to_double_double(v, got));
    const eulervop::double_double expected = soft(v);
    ASSERT_EQ(std::memcmp(&got.hi, &expected.hi, sizeof(double)), 0) << static_cast<double>(v);
    ASSERT_EQ(std::memcmp(&got.lo, &expected.lo, sizeof(double)), 0) << static_cast<double>(v);
  }
}
