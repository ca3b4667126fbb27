// The certificate's shortcuts keep what they claim: a product on 52-bit pieces that leaves out
// its lowest pieces' products moves by no more than the bound it reports; a residual loaded onto
// its grid with each component's scale as an exponent gives the integers of a scaled copy; the box
// algebra, which skips terms with an exactly zero factor, gives the balls of the full formulas;
// and an inverse enclosed by a Neumann series from an approximate one holds the exact inverse.
#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/ball_lohner_box.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/chunked_product.hpp>
#include <eulervop/certify/detail/field_algebra.hpp>
#include <eulervop/certify/detail/grid_models.hpp>
#include <eulervop/certify/detail/small_solve.hpp>

#include <arb.h>
#include <arb_mat.h>
#include <flint/fmpz.h>
#include <flint/fmpz_poly.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

namespace {

using eulervop::ball;
using eulervop::mag_value;

// A factor of `len` coefficients decaying from `bits` bits by 113 over the length (a quad
// segment's), random signs.
void decaying_factor(eulervop::detail::integer_poly& p, slong len, ulong bits, std::mt19937_64& rng) {
  fmpz_t f;
  fmpz_init(f);
  fmpz_poly_zero(p.p);
  for (slong k = 0; k < len; ++k) {
    const ulong b = static_cast<ulong>(std::max<long>(1, static_cast<long>(bits) - 113 * k / len));
    fmpz_zero(f);
    for (ulong w = 0; w < b; w += 60) {
      fmpz_mul_2exp(f, f, 60);
      fmpz_add_ui(f, f, rng() >> 4);
    }
    fmpz_fdiv_q_2exp(f, f, (b + 59) / 60 * 60 - b);
    fmpz_setbit(f, b - 1);
    if (rng() % 2) fmpz_neg(f, f);
    fmpz_poly_set_coeff_fmpz(p.p, k, f);
  }
  fmpz_clear(f);
}

// sum_k |x_k - y_k| <= bound (a mag), exactly: the sum as an integer against the bound as an arf.
bool within(const fmpz_poly_t x, const fmpz_poly_t y, const mag_t bound) {
  fmpz_t d, sum;
  fmpz_init(d);
  fmpz_init(sum);
  const slong n = std::max(fmpz_poly_length(x), fmpz_poly_length(y));
  for (slong k = 0; k < n; ++k) {
    fmpz_t a, b;
    fmpz_init(a);
    fmpz_init(b);
    fmpz_poly_get_coeff_fmpz(a, x, k);
    fmpz_poly_get_coeff_fmpz(b, y, k);
    fmpz_sub(d, a, b);
    fmpz_abs(d, d);
    fmpz_add(sum, sum, d);
    fmpz_clear(a);
    fmpz_clear(b);
  }
  arf_t s, m;
  arf_init(s);
  arf_init(m);
  arf_set_fmpz(s, sum);
  arf_set_mag(m, bound);
  const bool ok = arf_cmp(s, m) <= 0;
  arf_clear(s);
  arf_clear(m);
  fmpz_clear(d);
  fmpz_clear(sum);
  return ok;
}

// The exact product is FLINT's (grid_product_flint()). With an allowance, the pieces' kernel leaves
// out the products that fit in it, and sum_k |2 c_k - 2 c~_k| <= 2 `dropped` (each left-out
// product enters 2 c_k twice); the allowance below the lowest pieces' products leaves out nothing.
TEST(ChunkedProduct, LeftOutProductsStayWithinTheirBound) {
  namespace ch = eulervop::detail::chunked;
  std::mt19937_64 rng(12);
  eulervop::detail::integer_poly a, b, exact, cut;
  int left_out = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const slong la = 20 + static_cast<slong>(rng() % 60), lb = 20 + static_cast<slong>(rng() % 60);
    decaying_factor(a, la, 100 + rng() % 100, rng);
    decaying_factor(b, lb, 100 + rng() % 100, rng);
    eulervop::detail::grid_product_flint(exact.p, a.p, b.p);
    mag_value allowance, dropped;
    mag_set_ui_2exp_si(allowance.m, 1, 100 + static_cast<slong>(rng() % 200));
    ASSERT_TRUE(ch::product(cut.p, a.p, b.p, false, allowance.m, dropped.m)) << "trial " << trial;
    EXPECT_LE(mag_cmp(dropped.m, allowance.m), 0) << "trial " << trial;
    mag_value twice;
    mag_mul_2exp_si(twice.m, dropped.m, 1);
    EXPECT_TRUE(within(exact.p, cut.p, twice.m)) << "trial " << trial;
    if (!mag_is_zero(dropped.m)) ++left_out;
    if (mag_is_zero(dropped.m)) EXPECT_TRUE(fmpz_poly_equal(exact.p, cut.p)) << "trial " << trial;
  }
  EXPECT_GT(left_out, 100);
  // An allowance of 1 (below any nonzero product of pieces): the exact product.
  decaying_factor(a, 42, 145, rng);
  decaying_factor(b, 42, 145, rng);
  mag_value one, dropped;
  mag_one(one.m);
  ASSERT_TRUE(ch::product(cut.p, a.p, b.p, false, one.m, dropped.m));
  eulervop::detail::grid_product_flint(exact.p, a.p, b.p);
  EXPECT_TRUE(mag_is_zero(dropped.m));
  EXPECT_TRUE(fmpz_poly_equal(exact.p, cut.p));
}

