// The quad dense output's two evaluations of a segment, the barycentric formula (evaluate_segment)
// and the Chebyshev series by fixed-point Clenshaw (detail/segment_series.hpp), against the
// interpolant itself evaluated in 256-bit MPFR.
//
// Truth: the degree-N polynomial through the segment's increments at the Lobatto points
// -cos(j pi / N), its Chebyshev coefficients by the discrete transform in 256-bit MPFR and summed
// by Clenshaw in 256 bits (rounding there is about 2^-250 relative, nothing at quad's scale). The
// node positions the integrator stores are those points rounded to quad; the barycentric formula
// interpolates at the rounded ones, which moves its value by about eps |p'| as well.
//
// Bound: both evaluations within 16 ulp of the largest increment (2^-112 * 16 max|v|), where a
// plain quad evaluation makes about N = 41 roundings of that size; measured below 3 ulp for the
// series, and the same for the barycentric formula.
#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/detail/segment_series.hpp>
#include <eulervop/reference/segment.hpp>
#include <eulervop/reference/segment_sampler.hpp>

#include <gtest/gtest.h>

#include <boost/math/constants/constants.hpp>

#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;

constexpr std::size_t N = 41;  // the quad reference's degree

std::vector<quad> lobatto_nodes() {
  const quad pi = boost::math::constants::pi<quad>();
  std::vector<quad> nodes(N + 1);
  for (std::size_t j = 0; j <= N; ++j) nodes[j] = -cos(pi * quad(j) / quad(N));
  return nodes;
}

// A segment whose increments are smooth functions of s of very different sizes.
eulervop::chebyshev_segment<quad, 3> sample_segment(const std::vector<quad>& nodes) {
  eulervop::chebyshev_segment<quad, 3> seg;
  seg.tau_begin = quad(17) / 3;
  seg.half_length = quad(1) / 7;
  seg.tau_end = seg.tau_begin + 2 * seg.half_length;
  seg.base = {quad(0), quad(0), quad(0)};  // so that a sample is its increment, rounded once
  seg.base_lo = {quad(0), quad(0), quad(0)};
  for (const quad& s : nodes) {
    const quad x = s + 1;  // increments vanish at the segment's start
    seg.values.push_back({sin(3 * x + quad(1) / 5) - sin(quad(1) / 5), quad(1e-9) * x * exp(x), x * x * x / 1000});
  }
  return seg;
}

// sum c_k T_k(s) for the increments of component i, in 256-bit MPFR.
mpfr_real exact_increment(const eulervop::chebyshev_segment<quad, 3>& seg, std::size_t i, const mpfr_real& s) {
  const mpfr_real pi = boost::math::constants::pi<mpfr_real>();
  std::vector<mpfr_real> c(N + 1);
  for (std::size_t k = 0; k <= N; ++k) {
    mpfr_real sum = 0;
    for (std::size_t j = 0; j <= N; ++j) {
      mpfr_real term = mpfr_real(seg.values[j][i]) * cos(pi * mpfr_real(k * j) / N);
      if (j == 0 || j == N) term /= 2;
      sum += (k % 2 ? -term : term);
    }
    c[k] = sum * 2 / N;
    if (k == 0 || k == N) c[k] /= 2;
  }
  mpfr_real b1 = 0, b2 = 0;
  for (std::size_t k = N; k >= 1; --k) {
    const mpfr_real b0 = c[k] + 2 * s * b1 - b2;
    b2 = b1;
    b1 = b0;
  }
  return c[0] + s * b1 - b2;
}

