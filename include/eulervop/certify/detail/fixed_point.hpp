// A binary floating-point number on a fixed binary grid, truncated toward zero: what Arb's
// arf_get_fmpz_fixed_si computes (the same integer and the same inexact flag), read from the
// mantissa's limbs with one shift. Arb's general conversion went through an intermediate
// integer and a shift by GMP for every coefficient a segment moves to a grid (its values, its
// factors, its Jacobian's entries): 2.7% of a certified paper scene's instructions.
#pragma once

#include <arb.h>
#include <flint/fmpz.h>
#include <gmp.h>

#include <cstddef>

namespace eulervop::detail {

// |trunc(x 2^-e)| into out[0, L) and x's sign (1 negative), where it fits L limbs; returns 0 for
// an exact result, 1 for a truncated one, -1 where x is not finite, its exponent is not a small
// integer, its mantissa has more than 4 limbs or the result does not fit (out then unspecified).
inline int fixed_limbs(mp_limb_t* out, std::size_t L, unsigned& negative, const arf_struct* x, slong e) {
  for (std::size_t i = 0; i < L; ++i) out[i] = 0;
  negative = 0;
  if (arf_is_zero(x)) return 0;
  if (ARF_IS_SPECIAL(x) || COEFF_IS_MPZ(ARF_EXP(x))) return -1;
  const mp_size_t n = ARF_SIZE(x);
  if (n > 4) return -1;
  const mp_limb_t* d = n <= ARF_NOPTR_LIMBS ? ARF_NOPTR_D(x) : ARF_PTR_D(x);
  negative = ARF_SGNBIT(x) ? 1 : 0;
  // |x| = D 2^(E - 64 n), D the n limbs as an integer.
  const slong shift = ARF_EXP(x) - 64 * n - e;
  if (shift >= 0) {  // exact: D 2^shift
    const auto words = static_cast<std::size_t>(shift / 64);
    const auto bits = static_cast<unsigned>(shift % 64);
    if (words + static_cast<std::size_t>(n) > L + (bits == 0 ? 0 : 1)) return -1;
    mp_limb_t carry = 0;
    for (mp_size_t i = 0; i < n; ++i) {
      const std::size_t w = words + static_cast<std::size_t>(i);
      const mp_limb_t v = bits == 0 ? d[i] : (d[i] << bits) | carry;
      carry = bits == 0 ? 0 : d[i] >> (64 - bits);
      if (w < L) out[w] = v; else if (v != 0) return -1;
    }
    if (carry != 0) {
      const std::size_t w = words + static_cast<std::size_t>(n);
      if (w >= L) return -1;
      out[w] = carry;
    }
    return 0;
  }
  // D >> -shift, with the dropped bits' test.
  const auto drop = static_cast<unsigned long>(-shift);
  const auto words = drop / 64;
  const auto bits = static_cast<unsigned>(drop % 64);
  if (words >= static_cast<unsigned long>(n)) return 1;  // below one unit: zero, inexact
  bool inexact = false;
  for (unsigned long i = 0; i < words; ++i) inexact = inexact || d[i] != 0;
  if (bits != 0) inexact = inexact || (d[words] << (64 - bits)) != 0;
  const auto m = static_cast<std::size_t>(n - static_cast<mp_size_t>(words));  // limbs left
  for (std::size_t i = 0; i < m; ++i) {
    const mp_limb_t lo = d[words + i], hi = words + i + 1 < static_cast<unsigned long>(n) ? d[words + i + 1] : 0;
    const mp_limb_t v = bits == 0 ? lo : (lo >> bits) | (hi << (64 - bits));
    if (i < L) out[i] = v; else if (v != 0) return -1;
  }
  return inexact ? 1 : 0;
}

// c = the integer of sign `negative` and magnitude d[0, n) (high zero limbs allowed): FLINT's
// small form where it fits, else written into the GMP integer c already owns, with its limbs.
inline void set_signed_limbs(fmpz* c, const mp_limb_t* d, mp_size_t n, bool negative) {
  while (n > 0 && d[n - 1] == 0) --n;
  if (n == 0) {
    fmpz_zero(c);
  } else if (n == 1 && d[0] <= static_cast<mp_limb_t>(COEFF_MAX)) {
    _fmpz_demote(c);
    *c = negative ? -static_cast<slong>(d[0]) : static_cast<slong>(d[0]);
  } else {
    __mpz_struct* z = _fmpz_promote(c);
    if (z->_mp_alloc < n) mpz_realloc2(z, static_cast<mp_bitcnt_t>(n) * GMP_NUMB_BITS);
    for (mp_size_t i = 0; i < n; ++i) z->_mp_d[i] = d[i];
    z->_mp_size = negative ? -static_cast<int>(n) : static_cast<int>(n);
  }
}

// y = trunc(x 2^-e); true where that moved x (as arf_get_fmpz_fixed_si, which takes what the
// limbs above do not).
inline bool fixed_fmpz(fmpz_t y, const arf_struct* x, slong e) {
  mp_limb_t limbs[4];
  unsigned negative = 0;
  const int r = fixed_limbs(limbs, 4, negative, x, e);
  if (r < 0) return arf_get_fmpz_fixed_si(y, x, e) != 0;
  set_signed_limbs(y, limbs, 4, negative != 0);
  return r == 1;
}

}  // namespace eulervop::detail
