// The Chebyshev models of the general path of --certify (include/eulervop/certify/detail/:
// chebyshev_model.hpp, residual_model.hpp, kronecker_product.hpp, chunked_product.hpp,
// fixed_point.hpp, ball_node_transform.hpp, short_integer_series.hpp, magnitude_sum.hpp), tested as
// an adversary would: every enclosure must hold the exact value of every function the model
// stands for, at random and extreme inputs.
//
// Truth: MPFR at 1000 bits (about 300 digits, so that its own rounding is far below any radius
// here), evaluating the functions a model stands for directly: Chebyshev sums with coefficients
// chosen at the ends of their balls, plus a function of size up to the remainder (rem sin(17 s + 1)).
// The interpolant at the Lobatto nodes reproduces a polynomial of its degree (exact), and the
// exact integer products are checked against FLINT's.
#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/ball_node_transform.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/fixed_point.hpp>
#include <eulervop/certify/detail/magnitude_sum.hpp>
#include <eulervop/certify/detail/residual_model.hpp>
#include <eulervop/certify/detail/short_integer_series.hpp>
#include <eulervop/core/scalar.hpp>

#include <gtest/gtest.h>

#include "ball_test_support.hpp"

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace {

using namespace eulervop::test::ball_support;

TEST(ChebyshevModel, ProductsHoldEveryProductOfTheFunctionsTheyStandFor) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(20261127);
  for (int trial = 0; trial < 60; ++trial) {
    const slong la = 1 + static_cast<slong>(rng() % 45), lb = 1 + static_cast<slong>(rng() % 45);
    const double rho = trial % 3 == 0 ? 1.0 : 0.2 + 0.6 * static_cast<double>(rng() % 100) / 100;
    const chebyshev_model a = random_model(rng, la, rho, trial % 2 ? 100 : 0, trial % 4 == 0 ? 1e-20 : 0);
    chebyshev_model b = random_model(rng, lb, rho, trial % 3 ? 60 : 0, trial % 5 == 0 ? 1e-10 : 0);
    if (trial % 7 == 6) {  // a signed power of two, as a variable's derivative (multiply's own branch)
      b = chebyshev_model(1);
      arb_set_si(b.coeff(0), rng() % 2 ? 1 : -1);
      arb_mul_2exp_si(b.coeff(0), b.coeff(0), static_cast<slong>(rng() % 5) - 2);
    }
    for (const slong bits : {56L, 177L}) {
      chebyshev_model c;
      eulervop::detail::multiply(c, a, b, bits);
      for (int pick_round = 0; pick_round < 3; ++pick_round) {
        const represented fa = pick(a, rng), fb = pick(b, rng);
        for (const mpfr_real& s : points(rng)) {
          ball v;
          eulervop::detail::evaluate(v, c, point(s), truth_bits);
          ASSERT_TRUE(holds(v, fa(s) * fb(s))) << "trial " << trial << " bits " << bits << " lengths " << la << ", "
                                               << lb << " at s = " << s;
        }
      }
    }
  }
}

// Scaling by a number, exactly where it is a signed power of two (the fields' 1/2 and -1).
TEST(ChebyshevModel, ScalingHoldsEveryScaledFunction) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(3);
  ball third;
  arb_set_ui(third.get(), 1);
  arb_div_ui(third.get(), third.get(), 3, 200);
  for (const ball& x : {decimal(-0.5), decimal(4), decimal(1), decimal(-1), third}) {
    const chebyshev_model a = random_model(rng, 20, 0.5, 80, 1e-12);
    chebyshev_model c = a;
    eulervop::detail::scale(c, x, 200);
    const represented fa = pick(a, rng);
    for (const mpfr_real& s : points(rng)) {
      ball v, y;
      eulervop::detail::evaluate(v, c, point(s), truth_bits);
      // x's own ball: both of its ends.
      for (const int end : {-1, 1}) {
        arf_t e;
        arf_init(e);
        arf_set_mag(e, arb_radref(x.get()));
        if (end < 0) arf_neg(e, e);
        arf_add(e, e, arb_midref(x.get()), ARF_PREC_EXACT, ARF_RND_DOWN);
        ASSERT_TRUE(holds(v, fa(s) * to_mpfr(e))) << "s = " << s;
        arf_clear(e);
      }
    }
  }
}