TEST(SegmentSeries, BothEvaluationsAreWithinUlpsOfTheInterpolant) {
  const eulervop::mpfr_precision_scope bits(256);
  const std::vector<quad> nodes = lobatto_nodes();
  const auto seg = sample_segment(nodes);
  eulervop::detail::lobatto_transform_quad transform(N);
  const eulervop::detail::segment_series_quad<3> series(seg, nodes, transform);
  std::mt19937_64 random(20261128);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<quad> taus = {seg.tau_begin, seg.tau_end};
  for (int k = 0; k < 400; ++k) taus.push_back(seg.tau_begin + 2 * seg.half_length * quad(unit(random)));
  for (int k = 1; k <= 20; ++k) {  // near the ends, where Clenshaw's errors grow most
    taus.push_back(seg.tau_begin + seg.half_length * ldexp(quad(1), -4 * k));
    taus.push_back(seg.tau_end - seg.half_length * ldexp(quad(1), -4 * k));
  }
  for (std::size_t i = 0; i < 3; ++i) {
    quad vmax = 0;
    for (const auto& v : seg.values) vmax = std::max(vmax, quad(abs(v[i])));
    const double ulp = static_cast<double>(vmax * std::numeric_limits<quad>::epsilon());
    double worst_series = 0, worst_barycentric = 0;
    for (const quad& tau : taus) {
      const quad s = (tau - seg.tau_begin) / seg.half_length - 1;
      const mpfr_real truth = mpfr_real(seg.base[i]) + exact_increment(seg, i, mpfr_real(s));
      const quad a = series(tau)[i], b = eulervop::evaluate_segment(seg, nodes, tau)[i];
      worst_series = std::max(worst_series, static_cast<double>(abs(mpfr_real(a) - truth)) / ulp);
      worst_barycentric = std::max(worst_barycentric, static_cast<double>(abs(mpfr_real(b) - truth)) / ulp);
    }
    RecordProperty("component" + std::to_string(i) + "_series_ulps", std::to_string(worst_series));
    RecordProperty("component" + std::to_string(i) + "_barycentric_ulps", std::to_string(worst_barycentric));
    EXPECT_LE(worst_series, 16) << "component " << i;
    EXPECT_LE(worst_barycentric, 16) << "component " << i;
  }
}

TEST(SegmentSeries, NodesGiveTheStoredValuesExactly) {
  const std::vector<quad> nodes = lobatto_nodes();
  const auto seg = sample_segment(nodes);
  eulervop::detail::lobatto_transform_quad transform(N);
  const eulervop::detail::segment_series_quad<3> series(seg, nodes, transform);
  for (std::size_t j : {std::size_t(0), std::size_t(7), N}) {
    const quad tau = j == 0 ? seg.tau_begin : seg.tau_begin + seg.half_length * (nodes[j] + 1);
    const quad s = (tau - seg.tau_begin) / seg.half_length - 1;
    if (s != nodes[j]) continue;  // tau does not map back onto the node exactly
    const auto y = series(tau);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(y[i], seg.base[i] + (seg.base_lo[i] + seg.values[j][i]));
  }
}

TEST(SegmentSeries, ProductShiftedRoundsToNearest) {
  // Exact cases: 2^125 * b / 2^125 = b, and (2^126 - 1) * 3 / 2^126 rounds to 3.
  using eulervop::detail::product_shifted;
  const __int128 one = 1;
  EXPECT_EQ(product_shifted(one << 125, 12345, 125), 12345);
  EXPECT_EQ(product_shifted(-(one << 125), 12345, 125), -12345);
  EXPECT_EQ(product_shifted((one << 126) - 1, 3, 126), 3);
  EXPECT_EQ(product_shifted(one << 126, -(one << 120), 126), -(one << 120));
  // 3 * 2^124 * (2^64 + 1) / 2^125 = 1.5 (2^64 + 1) = 3 * 2^63 + 1.5, which rounds to 3 * 2^63 + 2.
  EXPECT_EQ(product_shifted(3 * (one << 124), (one << 64) + 1, 125), 3 * (one << 63) + 2);
}

// A sampler pulls the next time only after emitting the previous one, so a source can reuse one
// slot for the row it read last.
TEST(SegmentSampler, AsksForEachTimeAfterEmittingThePrevious) {
  const std::vector<quad> nodes = lobatto_nodes();
  const auto seg = sample_segment(nodes);
  std::size_t asked = 0, emitted = 0;
  eulervop::segment_sampler<quad> sampler(
      [&](quad& tau) {
        EXPECT_EQ(asked, emitted) << "asked for a time before the previous one was emitted";
        if (asked == 10) return false;
        tau = seg.tau_begin + seg.half_length * quad(asked) / 5;
        ++asked;
        return true;
      },
      [&](std::size_t index, const quad&, const std::array<quad, 3>&) {
        EXPECT_EQ(index, emitted);
        ++emitted;
      });
  sampler(seg, nodes);
  sampler.finish();
  EXPECT_EQ(emitted, 10u);
}

}  // namespace