// A model with random coefficients (`len` of them, random radii, magnitudes 2^-40 .. 1 times
// 2^scale) and a remainder.
eulervop::detail::chebyshev_model random_model(slong len, slong scale, bool zero_midpoints, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  eulervop::detail::chebyshev_model m(len);
  for (slong k = 0; k < len; ++k) {
    if (!zero_midpoints) {
      arb_set_d(m.coeff(k), std::ldexp(u(rng), -static_cast<int>(rng() % 40)));
      arb_mul_2exp_si(m.coeff(k), m.coeff(k), scale);
    }
    if (rng() % 3 == 0) mag_set_ui_2exp_si(arb_radref(m.coeff(k)), 1, scale - 60 - static_cast<slong>(rng() % 20));
  }
  mag_set_ui_2exp_si(m.remainder(), 1, scale - 70);
  return m;
}

// grid_models::load with shifts gives the same exponent, integers, remainders and magnitudes as a
// load of copies scaled by those powers of two, with a model whose midpoints are all zero and a
// zero model among them.
TEST(GridModels, AShiftedLoadEqualsALoadOfTheScaledModels) {
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t D = 3 + 4 * (trial % 2);
    std::vector<eulervop::detail::chebyshev_model> m, scaled(D);
    std::vector<slong> shift(D);
    for (std::size_t i = 0; i < D; ++i) {
      m.push_back(random_model(1 + static_cast<slong>(rng() % 60), static_cast<slong>(rng() % 200) - 100,
                               i == 1 && trial % 3 == 0, rng));
      if (i == 2 && trial % 5 == 0) m.back().set_zero();
      shift[i] = static_cast<slong>(rng() % 101) - 50;
      scaled[i] = m[i];
      for (slong k = 0; k < scaled[i].length(); ++k) arb_mul_2exp_si(scaled[i].coeff(k), scaled[i].coeff(k), shift[i]);
      mag_mul_2exp_si(scaled[i].remainder(), scaled[i].remainder(), shift[i]);
    }
    eulervop::detail::grid_models by_shift(D), by_copy(D);
    by_shift.load(m, 56, shift);
    by_copy.load(scaled, 56);
    ASSERT_EQ(by_shift.exponent(), by_copy.exponent()) << "trial " << trial;
    for (std::size_t i = 0; i < D; ++i) {
      EXPECT_TRUE(fmpz_poly_equal(by_shift.poly(i), by_copy.poly(i))) << "trial " << trial << " model " << i;
      EXPECT_TRUE(mag_equal(by_shift.remainder(i).m, by_copy.remainder(i).m)) << "trial " << trial << " model " << i;
      EXPECT_TRUE(mag_equal(by_shift.magnitude(i).m, by_copy.magnitude(i).m)) << "trial " << trial << " model " << i;
    }
  }
}

// A box jet of n variables with random balls, a third of its gradient and Hessian exactly zero.
eulervop::detail::box_jet random_jet(std::size_t n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-2, 2);
  const auto random_ball = [&](ball& x) {
    if (rng() % 3 == 0) return;
    arb_set_d(x.get(), u(rng));
    mag_set_d(arb_radref(x.get()), std::abs(u(rng)) * 1e-9);
  };
  eulervop::detail::box_jet v;
  random_ball(v.f);
  v.g.resize(n);
  v.H.resize(n * n);
  for (ball& x : v.g) random_ball(x);
  for (ball& x : v.H) random_ball(x);
  return v;
}

bool same(const eulervop::detail::box_jet& a, const eulervop::detail::box_jet& b) {
  bool ok = arb_equal(a.f.get(), b.f.get());
  for (std::size_t k = 0; k < a.g.size(); ++k) ok = ok && arb_equal(a.g[k].get(), b.g[k].get());
  for (std::size_t k = 0; k < a.H.size(); ++k) ok = ok && arb_equal(a.H[k].get(), b.H[k].get());
  return ok;
}