// The product is as tight as its grid: a product of exact polynomials on 177 bits is within
// 2^-170 of the exact one, relative to the factors' sizes (sum of magnitudes).
TEST(ChebyshevModel, ProductsOfExactPolynomialsAreTight) {
  std::mt19937_64 rng(7);
  const chebyshev_model a = random_model(rng, 42, 0.15, 0, 0), b = random_model(rng, 42, 0.15, 0, 0);
  chebyshev_model c;
  eulervop::detail::multiply(c, a, b, 177);
  mag_value sup, A, B;
  eulervop::detail::sup_bound(sup.m, c);
  eulervop::detail::coefficient_magnitude(A.m, a);
  eulervop::detail::coefficient_magnitude(B.m, b);
  mag_mul(A.m, A.m, B.m);
  mag_mul_2exp_si(A.m, A.m, -170);
  EXPECT_LE(mag_cmp(c.remainder(), A.m), 0) << "remainder " << mag_get_d(c.remainder());
}

// The integral alone: the residual's model with no start and no P (picard_residual_model()).
TEST(ChebyshevModel, IntegralsHoldTheIntegralOfEveryFunction) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 40; ++trial) {
    const slong n = 1 + static_cast<slong>(rng() % 60);
    const chebyshev_model a = random_model(rng, n, 0.7, trial % 2 ? 80 : 0, trial % 3 == 0 ? 1e-15 : 0);
    ball hl;
    arb_set_d(hl.get(), 0.375 + static_cast<double>(rng() % 1000) / 333);
    eulervop::detail::integral_weights w;
    w.set(hl, n, 200);
    chebyshev_model I;
    ball I1;
    eulervop::detail::picard_residual_model(I, I1, a, hl, w, ball(), chebyshev_model(), 200);
    const represented f = pick(a, rng);
    const mpfr_real h = to_mpfr(arb_midref(hl.get()));
    for (const mpfr_real& s : points(rng)) {
      ball v;
      eulervop::detail::evaluate(v, I, point(s), truth_bits);
      ASSERT_TRUE(holds(v, h * integral_of(f, s))) << "trial " << trial << " at s = " << s;
    }
    ASSERT_TRUE(holds(I1, h * integral_of(f, mpfr_real(1)))) << "trial " << trial << ": at s = 1";
  }
}

// The Picard residual start + hl int_{-1}^s F - P of every F and P the models stand for, and r(1),
// against the same integral at 1000 bits.
TEST(ChebyshevModel, PicardResidualsHoldEveryResidual) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 40; ++trial) {
    const slong nf = 1 + static_cast<slong>(rng() % 84), np = 1 + static_cast<slong>(rng() % 42);
    const chebyshev_model F = random_model(rng, nf, 0.7, trial % 2 ? 80 : 0, trial % 3 == 0 ? 1e-15 : 0);
    const chebyshev_model P = random_model(rng, np, 0.5, trial % 4 ? 100 : 0, trial % 5 == 0 ? 1e-20 : 0);
    ball hl, start = decimal(static_cast<double>(rng() % 2001) / 1000 - 1);
    arb_set_d(hl.get(), 0.375 + static_cast<double>(rng() % 1000) / 333);
    eulervop::detail::integral_weights w;
    w.set(hl, nf, 177);
    chebyshev_model r;
    ball r1, at_start;  // start - P's polynomial at s = -1
    chebyshev_model polynomial = P;
    mag_zero(polynomial.remainder());
    eulervop::detail::evaluate(at_start, polynomial, point(mpfr_real(-1)), 177);
    arb_sub(at_start.get(), start.get(), at_start.get(), 177);
    eulervop::detail::picard_residual_model(r, r1, F, hl, w, at_start, P, 177);
    const represented f = pick(F, rng), p = pick(P, rng);
    const mpfr_real h = to_mpfr(arb_midref(hl.get())), y0 = to_mpfr(arb_midref(start.get()));
    const auto truth = [&](const mpfr_real& s) { return y0 + h * integral_of(f, s) - p(s); };
    for (const mpfr_real& s : points(rng)) {
      ball v;
      eulervop::detail::evaluate(v, r, point(s), truth_bits);
      ASSERT_TRUE(holds(v, truth(s))) << "trial " << trial << " at s = " << s;
    }
    ASSERT_TRUE(holds(r1, truth(mpfr_real(1)))) << "trial " << trial << ": r(1)";
  }
}

