// The fixed-point matrix-vector product of the wide residual (detail/fixed_point_matvec.hpp),
// on the reference integrator's own Picard matrix S.
//
// Provenance of the reference values: the same products with the entries of A and x taken
// exactly into MPFR at 400 decimal digits (1330 bits: enough for every product of two 600-bit
// numbers and the sum of 73 of them to be exact), so the comparison measures the kernel's error alone. The bound checked is the one the
// header derives: 2^-(p+3) n max_k |A_rk| max|x| + ulp(y_r) (the quad form, 2^-116 n ... +
// 2 ulp, is tighter than this for p = 113).
#include <eulervop/reference/detail/chebyshev_basis.hpp>
#include <eulervop/reference/detail/fixed_point_matvec.hpp>
#include <eulervop/core/scalar.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;

using exact = boost::multiprecision::number<boost::multiprecision::mpfr_float_backend<400>>;

template <class T>
exact to_exact(const T& x) {
  if constexpr (std::is_same_v<T, quad>)
    return exact(x);
  else
    return exact(x.backend().data());
}

// Vectors like the integrator's f(X): smooth node values, an offset, a small part below the
// leading digits, zeros, and entries far below the largest (which the kernel may truncate).
template <class T>
std::vector<T> test_vector(std::mt19937_64& rng, std::size_t n, int kind) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<T> x(n);
  for (std::size_t k = 0; k < n; ++k) {
    x[k] = T(u(rng)) + T(u(rng)) * T(1e-17) + T(u(rng)) * T(1e-34);
    if (kind == 1) x[k] += T(3);
    if (kind == 2 && k % 3 == 0) x[k] = 0;
    if (kind == 3 && k % 2 == 0) x[k] *= T(1e-40);
  }
  return x;
}

// Largest error in units of the derived bound (must be <= 1), over several vectors.
template <class T>
// `bits` is the precision of T; the matrix resolves matrix_bits (default: the same).
double worst_error_over_bound(std::size_t degree, unsigned bits, unsigned matrix_bits = 0) {
  if (matrix_bits == 0) matrix_bits = bits;
  const std::size_t n1 = degree + 1;
  const eulervop::detail::chebyshev_basis<T> basis(degree);
  eulervop::detail::fixed_point_matrix<T> fx = [&] {
    if constexpr (std::is_same_v<T, quad>)
      return eulervop::detail::fixed_point_matrix<T>(basis.integral, n1, n1);
    else
      return eulervop::detail::fixed_point_matrix<T>(basis.integral, n1, n1, matrix_bits);
  }();
  std::mt19937_64 rng(7);
  double worst = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const std::vector<T> x = test_vector<T>(rng, n1, trial % 4);
    std::vector<T> y(n1);
    fx.multiply(x.data(), y.data(), 1);
    exact xmax = 0;
    for (const T& v : x) xmax = std::max(xmax, exact(abs(to_exact(v))));
    for (std::size_t r = 1; r < n1; ++r) {
      exact sum = 0, amax = 0;
      for (std::size_t k = 0; k < n1; ++k) {
        const exact a = to_exact(basis.integral[r * n1 + k]);
        sum += a * to_exact(x[k]);
        amax = std::max(amax, exact(abs(a)));
      }
      const exact err = abs(to_exact(y[r]) - sum);
      const exact ulp = ldexp(abs(sum), 1 - static_cast<int>(bits));
      const exact bound = ldexp(exact(n1) * amax * xmax, -static_cast<int>(matrix_bits) - 3) + ulp;
      worst = std::max(worst, static_cast<double>(err / bound));
    }
  }
  return worst;
}

TEST(FixedPointMatvec, QuadWithinDerivedBound) {
  EXPECT_LE(worst_error_over_bound<quad>(41, 113), 1.0);
}

// 64, 256, 320 bits: 2, 5 and 6 limbs (the unrolled kernels); 600 bits: 10 limbs (mpn_mul_n).
TEST(FixedPointMatvec, MpfrWithinDerivedBound) {
  for (unsigned requested : {64u, 256u, 320u, 600u}) {
    eulervop::mpfr_precision_scope scope(requested);
    const unsigned bits = eulervop::significand_bits<mpfr_real>();
    EXPECT_LE(worst_error_over_bound<mpfr_real>(72, bits), 1.0) << bits << " bits";
  }
}

