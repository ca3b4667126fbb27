// Fixed-size integer arithmetic on arrays of 64-bit limbs (GMP's mp_limb_t), for the exact sums
// of products that the certificate (certify/detail/ball_node_transform.hpp) and the reference's
// fixed-point products (reference/detail/fixed_point_matvec.hpp) compute.
#pragma once

#include <gmp.h>
#include <mpfr.h>

#include <cmath>
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

  // sum += a b 2^(64 S) (negative = 0) or its negative (negative = 1), a of L limbs and b of
  // M <= L - S (by default a b, both of L limbs): each limb product goes straight into its column
  // (a multiply and three additions), without product_columns between. With S > 0, b stands for
  // a number of L limbs whose S low limbs are zero, and takes M L limb products instead of L L.
  template <std::size_t M = L, std::size_t S = 0>
  [[gnu::always_inline]] void add_product(const mp_limb_t* a, const mp_limb_t* b, unsigned negative) {
    static_assert(M + S <= L);
    wide* lo = low[negative];
    std::uint64_t* hi = high[negative];
    [&]<std::size_t... K>(std::index_sequence<K...>) {
      (
          [&] {
            constexpr std::size_t I = K / M, J = K % M, C = I + J + S;
            if constexpr (C >= lowest) {
              const wide p = static_cast<wide>(a[I]) * b[J];
              wide& c = lo[C - lowest];
              c += p;
              hi[C - lowest] += c < p;
            }
          }(),
          ...);
    }(std::make_index_sequence<L * M>{});
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

// The magnitude of trunc(x 2^shift) into out[0, L) and x's sign as a mask, read from x's
// significand in place (MPFR's custom interface): no integer is allocated, as mpfr_get_z_2exp
// would. False if x is not finite or the result needs more than L limbs.
inline bool load_truncated(mpfr_srcptr x, long shift, std::size_t L, mp_limb_t* out, mp_limb_t& negative) {
  for (std::size_t i = 0; i < L; ++i) out[i] = 0;
  negative = 0;
  if (mpfr_zero_p(x)) return true;
  if (!mpfr_regular_p(x)) return false;
  negative = mpfr_signbit(x) ? ~mp_limb_t(0) : 0;
  const auto* m = static_cast<const mp_limb_t*>(mpfr_custom_get_significand(x));
  const std::size_t nx = (static_cast<std::size_t>(mpfr_get_prec(x)) + 63) / 64;
  // |x| = M 2^(e - 64 nx), M the nx limbs as an integer, its top bit set (bits below the
  // precision are zero).
  const long up = static_cast<long>(mpfr_get_exp(x)) - 64 * static_cast<long>(nx) + shift;
  if (up >= 0) {
    const auto words = static_cast<std::size_t>(up / 64);
    const auto bits = static_cast<unsigned>(up % 64);
    if (words + nx > L) return false;
    mp_limb_t carry = 0;
    if (bits)
      carry = mpn_lshift(out + words, m, static_cast<mp_size_t>(nx), bits);
    else
      for (std::size_t i = 0; i < nx; ++i) out[words + i] = m[i];
    if (carry) {
      if (words + nx >= L) return false;
      out[words + nx] = carry;
    }
    return true;
  }
  const auto words = static_cast<std::size_t>(-up / 64);
  const auto bits = static_cast<unsigned>(-up % 64);
  if (words >= nx) return true;  // below one step
  const std::size_t n = nx - words;  // the top limb stays nonzero
  if (n > L) return false;
  if (bits)
    mpn_rshift(out, m + words, static_cast<mp_size_t>(n), bits);
  else
    for (std::size_t i = 0; i < n; ++i) out[i] = m[words + i];
  return true;
}

// out = a + b or a - b (`subtract`) for sign-magnitude numbers of L limbs (load's form); the
// result must fit in L limbs.
inline void signed_sum(const mp_limb_t* a, mp_limb_t a_negative, const mp_limb_t* b, mp_limb_t b_negative,
                       bool subtract, std::size_t L, mp_limb_t* out, mp_limb_t& negative) {
  if (subtract) b_negative = ~b_negative;
  const auto n = static_cast<mp_size_t>(L);
  if ((a_negative & 1) == (b_negative & 1)) {
    mpn_add_n(out, a, b, n);
    negative = a_negative;
  } else if (mpn_cmp(a, b, n) >= 0) {
    mpn_sub_n(out, a, b, n);
    negative = a_negative;
  } else {
    mpn_sub_n(out, b, a, n);
    negative = b_negative;
  }
}

// acc += d 2^shift, acc a two's-complement integer of n limbs, where d 2^shift is an integer
// that fits beside acc's sign limb; false (acc unchanged) for a d that is not finite, has bits
// below the grid or is too large.
inline bool add_double(mp_limb_t* acc, std::size_t n, double d, long shift) {
  if (d == 0) return true;
  if (!std::isfinite(d)) return false;
  int e = 0;
  const double m = std::frexp(std::abs(d), &e);  // |d| = m 2^e, m in [1/2, 1)
  auto M = static_cast<std::uint64_t>(std::ldexp(m, 53));  // |d| = M 2^(e - 53), exactly
  long up = static_cast<long>(e) - 53 + shift;
  if (up < 0) {
    if (up <= -64 || (M & ((std::uint64_t{1} << -up) - 1)) != 0) return false;
    M >>= -up;
    up = 0;
  }
  const auto words = static_cast<std::size_t>(up / 64);
  const auto bits = static_cast<unsigned>(up % 64);
  if (words + 2 >= n) return false;
  const mp_limb_t term[2] = {static_cast<mp_limb_t>(M << bits), bits ? static_cast<mp_limb_t>(M >> (64 - bits)) : 0};
  const auto size = static_cast<mp_size_t>(n - words);
  if (d > 0)
    mpn_add(acc + words, acc + words, size, term, 2);
  else
    mpn_sub(acc + words, acc + words, size, term, 2);
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