// box_algebra's product, sum, difference, scaling and function of a jet give the very balls of
// the full formulas (every term, zero factors included, in the same order): the formulas written
// out here term by term.
TEST(BoxAlgebra, SkippedZeroTermsLeaveTheSameBalls) {
  const slong prec = 64;
  const std::size_t n = 7;
  const eulervop::detail::box_algebra alg(prec, n);
  std::mt19937_64 rng(14);
  for (int trial = 0; trial < 300; ++trial) {
    const eulervop::detail::box_jet a = random_jet(n, rng), b = random_jet(n, rng);
    // a b: H = H_a f_b + f_a H_b + g_a g_b^T + g_b g_a^T, g = g_a f_b + f_a g_b.
    eulervop::detail::box_jet full = a;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) {
        arb_ptr h = full.H[i * n + j].get();
        arb_mul(h, h, b.f.get(), prec);
        arb_addmul(h, a.f.get(), b.H[i * n + j].get(), prec);
        arb_addmul(h, a.g[i].get(), b.g[j].get(), prec);
        arb_addmul(h, b.g[i].get(), a.g[j].get(), prec);
      }
    for (std::size_t k = 0; k < n; ++k) {
      ball t;
      arb_mul(t.get(), a.g[k].get(), b.f.get(), prec);
      arb_addmul(t.get(), a.f.get(), b.g[k].get(), prec);
      full.g[k] = t;
    }
    arb_mul(full.f.get(), full.f.get(), b.f.get(), prec);
    eulervop::detail::box_jet fast = a;
    alg.mul(fast, b);
    EXPECT_TRUE(same(fast, full)) << "product, trial " << trial;
    // a + b, a - b, a x.
    eulervop::detail::box_jet sum = a, sum_full = a, diff = a, diff_full = a, scaled = a, scaled_full = a;
    alg.add(sum, b);
    alg.sub(diff, b);
    const ball x(3);
    alg.scale(scaled, x);
    arb_add(sum_full.f.get(), sum_full.f.get(), b.f.get(), prec);
    arb_sub(diff_full.f.get(), diff_full.f.get(), b.f.get(), prec);
    arb_mul(scaled_full.f.get(), scaled_full.f.get(), x.get(), prec);
    for (std::size_t k = 0; k < n; ++k) {
      arb_add(sum_full.g[k].get(), sum_full.g[k].get(), b.g[k].get(), prec);
      arb_sub(diff_full.g[k].get(), diff_full.g[k].get(), b.g[k].get(), prec);
      arb_mul(scaled_full.g[k].get(), scaled_full.g[k].get(), x.get(), prec);
    }
    for (std::size_t k = 0; k < n * n; ++k) {
      arb_add(sum_full.H[k].get(), sum_full.H[k].get(), b.H[k].get(), prec);
      arb_sub(diff_full.H[k].get(), diff_full.H[k].get(), b.H[k].get(), prec);
      arb_mul(scaled_full.H[k].get(), scaled_full.H[k].get(), x.get(), prec);
    }
    EXPECT_TRUE(same(sum, sum_full)) << "sum, trial " << trial;
    EXPECT_TRUE(same(diff, diff_full)) << "difference, trial " << trial;
    EXPECT_TRUE(same(scaled, scaled_full)) << "scaling, trial " << trial;
    // exp(a): H = f' H_a + f'' g g^T, g = f' g_a, f, f' and f'' over a's ball.
    eulervop::detail::box_jet e = a, e_full = a;
    alg.function(eulervop::detail::elementary::exp, e);
    ball v, d1, d2;
    ASSERT_TRUE(eulervop::detail::elementary_on_ball(eulervop::detail::elementary::exp, a.f, &v, &d1, &d2, prec));
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) {
        ball gg;
        arb_ptr h = e_full.H[i * n + j].get();
        arb_mul(h, h, d1.get(), prec);
        arb_mul(gg.get(), a.g[i].get(), a.g[j].get(), prec);
        arb_addmul(h, gg.get(), d2.get(), prec);
      }
    for (ball& y : e_full.g) arb_mul(y.get(), y.get(), d1.get(), prec);
    e_full.f = v;
    EXPECT_TRUE(same(e, e_full)) << "exp, trial " << trial;
  }
}