// The coefficients of the Lobatto interpolant: c_k = (2/N) sum_j'' v_j (-1)^k cos(k j pi / N),
// the ends halved (the transform the reference's dense output also rests on), from quad node
// values of every size and sign. Component 0 spans 2^-100 to 2^100; component 1 either lies
// within a factor 2^6 (every fold's lowest limb zero: the shorter products) or near 2^600 (its
// bound then in Arb's magnitudes instead of doubles).
TEST(BallNodeTransform, HoldsTheInterpolantsCoefficients) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const std::size_t N : {4u, 5u, 17u, 41u, 64u}) {
    eulervop::detail::ball_node_transform transform(177, N, 2);
    std::vector<std::vector<mpfr_real>> v(2, std::vector<mpfr_real>(N + 1));
    const bool narrow = N % 2 == 1;
    for (std::size_t j = 0; j <= N; ++j)
      for (std::size_t i = 0; i < 2; ++i) {
        const int e = i == 0 ? static_cast<int>(rng() % 200) - 100 : narrow ? static_cast<int>(rng() % 6) : 600;
        const eulervop::quad q = eulervop::quad(u(rng)) * ldexp(eulervop::quad(1), e) / 3;
        ball b;
        eulervop::set_exact(b, q);
        arb_set(transform.value(j, i), b.get());
        v[i][j] = mpfr_real(q);
      }
    arb_mat_t c;
    arb_mat_init(c, static_cast<slong>(N + 1), 2);
    transform.apply(c);
    const mpfr_real pi = boost::math::constants::pi<mpfr_real>();
    for (std::size_t i = 0; i < 2; ++i)
      for (std::size_t k = 0; k <= N; ++k) {
        mpfr_real sum = 0;
        for (std::size_t j = 0; j <= N; ++j) {
          mpfr_real term = v[i][j] * cos(pi * mpfr_real(k * j) / N);
          if (j == 0 || j == N) term /= 2;
          sum += term;
        }
        sum *= mpfr_real(2) / N;
        if (k % 2) sum = -sum;
        if (k == 0 || k == N) sum /= 2;
        ball x;
        arb_set(x.get(), arb_mat_entry(c, static_cast<slong>(k), static_cast<slong>(i)));
        EXPECT_TRUE(holds(x, sum)) << "N " << N << " k " << k;
        // As tight as the working precision: within 2^-170 of the values' sum of magnitudes.
        mpfr_real size = 0;
        for (const mpfr_real& vj : v[i]) size += abs(vj);
        EXPECT_LT(mpfr_real(mag_get_d(arb_radref(x.get()))), size * pow(mpfr_real(2), -170)) << "N " << N << " k " << k;
      }
    arb_mat_clear(c);
  }
}

// The 128-bit sums of Chebyshev products equal FLINT's exact ones, at the largest sizes fits()
// admits (and fits() refuses a size that could overflow).
TEST(ShortIntegerSeries, SumsOfProductsEqualFlintsExactOnes) {
  using eulervop::detail::short_integer_series;
  using eulervop::detail::wide_int;
  std::mt19937_64 rng(4);
  const auto random_poly = [&](eulervop::detail::integer_poly& p, std::size_t n, unsigned bits) {
    fmpz_poly_zero(p.p);
    for (std::size_t k = 0; k < n; ++k) {
      const auto magnitude = static_cast<std::int64_t>(rng() >> (64 - bits));  // below 2^bits, often at its top
      fmpz_poly_set_coeff_si(p.p, static_cast<slong>(k), rng() % 2 ? magnitude : -magnitude);
    }
  };
  EXPECT_FALSE(eulervop::detail::fits(62, 62, 90, 7));
  for (const auto& [la, lb, abits, bbits, count] :
       std::vector<std::tuple<std::size_t, std::size_t, unsigned, unsigned, std::size_t>>{
           {25, 15, 56, 40, 7}, {30, 90, 56, 58, 7}, {1, 40, 60, 50, 3}, {65, 65, 52, 56, 7}}) {
    ASSERT_TRUE(eulervop::detail::fits(abits, bbits, std::min(la, lb), count));
    std::vector<wide_int> sums(la + lb, 0);
    eulervop::detail::integer_poly total, term, a, b;
    for (std::size_t c = 0; c < count; ++c) {
      random_poly(a, la, abits);
      random_poly(b, lb, bbits);
      short_integer_series sa, sb;
      ASSERT_TRUE(sa.load(a.p));
      ASSERT_TRUE(sb.load(b.p));
      eulervop::detail::add_chebyshev_product(sums, sa, sb);
      eulervop::detail::grid_product_flint(term.p, a.p, b.p);
      fmpz_poly_add(total.p, total.p, term.p);
    }
    arf_t x, y;
    arf_init(x);
    arf_init(y);
    for (std::size_t k = 0; k < sums.size(); ++k) {
      eulervop::detail::set_wide(x, sums[k]);
      fmpz_t f;
      fmpz_init(f);
      fmpz_poly_get_coeff_fmpz(f, total.p, static_cast<slong>(k));
      arf_set_fmpz(y, f);
      fmpz_clear(f);
      EXPECT_TRUE(arf_equal(x, y)) << "coefficient " << k << " of lengths " << la << ", " << lb;
    }
    arf_clear(x);
    arf_clear(y);
  }
}

