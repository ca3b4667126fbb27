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

// Integers of at most L limbs, as a sign and a magnitude, with exact products and sums of
// products in two's complement over 2L + 1 limbs, the limb loops unrolled at compile time: GMP's
// calls cost more than their arithmetic at these sizes (three limbs for quad). The top limb holds
// the sums' growth: up to 2^62 products of magnitude below 2^(128 L) each.
namespace limbs {

using wide = unsigned __int128;

// out[0, 2L) = a b, exactly: column by column, with a 192-bit column sum (c, top).
template <std::size_t L>
[[gnu::always_inline]] inline void product(const mp_limb_t* a, const mp_limb_t* b, mp_limb_t* out) {
  wide c = 0;
#pragma GCC unroll 16
  for (std::size_t s = 0; s + 1 < 2 * L; ++s) {
    std::uint64_t top = 0;
#pragma GCC unroll 8
    for (std::size_t i = (s < L ? 0 : s + 1 - L); i <= (s < L ? s : L - 1); ++i) {
      const wide p = static_cast<wide>(a[i]) * b[s - i];
      c += p;
      top += c < p;
    }
    out[s] = static_cast<mp_limb_t>(c);
    c = (c >> 64) | (static_cast<wide>(top) << 64);
  }
  out[2 * L - 1] = static_cast<mp_limb_t>(c);
}

// acc[0, 2L + 1) += p or -p (negative: an all-ones mask), p of 2L limbs: -p = (p XOR mask) + 1,
// its top limb all ones.
template <std::size_t L>
[[gnu::always_inline]] inline void accumulate(mp_limb_t* acc, const mp_limb_t* p, mp_limb_t negative) {
  wide carry = negative & 1;
#pragma GCC unroll 16
  for (std::size_t t = 0; t < 2 * L; ++t) {
    carry += static_cast<wide>(acc[t]) + (p[t] ^ negative);
    acc[t] = static_cast<mp_limb_t>(carry);
    carry >>= 64;
  }
  acc[2 * L] += negative + static_cast<mp_limb_t>(carry);
}

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
