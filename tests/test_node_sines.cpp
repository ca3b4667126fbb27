// Sines of an argument affine in the node coordinate (reference/detail/node_sines.hpp), and the
// batch evaluation of a torque of time at a segment's nodes (compiled_expression::values_at_nodes)
// that hands such sines to it.
//
// Truth: sin and cos of alpha + beta s_j in MPFR at 300 bits, from the exact quad alpha, beta and
// nodes s_j (the same numbers the kernel reads). Bound: 12 units of 2^-113, derived from the
// kernel's steps: the fixed-point product errs by at most 2^-116 n max|x| + 2 ulp(y) (its header;
// n <= 40 terms, |x| <= 1, |y| <= 1: at most 7 units), and each coefficient x_n carries about
// four roundings (sin or cos alpha, the normalization, the product, Miller's recurrence) on
// sum |x_n| <= 1.3: at most 5 more. Measured: 2.7 units over 2000 arguments.
#include <eulervop/core/error_free.hpp>
#include <eulervop/model/expression.hpp>
#include <eulervop/reference/detail/chebyshev_basis.hpp>
#include <eulervop/reference/detail/node_sines.hpp>
#include <eulervop/scene/expression_parser.hpp>

#include <gtest/gtest.h>

#include <boost/multiprecision/mpfr.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace {

using eulervop::quad;
using exact = boost::multiprecision::number<boost::multiprecision::mpfr_float_backend<91>>;  // >= 300 bits

constexpr std::size_t degree = 41;

exact to_exact(const quad& x) { return exact(x.backend().value()); }
double in_units(const exact& error) { return static_cast<double>(error / exact(ldexp(exact(1), -113))); }

TEST(NodeSines, WithinTwelveUnitsOf2ToMinus113) {
  eulervop::detail::node_sines sines(degree);
  const eulervop::detail::chebyshev_basis<quad> basis(degree);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  int evaluated = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const quad alpha = quad(200 * u(rng) - 100) + quad(u(rng)) * quad(1e-17);
    // Half the trials with a low part, as the integrator passes a segment's exact midpoint.
    const quad alpha_lo = trial % 2 ? quad(0) : quad(u(rng) - 0.5) * ldexp(abs(alpha) + 1, -113);
    quad beta = quad(std::pow(10.0, -4 + 4 * u(rng)));  // 1e-4 .. 1
    if (trial % 2) beta = -beta;
    for (const bool cosine : {false, true}) {
      std::vector<quad> out;
      ASSERT_TRUE(sines.evaluate(alpha, alpha_lo, beta, cosine, out)) << "beta " << static_cast<double>(beta);
      ++evaluated;
      for (std::size_t j = 0; j <= degree; ++j) {
        const exact arg = to_exact(alpha) + to_exact(alpha_lo) + to_exact(beta) * to_exact(basis.nodes[j]);
        const exact truth = cosine ? exact(cos(arg)) : exact(sin(arg));
        worst = std::max(worst, in_units(abs(to_exact(out[j]) - truth)));
      }
    }
  }
  EXPECT_EQ(evaluated, 800);
  EXPECT_LE(worst, 12.0);
}

TEST(NodeSines, DeclinesArgumentsItDoesNotCover) {
  eulervop::detail::node_sines sines(degree);
  std::vector<quad> out;
  EXPECT_FALSE(sines.evaluate(quad(1), quad(0), quad(0), false, out));    // constant: the caller's case
  EXPECT_FALSE(sines.evaluate(quad(1), quad(0), quad(1.5), false, out));  // beyond max_beta
  EXPECT_FALSE(sines.evaluate(std::numeric_limits<quad>::quiet_NaN(), quad(0), quad(0.1), false, out));
  EXPECT_TRUE(out.empty());
}