// f = a random integer below 2^b (60 random bits at a time).
void random_below(fmpz_t f, ulong b, std::mt19937_64& rng) {
  fmpz_zero(f);
  for (ulong w = 0; w < b; w += 60) {
    fmpz_mul_2exp(f, f, 60);
    fmpz_add_ui(f, f, rng() >> 4);
  }
  fmpz_fdiv_q_2exp(f, f, (b + 59) / 60 * 60 - b);
}

// A factor for the exact products' tests, of `len` coefficients. kind 0: random bit lengths up to
// `bits`, a sixth zero; 1: all +-(2^bits - 1), of one sign where same_sign; 2: decaying from
// `bits` bits by `decay` bits over the length, as a segment's coefficients. Random signs
// otherwise, and never the zero polynomial.
void random_factor(eulervop::detail::integer_poly& p, slong len, ulong bits, int kind, bool same_sign, ulong decay,
                   std::mt19937_64& rng) {
  fmpz_t f;
  fmpz_init(f);
  fmpz_poly_zero(p.p);
  for (slong k = 0; k < len; ++k) {
    if (kind == 1) {
      fmpz_one(f);
      fmpz_mul_2exp(f, f, bits);
      fmpz_sub_ui(f, f, 1);
      if (!same_sign && rng() % 2) fmpz_neg(f, f);
    } else {
      const long decayed = static_cast<long>(bits) - static_cast<long>(decay) * k / len;
      const ulong b = kind == 2 ? static_cast<ulong>(std::max(1L, decayed)) : 1 + rng() % bits;
      random_below(f, b - 1, rng);  // exactly b bits
      fmpz_setbit(f, b - 1);
      if (kind == 0 && rng() % 6 == 0) fmpz_zero(f);
      if (rng() % 2) fmpz_neg(f, f);
    }
    fmpz_poly_set_coeff_fmpz(p.p, k, f);
  }
  if (fmpz_poly_length(p.p) == 0) fmpz_poly_set_si(p.p, rng() % 2 ? 1 : -1);
  fmpz_clear(f);
}

// The Kronecker kernel's Chebyshev products (kronecker_product.hpp) equal FLINT's exact ones
// (grid_product_flint(), two fmpz_poly_mul), bit for bit, on random integer polynomials: lengths
// 1 to 90, 1 to 1200 bits, random signs and zeros, decaying magnitudes as a segment's, and
// coefficients all at +-(2^bits - 1) (every slot's sum at its bound); up to the largest factor the
// kernel takes, and one past it (then grid_product() falls back to FLINT).
TEST(KroneckerProduct, ChebyshevProductsEqualFlintsExactOnes) {
  namespace kr = eulervop::detail::kronecker;
  std::mt19937_64 rng(51);
  // Decaying from `bits` by `bits` over the length.
  const auto random_poly = [&](eulervop::detail::integer_poly& p, slong len, ulong bits, int kind, bool same_sign) {
    random_factor(p, len, bits, kind, same_sign, bits, rng);
  };
  eulervop::detail::integer_poly a, b, fast, flint;
  const auto check = [&](const char* what) {
    ASSERT_TRUE(eulervop::detail::kronecker_grid_product(fast.p, a.p, b.p)) << what;
    eulervop::detail::grid_product_flint(flint.p, a.p, b.p);
    EXPECT_TRUE(fmpz_poly_equal(fast.p, flint.p))
        << what << ": lengths " << fmpz_poly_length(a.p) << ", " << fmpz_poly_length(b.p) << ", bits "
        << fmpz_poly_max_bits(a.p) << ", " << fmpz_poly_max_bits(b.p);
  };
  for (int trial = 0; trial < 3000; ++trial) {
    const slong la = 1 + static_cast<slong>(rng() % 90), lb = 1 + static_cast<slong>(rng() % 90);
    const ulong bits = trial % 10 == 0 ? 1 + rng() % 1200 : 1 + rng() % 200;
    const int kind = static_cast<int>(rng() % 3);
    random_poly(a, la, bits, kind, rng() % 2);
    if (trial % 7 == 0) fmpz_poly_set(b.p, a.p); else random_poly(b, lb, 1 + rng() % 200, kind, rng() % 2);
    check("random");
  }
  // The largest factors taken: 2 + len b / 64 limbs at most kr::max_limbs, b = (w + 1) / 2 and
  // w = 2 bits + ceil(log2 len) + 1, so b = bits + 4 at len = 128 (then exactly kr::max_limbs).
  const slong len = 128;
  const ulong bits = static_cast<ulong>(kr::max_limbs - 2) * kr::limb_bits / len - 4;
  for (int kind = 0; kind < 3; ++kind) {
    random_poly(a, len, bits, kind == 0 ? 1 : kind, kind == 0);
    random_poly(b, len, bits, kind == 0 ? 1 : kind, false);
    check("largest");
  }
  random_poly(a, len, bits + 1, 1, true);  // one bit more: b + 1, two limbs more, FLINT's
  EXPECT_FALSE(eulervop::detail::kronecker_grid_product(fast.p, a.p, b.p));
  eulervop::detail::grid_product(fast.p, a.p, b.p);
  eulervop::detail::grid_product_flint(flint.p, a.p, b.p);
  EXPECT_TRUE(fmpz_poly_equal(fast.p, flint.p));
}

