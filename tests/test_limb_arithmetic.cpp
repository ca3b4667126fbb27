// The column sums of core/limb_arithmetic.hpp: exact sums of signed products of L-limb integers,
// kept by columns of limb products and combined once.
//
// Provenance of the reference values: the same sums in GMP's integers (mpz_addmul, mpz_submul),
// exact, then reduced to the two's-complement limbs the kernel returns.
#include <eulervop/core/limb_arithmetic.hpp>

#include <gtest/gtest.h>

#include <gmp.h>

#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

namespace {

namespace limbs = eulervop::detail::limbs;

// sum (mod 2^(64 n)) as n limbs, two's complement.
std::vector<mp_limb_t> twos_complement(const mpz_t sum, std::size_t n) {
  mpz_t m, modulus;
  mpz_inits(m, modulus, nullptr);
  mpz_ui_pow_ui(modulus, 2, 64 * n);
  mpz_mod(m, sum, modulus);  // in [0, 2^(64 n))
  std::vector<mp_limb_t> out(n, 0);
  for (std::size_t i = 0; i < mpz_size(m); ++i) out[i] = mpz_getlimbn(m, static_cast<mp_size_t>(i));
  mpz_clears(m, modulus, nullptr);
  return out;
}

template <std::size_t L>
void check_sums(std::mt19937_64& rng) {
  std::uniform_int_distribution<std::uint64_t> limb;
  for (int trial = 0; trial < 50; ++trial) {
    const std::size_t terms = 1 + static_cast<std::size_t>(trial) * 7;
    limbs::column_sum<L> sum;
    mpz_t exact, a_z, b_z;
    mpz_inits(exact, a_z, b_z, nullptr);
    for (std::size_t t = 0; t < terms; ++t) {
      mp_limb_t a[L], b[L];
      for (std::size_t i = 0; i < L; ++i) {
        // Every fourth trial at the largest magnitudes (all ones), where every column overflows.
        a[i] = trial % 4 == 0 ? ~mp_limb_t(0) : limb(rng);
        b[i] = trial % 4 == 0 ? ~mp_limb_t(0) : limb(rng);
      }
      const unsigned negative = trial % 4 == 1 ? 1 : static_cast<unsigned>(limb(rng) & 1);
      limbs::product_columns<L> p;
      limbs::columns_of<L>(a, b, p);
      sum.add(p, negative);
      mpz_import(a_z, L, -1, sizeof(mp_limb_t), 0, 0, a);
      mpz_import(b_z, L, -1, sizeof(mp_limb_t), 0, 0, b);
      if (negative) mpz_submul(exact, a_z, b_z);
      else mpz_addmul(exact, a_z, b_z);
    }
    constexpr std::size_t n = 2 * L + 1;
    mp_limb_t out[n];
    sum.to_limbs(out, n);
    const std::vector<mp_limb_t> expected = twos_complement(exact, n);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(out[i], expected[i]) << "L " << L << " trial " << trial << " limb " << i;
    mpz_clears(exact, a_z, b_z, nullptr);
  }
}

TEST(LimbColumnSum, EqualsTheExactSumOfSignedProducts) {
  std::mt19937_64 rng(5);
  check_sums<1>(rng);
  check_sums<2>(rng);
  check_sums<3>(rng);
  check_sums<4>(rng);
  check_sums<5>(rng);
  check_sums<8>(rng);
}

// With `lowest` > 0 the columns below it are left out: the sum equals the exact sum of the limb
// products a_i b_j 2^(64 (i + j - lowest)) with i + j >= lowest (as fixed_point_matvec.hpp uses).
TEST(LimbColumnSum, LeavesOutTheColumnsBelowLowest) {
  constexpr std::size_t L = 4, lowest = 2;
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<std::uint64_t> limb;
  limbs::column_sum<L, lowest> sum;
  mpz_t exact, term;
  mpz_inits(exact, term, nullptr);
  for (int t = 0; t < 100; ++t) {
    mp_limb_t a[L], b[L];
    for (std::size_t i = 0; i < L; ++i) {
      a[i] = limb(rng);
      b[i] = limb(rng);
    }
    const unsigned negative = static_cast<unsigned>(limb(rng) & 1);
    limbs::product_columns<L, lowest> p;
    limbs::columns_of<L, lowest>(a, b, p);
    sum.add(p, negative);
    for (std::size_t i = 0; i < L; ++i)
      for (std::size_t j = 0; j < L; ++j) {
        if (i + j < lowest) continue;
        mpz_set_ui(term, a[i]);
        mpz_mul_ui(term, term, b[j]);
        mpz_mul_2exp(term, term, 64 * (i + j - lowest));
        if (negative) mpz_sub(exact, exact, term);
        else mpz_add(exact, exact, term);
      }
  }
  constexpr std::size_t n = 2 * L - lowest + 1;
  mp_limb_t out[n];
  sum.to_limbs(out, n);
  const std::vector<mp_limb_t> expected = twos_complement(exact, n);
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(out[i], expected[i]) << "limb " << i;
  mpz_clears(exact, term, nullptr);
}

}  // namespace
