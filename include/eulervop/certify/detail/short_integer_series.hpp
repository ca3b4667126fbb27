// Exact Chebyshev products of short integer series in 128-bit sums, for the residuals of the
// linear flow (ball_linear_flow.hpp): there the factors lie on grids of at most 56 bits (the
// Jacobian's) and 56 or 40 bits (Phi_num, u_num + r), so that each product of two coefficients
// fits 112 bits and a sum of up to 2^14 of them fits a signed 128-bit integer. FLINT's polynomial
// products reach the same exact results, but at these lengths their calls cost more than the
// arithmetic. Where the bits do not fit, the caller takes FLINT's path (fits() says which).
#pragma once

#include <arf.h>
#include <flint/fmpz.h>
#include <flint/fmpz_poly.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#ifndef __SIZEOF_INT128__
#error "eulervop needs a compiler with 128-bit integers (GCC or Clang on a 64-bit target)"
#endif

namespace eulervop::detail {

using wide_int = __int128;

// An integer polynomial whose coefficients fit 63 bits, with the bit length of the largest.
struct short_integer_series {
  std::vector<std::int64_t> c;
  unsigned bits = 0;

  // From a FLINT polynomial; false (and empty) if a coefficient needs more than 62 bits.
  bool load(const fmpz_poly_t p) {
    c.resize(static_cast<std::size_t>(p->length));
    bits = 0;
    for (slong k = 0; k < p->length; ++k) {
      const fmpz* x = p->coeffs + k;
      if (!fmpz_fits_si(x) || fmpz_bits(x) > 62) {
        c.clear();
        bits = 0;
        return false;
      }
      c[static_cast<std::size_t>(k)] = fmpz_get_si(x);
      bits = std::max<unsigned>(bits, static_cast<unsigned>(fmpz_bits(x)));
    }
    return true;
  }
  bool empty() const { return c.empty(); }
};

// True when `count` Chebyshev products of factors of at most a_bits and b_bits bits, the shorter
// of each pair at most `length` long, sum exactly in a signed 128-bit integer with room for the
// integral's differences 2 S_0 - S_2 (three sums): each coefficient of a product sums at most
// 2 length terms below 2^(a_bits + b_bits), so the sums stay below 2^124.
inline bool fits(unsigned a_bits, unsigned b_bits, std::size_t length, std::size_t count) {
  unsigned growth = 0;
  for (std::size_t n = 2 * length * count; n > 1; n = (n + 1) / 2) ++growth;
  return a_bits + b_bits + growth <= 124;
}

// acc += 2 (a b) in the Chebyshev basis: T_p T_q = (T_{p+q} + T_{|p-q|}) / 2, so that acc[n]
// gains sum_{p+q=n} a_p b_q + sum_{|p-q|=n} a_p b_q (acc long enough: la + lb - 1).
inline void add_chebyshev_product(std::vector<wide_int>& acc, const short_integer_series& a,
                                  const short_integer_series& b) {
  const std::size_t la = a.c.size(), lb = b.c.size();
  wide_int* out = acc.data();
  for (std::size_t p = 0; p < la; ++p) {
    const wide_int ap = a.c[p];
    for (std::size_t q = 0; q < lb; ++q) {
      const wide_int t = ap * b.c[q];
      out[p + q] += t;
      out[p >= q ? p - q : q - p] += t;
    }
  }
}

// x = v exactly (two limbs: Arb keeps them without allocating).
inline void set_wide(arf_t x, wide_int v) {
  if (v == 0) {
    arf_zero(x);
    return;
  }
  const bool negative = v < 0;
  const auto u = static_cast<unsigned __int128>(negative ? -v : v);
  const mp_limb_t limbs[2] = {static_cast<mp_limb_t>(u), static_cast<mp_limb_t>(u >> 64)};
  arf_set_mpn(x, limbs, limbs[1] != 0 ? 2 : 1, negative);
}

}  // namespace eulervop::detail