// The truncation onto a grid (fixed_point.hpp) equals Arb's arf_get_fmpz_fixed_si, integer and
// inexact flag, on random numbers of 1 to 300 bits (one to five limbs, the last Arb's), of both
// signs, with grids from far below to far above them, and on zero and exact powers of two.
TEST(FixedPoint, TruncatesAsArbDoes) {
  std::mt19937_64 rng(53);
  fmpz_t mine, arbs, m;
  fmpz_init(mine);
  fmpz_init(arbs);
  fmpz_init(m);
  arf_t x;
  arf_init(x);
  int truncated = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const ulong bits = 1 + rng() % 300;
    random_below(m, bits, rng);
    if (trial % 97 == 0) fmpz_one(m);
    if (trial % 89 == 0) fmpz_zero(m);
    if (rng() % 2) fmpz_neg(m, m);
    const slong exponent = static_cast<slong>(rng() % 600) - 300;
    arf_set_fmpz(x, m);
    arf_mul_2exp_si(x, x, exponent);
    const slong e = exponent + static_cast<slong>(rng() % 400) - 200;
    const bool a = eulervop::detail::fixed_fmpz(mine, x, e);
    const bool b = arf_get_fmpz_fixed_si(arbs, x, e) != 0;
    truncated += b;
    ASSERT_TRUE(fmpz_equal(mine, arbs) && a == b) << "bits " << bits << " exponent " << exponent << " grid " << e;
  }
  EXPECT_GT(truncated, 5000);
  arf_clear(x);
  fmpz_clear(mine);
  fmpz_clear(arbs);
  fmpz_clear(m);
}

// The kernel on 52-bit pieces (chunked_product.hpp) equals FLINT's exact products bit for bit:
// random lengths 1 to 96 and 1 to 208 bits, random signs and zeros, decaying magnitudes as a
// segment's (where grid_product() takes it), and at its limits every coefficient +-(2^208 - 1) at
// length 96 (the most terms in a column sum, each piece product at its largest) and each piece
// at 2^52 - 1 with both signs; one bit or one coefficient more is refused.
TEST(ChunkedProduct, ChebyshevProductsEqualFlintsExactOnes) {
  namespace ch = eulervop::detail::chunked;
  std::mt19937_64 rng(52);
  fmpz_t f;
  fmpz_init(f);
  // Decaying from `bits` by 113 bits over the length, as a quad segment's coefficients.
  const auto random_poly = [&](eulervop::detail::integer_poly& p, slong len, ulong bits, int kind) {
    random_factor(p, len, bits, kind, false, 113, rng);
  };
  eulervop::detail::integer_poly a, b, fast, flint;
  int taken = 0;
  const auto check = [&](bool forced, const char* what) {
    const bool done = ch::product(fast.p, a.p, b.p, !forced);
    if (forced) ASSERT_TRUE(done) << what;
    if (!done) return;
    ++taken;
    eulervop::detail::grid_product_flint(flint.p, a.p, b.p);
    EXPECT_TRUE(fmpz_poly_equal(fast.p, flint.p))
        << what << ": lengths " << fmpz_poly_length(a.p) << ", " << fmpz_poly_length(b.p) << ", bits "
        << fmpz_poly_max_bits(a.p) << ", " << fmpz_poly_max_bits(b.p);
  };
  for (int trial = 0; trial < 3000; ++trial) {
    const slong la = 1 + static_cast<slong>(rng() % ch::max_length), lb = 1 + static_cast<slong>(rng() % ch::max_length);
    const ulong bits = 1 + rng() % (ch::piece_bits * ch::max_pieces);
    const int kind = static_cast<int>(rng() % 3);
    random_poly(a, la, bits, kind);
    if (trial % 7 == 0) fmpz_poly_set(b.p, a.p); else random_poly(b, lb, 1 + rng() % (ch::piece_bits * ch::max_pieces), kind);
    check(trial % 2 == 0, "random");
  }
  EXPECT_GT(taken, 1500);
  // Where grid_product() takes it: the paper scene's factors (42 coefficients, 145 bits decaying).
  random_poly(a, 42, 145, 2);
  random_poly(b, 42, 145, 2);
  EXPECT_TRUE(eulervop::detail::chunked_grid_product(fast.p, a.p, b.p));
  // The limits: every coefficient +-(2^208 - 1) at the longest length.
  const ulong widest = ch::piece_bits * ch::max_pieces;
  random_poly(a, ch::max_length, widest, 1);
  random_poly(b, ch::max_length, widest, 1);
  check(true, "widest");
  fmpz_poly_set(b.p, a.p);
  check(true, "widest square");
  // One sign throughout: the column sums at their largest.
  for (slong k = 0; k < ch::max_length; ++k) {
    fmpz_poly_get_coeff_fmpz(f, a.p, k);
    fmpz_abs(f, f);
    fmpz_poly_set_coeff_fmpz(a.p, k, f);
  }
  fmpz_poly_set(b.p, a.p);
  check(true, "widest, one sign");
  fmpz_poly_neg(b.p, b.p);
  check(true, "widest, opposite signs");
  random_poly(a, ch::max_length, widest + 1, 1);
  EXPECT_FALSE(ch::product(fast.p, a.p, b.p, false));  // a fifth piece
  random_poly(a, ch::max_length + 1, 10, 0);
  EXPECT_FALSE(ch::product(fast.p, a.p, b.p, false));  // one coefficient more
  fmpz_clear(f);
}

