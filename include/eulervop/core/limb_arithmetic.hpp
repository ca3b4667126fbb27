// Fixed-size integer arithmetic on arrays of 64-bit limbs (GMP's mp_limb_t), for the exact sums
// of products that the certificate (certify/detail/grid_integer.hpp) and the reference's
// fixed-point products (reference/detail/fixed_point_matvec.hpp) compute.
#pragma once

#include <gmp.h>
#include <mpfr.h>

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

namespace eulervop::detail {

// Integers of at most L limbs, as a sign and a magnitude, with exact sums of products, the limb
// loops unrolled at compile time: GMP's calls cost more than their arithmetic at these sizes
// (three limbs for quad). A sum is kept by columns of limb products (column_sum) and becomes a
// two's-complement integer of 2L + 1 limbs at the end, whose top limb holds the sums' growth: up
// to 2^62 products of magnitude below 2^(128 L) each.
namespace limbs {

using wide = unsigned __int128;

// The limb products of a b (L limbs each) summed by column: column S = lowest .. 2L - 2 holds
// sum_{i+j=S} a_i b_j, as 128 bits (low) and the count of their overflows (high), so that
// a b = sum_S (high_S 2^128 + low_S) 2^(64 S) exactly where lowest = 0. Columns below `lowest`
// are left out (the caller bounds them).
template <std::size_t L, std::size_t lowest = 0>
struct product_columns {
  static constexpr std::size_t count = 2 * L - 1 - lowest;
  wide low[count];
  std::uint64_t high[count];
};

namespace unrolled {
// Column S of a b: c (128 bits) and top (its overflows) += a_I b_(S-I) for I = first .. last.
template <std::size_t L, std::size_t S, std::size_t... I>
[[gnu::always_inline]] inline void column(const mp_limb_t* a, const mp_limb_t* b, wide& c, std::uint64_t& top,
                                          std::index_sequence<I...>) {
  constexpr std::size_t first = S < L ? 0 : S + 1 - L;
  ((c += static_cast<wide>(a[first + I]) * b[S - first - I],
    top += c < static_cast<wide>(a[first + I]) * b[S - first - I]),
   ...);
}
}  // namespace unrolled

template <std::size_t L, std::size_t lowest = 0>
[[gnu::always_inline]] inline void columns_of(const mp_limb_t* a, const mp_limb_t* b,
                                              product_columns<L, lowest>& out) {
  [&]<std::size_t... K>(std::index_sequence<K...>) {
    (
        [&] {
          constexpr std::size_t S = lowest + K;
          constexpr std::size_t terms = (S < L ? S : L - 1) - (S < L ? 0 : S + 1 - L) + 1;
          wide c = 0;
          std::uint64_t top = 0;
          unrolled::column<L, S>(a, b, c, top, std::make_index_sequence<terms>{});
          out.low[K] = c;
          out.high[K] = top;
        }(),
        ...);
  }(std::make_index_sequence<product_columns<L, lowest>::count>{});
}

// An exact sum of signed products, column by column (product_columns), positive and negative
// products apart: adding a product costs one add per column, with no carry running across the
// columns for each product (each column's 192 bits hold up to 2^62 products). to_limbs combines
// the columns once.
template <std::size_t L, std::size_t lowest = 0>
struct column_sum {
  static constexpr std::size_t count = product_columns<L, lowest>::count;
  wide low[2][count] = {};
  std::uint64_t high[2][count] = {};

  // sum += p (negative = 0) or -p (negative = 1).
  [[gnu::always_inline]] void add(const product_columns<L, lowest>& p, unsigned negative) {
    wide* lo = low[negative];
    std::uint64_t* hi = high[negative];
#pragma GCC unroll 16
    for (std::size_t s = 0; s < count; ++s) {
      lo[s] += p.low[s];
      hi[s] += p.high[s] + (lo[s] < p.low[s]);
    }
  }

  // The sum in two's complement on out[0, n), out[0] the column `lowest`; n >= count + 2 (each
  // column spans three limbs), and the sum must fit. One pass over the limbs: limb t gathers the
  // low, middle and top words of columns t, t - 1 and t - 2 of each sign.
  void to_limbs(mp_limb_t* out, std::size_t n) const {
    const auto word = [&](int sign, std::size_t c, std::size_t w) -> mp_limb_t {
      if (c >= count) return 0;
      return w == 0 ? static_cast<mp_limb_t>(low[sign][c])
                    : w == 1 ? static_cast<mp_limb_t>(low[sign][c] >> 64) : high[sign][c];
    };
    wide plus = 0, minus = 0;
    mp_limb_t borrow = 0;
    for (std::size_t t = 0; t < n; ++t) {
      for (std::size_t w = 0; w < 3 && w <= t; ++w) {
        plus += word(0, t - w, w);
        minus += word(1, t - w, w);
      }
      // out[t] = plus - minus - borrow, the borrow carried on.
      const auto p = static_cast<mp_limb_t>(plus), m = static_cast<mp_limb_t>(minus);
      const mp_limb_t d = p - m;
      out[t] = d - borrow;
      borrow = (p < m) | (d < borrow);
      plus >>= 64;
      minus >>= 64;
    }
  }
};

// The magnitude of z into out[0, L) and its sign as a mask; false if z needs more than L limbs.
inline bool load(mpz_srcptr z, std::size_t L, mp_limb_t* out, mp_limb_t& negative) {
  const std::size_t size = mpz_size(z);
  if (size > L) return false;
  for (std::size_t i = 0; i < L; ++i) out[i] = i < size ? mpz_getlimbn(z, static_cast<mp_size_t>(i)) : 0;
  negative = mpz_sgn(z) < 0 ? ~mp_limb_t(0) : 0;
  return true;
}

// y = acc 2^-shift rounded to nearest, acc a two's-complement integer of n limbs (overwritten).
inline void round_to(mp_limb_t* acc, std::size_t n, mpfr_ptr y, long shift) {
  const bool negative = acc[n - 1] >> 63;
  if (negative) mpn_neg(acc, acc, static_cast<mp_size_t>(n));
  mp_size_t size = static_cast<mp_size_t>(n);
  while (size > 0 && acc[size - 1] == 0) --size;
  mpz_t view;
  mpfr_set_z_2exp(y, mpz_roinit_n(view, acc, negative ? -size : size), -shift, MPFR_RNDN);
}

// f(std::integral_constant<std::size_t, L>{}) for n = L in [1, 8], where the loops above are
// unrolled; false (f not called) for other n.
template <class F>
bool with_limb_count(std::size_t n, F&& f) {
  return [&]<std::size_t... L>(std::index_sequence<L...>) {
    return ((n == L + 1 ? (f(std::integral_constant<std::size_t, L + 1>{}), true) : false) || ...);
  }(std::make_index_sequence<8>{});
}

}  // namespace limbs

}  // namespace eulervop::detail