// The integrator's case of a tolerance looser than the precision: 256-bit numbers, products
// resolved to 223 bits (4 limbs), 188 bits (3 limbs: the first residual's matrix,
// picard_matrices.hpp), 130 bits (3 limbs) and 100 bits (2 limbs).
TEST(FixedPointMatvec, MpfrWithFewerMatrixBitsWithinDerivedBound) {
  eulervop::mpfr_precision_scope scope(256);
  const unsigned bits = eulervop::significand_bits<mpfr_real>();
  for (unsigned matrix_bits : {223u, 188u, 130u, 100u})
    EXPECT_LE(worst_error_over_bound<mpfr_real>(72, bits, matrix_bits), 1.0) << matrix_bits << " matrix bits";
}

// A zero vector gives exact zeros (no scaling of an all-zero vector).
// Where A and x enter exactly (A: multiples of 2^-20 below 1; x: 113-bit numbers within 3
// binades of the largest, down to the last bit the images keep), the only rounding left is that
// of the exact integer sum: every row must be that sum rounded once to 113 bits, to nearest with
// ties to even. Reference: the same sum exact in MPFR (1330 bits) and rounded to 113 bits by
// mpfr_set. Sums of both signs, ties (x made of halves of an ulp), and rows whose sum fits in 64
// bits.
TEST(FixedPointMatvec, ExactImagesAreRoundedOnceToNearestEven) {
  constexpr std::size_t rows = 64, cols = 9;
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> entry(-(1 << 20) + 1, (1 << 20) - 1);
  std::vector<quad> a(rows * cols);
  for (auto& v : a) v = ldexp(quad(entry(rng)), -20);
  a[0] = 1;  // row 0 sums x alone where the other entries vanish
  for (std::size_t k = 1; k < cols; ++k) a[k] = k == 1 ? 1 : 0;
  eulervop::detail::fixed_point_matrix<quad> fx(a, rows, cols);
  std::uniform_int_distribution<std::uint64_t> bits64;
  std::uniform_int_distribution<int> binade(-3, 0);
  mpfr_t rounded;
  mpfr_init2(rounded, 113);
  int ties = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<quad> x(cols);
    for (std::size_t k = 0; k < cols; ++k) {
      // A 113-bit significand 2^112 + m, m < 2^112 from two 64-bit draws.
      const quad m = ldexp(quad(bits64(rng) >> 16), 64) + quad(bits64(rng));
      x[k] = ldexp(ldexp(quad(1), 112) + m, binade(rng) - 112);
      if (bits64(rng) & 1) x[k] = -x[k];
    }
    x[0] = 1;  // the largest: the images keep bits down to 2^-115
    if (trial % 4 == 0) x[1] = ldexp(quad(trial % 8 == 0 ? 1 : 3), -113);  // row 0: 1 + 2^-113 (a tie) or 1 + 3 2^-113
    if (trial % 5 == 0) for (std::size_t k = 1; k < cols; ++k) x[k] = ldexp(quad(static_cast<int>(k)), -100);
    std::vector<quad> y(rows);
    fx.multiply(x.data(), y.data(), 0);
    for (std::size_t r = 0; r < rows; ++r) {
      exact sum = 0;
      for (std::size_t k = 0; k < cols; ++k) sum += to_exact(a[r * cols + k]) * to_exact(x[k]);
      mpfr_set(rounded, sum.backend().data(), MPFR_RNDN);
      ties += mpfr_cmp(rounded, sum.backend().data()) != 0 && r == 0 && trial % 8 == 0;
      ASSERT_EQ(to_exact(y[r]), exact(rounded)) << "trial " << trial << " row " << r;
    }
  }
  mpfr_clear(rounded);
  EXPECT_GT(ties, 0);  // the tie case was met
}