// The sums of magnitudes (sup bounds, grid moves): never below the exact sum, computed in Arb at
// 5000 bits (exact for these inputs: the terms' exponents span less than 5000 bits), and never
// above Arb's own chain of mag_add (each partial sum rounded up to 30 bits), or the integers'
// exact sum, by more than 2^-28 of it (a mag's last bit and a double sum's few units). Inputs: balls of 30 to 430 bits with exponents from 2^-1100 to 2^12, exact zeros,
// radii of every size, and integers of up to 300 bits on grids 2^-200 to 2^200 (the fast path in
// doubles and, outside the doubles' range, Arb's mag arithmetic both taken).
TEST(MagnitudeSum, BoundsTheExactSumAndIsNoLooserThanArbsChain) {
  flint_rand_t state;
  flint_randinit(state);
  std::mt19937_64 rng(20261129);
  mag_value fast, chain, m, slack;
  arf_t exact, bound;
  arf_init(exact);
  arf_init(bound);
  for (int trial = 0; trial < 4000; ++trial) {
    const slong n = 1 + static_cast<slong>(rng() % 90);
    arb_ptr x = _arb_vec_init(n);
    for (slong k = 0; k < n; ++k) {
      arb_randtest(x + k, state, 30 + static_cast<slong>(rng() % 400), 12);
      if (rng() % 3 == 0) arb_mul_2exp_si(x + k, x + k, -static_cast<slong>(rng() % 1100));
      if (rng() % 5 == 0) mag_zero(arb_radref(x + k));
      if (rng() % 11 == 0) arb_zero(x + k);
    }
    const bool radii = trial % 2 == 1;
    if (radii) eulervop::detail::radius_sum(fast.m, x, n); else eulervop::detail::magnitude_sum(fast.m, x, n);
    arf_zero(exact);
    mag_zero(chain.m);
    for (slong k = 0; k < n; ++k) {
      if (!radii) {
        arf_abs(bound, arb_midref(x + k));
        arf_add(exact, exact, bound, 5000, ARF_RND_UP);
      }
      arf_set_mag(bound, arb_radref(x + k));
      arf_add(exact, exact, bound, 5000, ARF_RND_UP);
      if (radii) mag_set(m.m, arb_radref(x + k)); else arb_get_mag(m.m, x + k);
      mag_add(chain.m, chain.m, m.m);
    }
    arf_set_mag(bound, fast.m);
    EXPECT_GE(arf_cmp(bound, exact), 0) << "trial " << trial;
    mag_mul_2exp_si(slack.m, chain.m, -28);
    mag_add(slack.m, slack.m, chain.m);
    EXPECT_LE(mag_cmp(fast.m, slack.m), 0) << "trial " << trial;
    EXPECT_EQ(mag_is_zero(fast.m), arf_is_zero(exact)) << "trial " << trial;
    _arb_vec_clear(x, n);
  }
  {
    // (1 - 2^-53) + 10 (3 2^-55): the first term's bound is 1 exactly, and each later partial sum
    // would round down to it in double (to nearest): the bound must still reach the exact sum.
    arb_ptr x = _arb_vec_init(11);
    arb_one(x);
    arb_set_ui(x + 1, 1);
    arb_mul_2exp_si(x + 1, x + 1, -53);
    arb_sub(x, x, x + 1, ARF_PREC_EXACT);
    for (slong k = 1; k < 11; ++k) {
      arb_set_ui(x + k, 3);
      arb_mul_2exp_si(x + k, x + k, -55);
    }
    eulervop::detail::magnitude_sum(fast.m, x, 11);
    arf_set_ui(exact, 26);  // 30 2^-55 - 2^-53
    arf_mul_2exp_si(exact, exact, -55);
    arf_add_ui(exact, exact, 1, ARF_PREC_EXACT, ARF_RND_DOWN);
    arf_set_mag(bound, fast.m);
    EXPECT_GE(arf_cmp(bound, exact), 0);
    _arb_vec_clear(x, 11);
  }
  fmpz_t e, a;
  fmpz_init(e);
  fmpz_init(a);
  for (int trial = 0; trial < 4000; ++trial) {
    const slong n = 1 + static_cast<slong>(rng() % 90);
    const slong grid = static_cast<slong>(rng() % 401) - 200;
    fmpz* c = _fmpz_vec_init(n);
    for (slong k = 0; k < n; ++k) fmpz_randtest(c + k, state, 1 + static_cast<slong>(rng() % 300));
    eulervop::detail::magnitude_sum(fast.m, c, n, grid);
    fmpz_zero(e);
    for (slong k = 0; k < n; ++k) {
      fmpz_abs(a, c + k);
      fmpz_add(e, e, a);
    }
    fmpz_set_si(a, grid);
    arf_set_fmpz_2exp(exact, e, a);  // the exact sum
    arf_set_mag(bound, fast.m);
    EXPECT_GE(arf_cmp(bound, exact), 0) << "integers, trial " << trial;
    arf_mul_2exp_si(bound, exact, -28);
    arf_add(exact, exact, bound, ARF_PREC_EXACT, ARF_RND_DOWN);
    arf_set_mag(bound, fast.m);
    EXPECT_LE(arf_cmp(bound, exact), 0) << "integers, trial " << trial;
    _fmpz_vec_clear(c, n);
  }
  fmpz_clear(e);
  fmpz_clear(a);
  arf_clear(exact);
  arf_clear(bound);
  flint_randclear(state);
}