// The batch over a segment's nodes t_j = alpha + beta s_j against operator() at each t_j: bit for
// bit where no sine of an affine argument occurs (the same operations); where one does, within
// the difference of the two ways of forming the argument. operator() reads the rounded node
// time t_j (within 32 units of 2^-113 of tau + hl (s_j + 1) at t < 64; the batch starts from the
// exact midpoint, alpha + alpha_lo: counted as 64 apart to spare the derivation) and rounds its
// own sums (2 t + 1 near 75: 64 units, on both sides), the batch adds the sines' 12 units. So,
// with |d sin| <= 1 per unit:
//   0.25 sin(t)^2: 0.25 * 2 (64 + 12 + 1) + 2 roundings of at most a unit: 41;
//   t sin(2t + 1) + cos(t/3)^2 - exp(-t): |t| <= 38 times (2 * 64 + 64 + 64 + 12 + 1) = 10,374,
//   plus 2 (64/3 + 8 + 8 + 12 + 1) = 101 for the cosine, plus three roundings of sums near 40
//   (64 units each): 10,667.
// The last two formulas have no sine of an affine argument (sin(t^2), and tanh, atan, sinh and
// cosh): node by node, bit for bit.
TEST(NodeSines, BatchAtTheNodesMatchesTheValueAtEachNode) {
  eulervop::detail::node_sines sines(degree);
  const eulervop::detail::chebyshev_basis<quad> basis(degree);
  const eulervop::scene::expression_variables time_only{{"t", "", "", ""}};
  const quad tau = quad(37) + quad(1) / 3, hl = quad(0.0625) + quad(1e-20);
  std::vector<quad> t(degree + 1);
  for (std::size_t j = 0; j <= degree; ++j) t[j] = tau + hl * (basis.nodes[j] + 1);
  quad alpha, alpha_lo, scratch;
  eulervop::two_sum(tau, hl, alpha, alpha_lo, scratch);  // the exact midpoint, as the integrator passes it
  struct formula {
    const char* text;
    bool batched;   // a sine or cosine of an affine argument
    double bound;   // units of 2^-113 where batched
  };
  for (const formula& f : {formula{"0.25*sin(t)^2", true, 41}, formula{"t*sin(2*t + 1) + cos(t/3)^2 - exp(-t)", true, 10667},
                           formula{"3*t^2 - t/7 + 1.5", false, 0}, formula{"sin(t^2)", false, 0},
                           formula{"tanh(t/40) - atan(t)*sinh(t/50) + cosh(t/60)", false, 0}}) {
    const eulervop::compiled_expression<quad> program(eulervop::scene::parse_expression(f.text, time_only));
    std::vector<quad> batch;
    int handed = 0;
    program.values_at_nodes(alpha, alpha_lo, hl, t,
                            [&](const quad& a, const quad& a_lo, const quad& b, bool cosine, std::vector<quad>& out) {
                              ++handed;
                              return sines.evaluate(a, a_lo, b, cosine, out);
                            },
                            batch);
    ASSERT_EQ(batch.size(), degree + 1) << f.text;
    EXPECT_EQ(handed > 0, f.batched) << f.text;
    double worst = 0;
    for (std::size_t j = 0; j <= degree; ++j) {
      const quad one = program(t[j], {quad(0), quad(0), quad(0)});
      if (f.batched) worst = std::max(worst, in_units(abs(to_exact(batch[j]) - to_exact(one))));
      else EXPECT_EQ(batch[j], one) << f.text << " node " << j;
    }
    EXPECT_LE(worst, f.bound) << f.text;
  }
}

// evaluate() takes sin(alpha) and cos(alpha) from one sincosq; the reference's outputs stay those
// of sinq and cosq only if the three agree bit for bit. Random arguments over the scales a torque
// sees (|alpha| up to 1e6, so every quadrant and both reductions), against the separate calls.
TEST(NodeSines, SincosqGivesTheBitsOfSinqAndCosq) {
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> exponent(-30, 20);
  for (int i = 0; i < 200000; ++i) {
    const __float128 a = ldexpq(static_cast<__float128>(unit(rng)) + static_cast<__float128>(unit(rng)) * 0x1p-60Q,
                                exponent(rng));
    __float128 s, c;
    sincosq(a, &s, &c);
    const __float128 s1 = sinq(a), c1 = cosq(a);
    ASSERT_EQ(std::memcmp(&s, &s1, sizeof s), 0) << static_cast<double>(a);
    ASSERT_EQ(std::memcmp(&c, &c1, sizeof c), 0) << static_cast<double>(a);
  }
}

}  // namespace