TEST(FixedPointMatvec, ZeroVectorGivesZeros) {
  const eulervop::detail::chebyshev_basis<quad> basis(8);
  eulervop::detail::fixed_point_matrix<quad> fx(basis.integral, 9, 9);
  std::vector<quad> x(9, quad(0)), y(9, quad(1));
  fx.multiply(x.data(), y.data(), 0);
  for (const quad& v : y) EXPECT_EQ(v, 0);
}

// A vector with an infinity or a NaN has no fixed-point image: every row is NaN (so the
// integrator's finiteness checks see it), and a negative entry larger than every positive one
// sets the scale by its magnitude (the largest |x_k| is taken from the bit patterns).
TEST(FixedPointMatvec, NonFiniteEntriesGiveNaNAndSignsDoNotSetTheScale) {
  const eulervop::detail::chebyshev_basis<quad> basis(8);
  eulervop::detail::fixed_point_matrix<quad> fx(basis.integral, 9, 9);
  for (const quad bad : {std::numeric_limits<quad>::infinity(), -std::numeric_limits<quad>::infinity(),
                         std::numeric_limits<quad>::quiet_NaN()}) {
    std::vector<quad> x(9, quad(1)), y(9, quad(0));
    x[4] = bad;
    fx.multiply(x.data(), y.data(), 0);
    for (const quad& v : y) EXPECT_TRUE(isnan(v)) << bad;
  }
  // x = (-1e6, 1e-3, ...) against the exact S x (MPFR, 1330 bits): within the header's bound,
  // 2^-116 n max|S_rk| max|x| + 2 ulp, with max|S_rk| <= 2; a scale taken from 1e-3 would
  // overflow the integer images and miss it by far.
  std::vector<quad> x(9, quad(1e-3)), y(9);
  x[0] = quad(-1e6);
  fx.multiply(x.data(), y.data(), 0);
  for (std::size_t r = 1; r < 9; ++r) {
    exact sum = 0;
    for (std::size_t k = 0; k < 9; ++k) sum += to_exact(basis.integral[r * 9 + k]) * to_exact(x[k]);
    const double err = static_cast<double>(abs(to_exact(y[r]) - sum));
    EXPECT_LE(err, 18 * std::ldexp(1.0, -116) * 1e6 + 4 * std::ldexp(static_cast<double>(abs(sum)), -112)) << r;
  }
}

// dots() forms the weights' integer images once for a sum and several dot products; it must give
// the bits of the separate calls of dot() it replaces (evaluate_segment's output depends on them),
// for random vectors over many binades and where a vector is zero or not finite.
TEST(FixedPointMatvec, DotsGiveTheBitsOfSeparateDots) {
  using fx = eulervop::detail::fixed_point_matrix<quad>;
  constexpr std::size_t n = 42, D = 3;
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-40, 40);
  auto random_quad = [&] { return ldexp(quad(mantissa(rng)) + quad(mantissa(rng)) * 0x1p-60, exponent(rng)); };
  auto same_bits = [](const quad& a, const quad& b) { return (isnan(a) && isnan(b)) || (a == b && signbit(a) == signbit(b)); };
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<quad> a(n), b(n * D);
    for (quad& v : a) v = random_quad();
    for (quad& v : b) v = random_quad();
    if (trial == 1) std::fill(a.begin(), a.end(), quad(0));
    if (trial == 2) for (std::size_t k = 0; k < n; ++k) b[k * D + 1] = 0;
    if (trial == 3) a[7] = std::numeric_limits<quad>::infinity();
    if (trial == 4) b[5 * D + 2] = std::numeric_limits<quad>::quiet_NaN();
    if (trial == 5) for (std::size_t k = 0; k < n; ++k) b[k * D] = 0, a[3] = -std::numeric_limits<quad>::infinity();
    std::array<quad, D + 1> sums;
    fx::dots(a.data(), b.data(), D, D, n, sums.data());
    EXPECT_TRUE(same_bits(sums[0], fx::dot(a.data(), nullptr, 0, n))) << "trial " << trial;
    for (std::size_t i = 0; i < D; ++i)
      EXPECT_TRUE(same_bits(sums[1 + i], fx::dot(a.data(), b.data() + i, D, n))) << "trial " << trial << " i " << i;
  }
}

}  // namespace