// A model's tail cut at a level (length_above, which truncate_below and the rows take): the dropped
// coefficients' magnitudes (midpoints and radii, summed exactly at 5000 bits) never exceed the
// level and never exceed the returned tail, and the cut is not early: one more coefficient would
// pass the level (up to 2^-20 of it, the rounded-up partial sums' few units over at most 90
// terms). Coefficients fall off by 0 to 8 bits each from 2^12 down, sometimes below the doubles'
// range, and levels reach 2^-1200, so both the sum in doubles and Arb's mag chain are taken.
TEST(LengthAbove, DropsAtMostTheLevelAndBoundsWhatItDrops) {
  flint_rand_t state;
  flint_randinit(state);
  std::mt19937_64 rng(20261130);
  mag_value tail, level;
  arf_t dropped, next, t, cap;
  arf_init(dropped);
  arf_init(next);
  arf_init(t);
  arf_init(cap);
  for (int trial = 0; trial < 4000; ++trial) {
    const slong n = 1 + static_cast<slong>(rng() % 90);
    const slong drop = static_cast<slong>(rng() % 9);
    eulervop::detail::chebyshev_model a;
    a.resize(n);
    for (slong k = 0; k < n; ++k) {
      arb_randtest(a.coeff(k), state, 30 + static_cast<slong>(rng() % 400), 4);
      arb_mul_2exp_si(a.coeff(k), a.coeff(k), 8 - drop * k - (trial % 7 == 0 ? 1000 : 0));
      if (rng() % 11 == 0) arb_zero(a.coeff(k));
    }
    mag_set_ui_2exp_si(level.m, 1 + rng() % 1000, -static_cast<slong>(rng() % (trial % 5 == 0 ? 1200 : 300)));
    const slong keep = eulervop::detail::length_above(a, level.m, tail.m);
    ASSERT_GE(keep, 1) << "trial " << trial;
    ASSERT_LE(keep, n) << "trial " << trial;
    arf_zero(dropped);
    for (slong k = keep; k < n; ++k) {
      arf_abs(t, arb_midref(a.coeff(k)));
      arf_add(dropped, dropped, t, 5000, ARF_RND_UP);
      arf_set_mag(t, arb_radref(a.coeff(k)));
      arf_add(dropped, dropped, t, 5000, ARF_RND_UP);
    }
    arf_set_mag(cap, level.m);
    EXPECT_LE(arf_cmp(dropped, cap), 0) << "trial " << trial << ": more than the level dropped";
    arf_set_mag(t, tail.m);
    EXPECT_GE(arf_cmp(t, dropped), 0) << "trial " << trial << ": the tail below what was dropped";
    if (keep > 1) {
      arf_abs(t, arb_midref(a.coeff(keep - 1)));
      arf_add(next, dropped, t, 5000, ARF_RND_DOWN);
      arf_set_mag(t, arb_radref(a.coeff(keep - 1)));
      arf_add(next, next, t, 5000, ARF_RND_DOWN);
      arf_mul_2exp_si(t, cap, -20);
      arf_sub(cap, cap, t, 5000, ARF_RND_DOWN);
      EXPECT_GT(arf_cmp(next, cap), 0) << "trial " << trial << ": cut early at " << keep << " of " << n;
    }
  }
  arf_clear(dropped);
  arf_clear(next);
  arf_clear(t);
  arf_clear(cap);
  flint_randclear(state);
}