// The exact inverse of a matrix of doubles (arb_mat_inv at 400 bits: radii far below the ones
// tested) lies in enclose_inverse's balls, from Gaussian elimination's X (conditions up to about
// 1e7) and from Q^T for an orthogonal Q; up to conditions of about 1e5 the balls are tight: the
// radius is at most d^2 / (1 - d) |X|_inf plus E X's rounding at 64 bits, with d about 1e-11 there,
// so below 2^-60 |X|_inf. A matrix of rank one, or an X off by a factor of two (d = 1), is refused.
TEST(LohnerBox, NeumannInverseHoldsTheExactInverse) {
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto holds_inverse = [](const std::vector<double>& M, std::size_t D, const std::vector<ball>& inv) {
    arb_mat_t m, r;
    arb_mat_init(m, static_cast<slong>(D), static_cast<slong>(D));
    arb_mat_init(r, static_cast<slong>(D), static_cast<slong>(D));
    for (std::size_t q = 0; q < D * D; ++q)
      arb_set_d(arb_mat_entry(m, static_cast<slong>(q / D), static_cast<slong>(q % D)), M[q]);
    bool ok = arb_mat_inv(r, m, 400) != 0;
    for (std::size_t q = 0; q < D * D && ok; ++q)
      ok = arb_contains(inv[q].get(), arb_mat_entry(r, static_cast<slong>(q / D), static_cast<slong>(q % D)));
    arb_mat_clear(m);
    arb_mat_clear(r);
    return ok;
  };
  const auto tight = [](const std::vector<double>& X, std::size_t D, const std::vector<ball>& inv) {
    double norm = 0;
    for (std::size_t i = 0; i < D; ++i) {
      double row = 0;
      for (std::size_t j = 0; j < D; ++j) row += std::abs(X[i * D + j]);
      norm = std::max(norm, row);
    }
    for (const ball& x : inv)
      if (!(mag_get_d(arb_radref(x.get())) <= std::ldexp(norm, -60))) return false;
    return true;
  };
  for (int trial = 0; trial < 300; ++trial) {
    const std::size_t D = trial % 2 ? 7 : 3;
    std::vector<double> M(D * D), X;
    // A random matrix times diag(1, ..., 10^-s), s = 0 .. 6.
    const double s = static_cast<double>(trial % 7);
    for (std::size_t q = 0; q < D * D; ++q) M[q] = u(rng) * std::pow(10.0, -s * static_cast<double>(q % D) / static_cast<double>(D - 1));
    ASSERT_TRUE(eulervop::detail::approximate_inverse(M, D, X)) << "trial " << trial;
    std::vector<ball> inv;
    ASSERT_TRUE(eulervop::detail::enclose_inverse(M, X, D, inv)) << "trial " << trial;
    EXPECT_TRUE(holds_inverse(M, D, inv)) << "trial " << trial;
    if (s <= 4) EXPECT_TRUE(tight(X, D, inv)) << "trial " << trial;
  }
  // Q from Gram-Schmidt on a random matrix, X = Q^T.
  const std::size_t D = 7;
  std::vector<double> Q(D * D), QT(D * D);
  for (double& q : Q) q = u(rng);
  for (std::size_t c = 0; c < D; ++c) {
    for (std::size_t p = 0; p < c; ++p) {
      double dot = 0;
      for (std::size_t i = 0; i < D; ++i) dot += Q[i * D + c] * Q[i * D + p];
      for (std::size_t i = 0; i < D; ++i) Q[i * D + c] -= dot * Q[i * D + p];
    }
    double len = 0;
    for (std::size_t i = 0; i < D; ++i) len += Q[i * D + c] * Q[i * D + c];
    for (std::size_t i = 0; i < D; ++i) Q[i * D + c] /= std::sqrt(len);
  }
  for (std::size_t i = 0; i < D; ++i)
    for (std::size_t j = 0; j < D; ++j) QT[i * D + j] = Q[j * D + i];
  std::vector<ball> inv;
  ASSERT_TRUE(eulervop::detail::enclose_inverse(Q, QT, D, inv));
  EXPECT_TRUE(holds_inverse(Q, D, inv));
  EXPECT_TRUE(tight(QT, D, inv));
  // Refused: rank one (no approximate inverse, or none whose E is below 1), and X = 2 M^-1.
  std::vector<double> rank_one(D * D), X(D * D);
  for (std::size_t q = 0; q < D * D; ++q) rank_one[q] = static_cast<double>(1 + q / D) * static_cast<double>(1 + q % D);
  EXPECT_FALSE(eulervop::detail::enclose_general_inverse(rank_one, D, 1e6, inv));
  for (std::size_t q = 0; q < D * D; ++q) X[q] = 2 * QT[q];
  EXPECT_FALSE(eulervop::detail::enclose_inverse(Q, X, D, inv));
}

}  // namespace