// A table of T_k(s) at 64 bits made from one at 177 bits (the rows' two tables, ball_certifier's
// evaluate_row) holds T_k at every point of s, checked against cos(k acos x) in MPFR at 1000 bits
// at both ends and the midpoint of random balls s (and s = -1, 1), up to k = 60, beyond the finer
// table's 42 values. Where it rounds the finer table, its radius is that of a 64-bit rounding,
// at most 2^-63 more than the finer one's (|T_k| <= 1), where the recurrence at 64 bits widens
// like 2.4^k 2^-64: no wider than that recurrence from k = 8 on.
TEST(ChebyshevValues, RoundedFromAFinerTableHoldEveryValueAndAreNoWider) {
  std::mt19937_64 rng(20261129);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    eulervop::ball s;
    arb_set_d(s.get(), unit(rng));
    arb_div_ui(s.get(), s.get(), 3, 177);  // a ball with a radius, as a row's s
    if (trial % 10 == 0) arb_set_si(s.get(), trial % 20 == 0 ? 1 : -1);  // the segment's ends
    eulervop::detail::chebyshev_values finer(42, s, 177), coarse, plain(60, s, 64);
    coarse.assign_rounded(60, s, finer, 64);
    ASSERT_EQ(coarse.length(), 60);
    for (slong k = 0; k < 60; ++k) {
      if (k < 42) {
        mag_t bound;
        mag_init(bound);
        mag_set_ui_2exp_si(bound, 1, -63);
        mag_add(bound, bound, arb_radref(finer.get() + k));
        EXPECT_LE(mag_cmp(arb_radref(coarse.get() + k), bound), 0) << k;
        mag_clear(bound);
      }
      if (k >= 8) EXPECT_LE(mag_cmp(arb_radref(coarse.get() + k), arb_radref(plain.get() + k)), 0) << k;
      for (int end = -1; end <= 1; ++end) {
        mpfr_t x, t;
        mpfr_init2(x, 1000);
        mpfr_init2(t, 1000);
        arf_get_mpfr(x, arb_midref(s.get()), MPFR_RNDN);
        mpfr_t r;
        mpfr_init2(r, 1000);
        arf_t rad;
        arf_init(rad);
        arf_set_mag(rad, arb_radref(s.get()));
        arf_get_mpfr(r, rad, MPFR_RNDN);  // exact: a radius has 30 bits
        arf_clear(rad);
        if (end < 0) mpfr_sub(x, x, r, MPFR_RNDN);
        if (end > 0) mpfr_add(x, x, r, MPFR_RNDN);
        if (mpfr_cmp_si(x, 1) > 0) mpfr_set_si(x, 1, MPFR_RNDN);
        if (mpfr_cmp_si(x, -1) < 0) mpfr_set_si(x, -1, MPFR_RNDN);
        mpfr_acos(t, x, MPFR_RNDN);
        mpfr_mul_si(t, t, k, MPFR_RNDN);
        mpfr_cos(t, t, MPFR_RNDN);
        eulervop::ball exact;  // within 2^-900 of T_k at that point (MPFR's own rounding)
        arf_set_mpfr(arb_midref(exact.get()), t);
        mag_set_ui_2exp_si(arb_radref(exact.get()), 1, -900);
        EXPECT_TRUE(arb_overlaps(coarse.get() + k, exact.get())) << "k " << k << " trial " << trial;
        mpfr_clear(x);
        mpfr_clear(t);
        mpfr_clear(r);
      }
    }
  }
}

}  // namespace
