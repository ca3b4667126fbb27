// Numbers on a common grid, as integers (GMP's, or the fixed-size limb arrays below): the
// certificate's two large linear maps (the transform of the node values, node_transform.hpp, and
// the products of the Picard residual, picard_residual.hpp) put their inputs on a grid of step
// 2^-shift, so that every product and sum after that is an exact integer operation. Only two
// steps err, and both are bounded where they are used: the entry onto the grid (rounding down,
// by less than one step) and the exit to MPFR (one rounding to nearest at the working precision,
// at most 2^-p of the result).
//
// Why: MPFR sums of terms of unequal size spend most of their time aligning and normalising
// (the coefficients decay by tens of orders of magnitude across a segment); integers on one grid
// need neither, and small terms are short integers.
#pragma once

#include <gmp.h>
#include <mpfr.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace eulervop::detail {

// An owning GMP integer (reserving room for `bits` bits, so that the loops do not reallocate).
class grid_integer {
 public:
  explicit grid_integer(mp_bitcnt_t bits = 64) { mpz_init2(v_, bits); }
  grid_integer(const grid_integer& o) { mpz_init_set(v_, o.v_); }
  grid_integer(grid_integer&& o) noexcept {
    mpz_init(v_);
    mpz_swap(v_, o.v_);
  }
  grid_integer& operator=(const grid_integer& o) {
    mpz_set(v_, o.v_);
    return *this;
  }
  grid_integer& operator=(grid_integer&& o) noexcept {
    mpz_swap(v_, o.v_);
    return *this;
  }
  ~grid_integer() { mpz_clear(v_); }
  mpz_ptr get() { return v_; }
  mpz_srcptr get() const { return v_; }

 private:
  mpz_t v_;
};

// out = floor(x 2^shift) for a finite x: 0 <= x - out 2^-shift < 2^-shift.
inline void to_grid(grid_integer& out, mpfr_srcptr x, long shift) {
  if (mpfr_zero_p(x)) {
    mpz_set_ui(out.get(), 0);
    return;
  }
  const long e = static_cast<long>(mpfr_get_z_2exp(out.get(), x)) + shift;  // x 2^shift = out 2^e
  if (e >= 0)
    mpz_mul_2exp(out.get(), out.get(), static_cast<mp_bitcnt_t>(e));
  else
    mpz_fdiv_q_2exp(out.get(), out.get(), static_cast<mp_bitcnt_t>(-e));
}

// The grid for numbers below 2^top with `bits` bits under the top: shift = bits - top, so that the
// integers have at most `bits` bits. top is the largest MPFR exponent of the nonzero numbers
// (|x| < 2^exponent), 0 when all are zero.
template <class Range, class Get>
long grid_shift(const Range& numbers, Get get, mpfr_prec_t bits) {
  mpfr_exp_t top = std::numeric_limits<mpfr_exp_t>::min();
  for (const auto& x : numbers)
    if (mpfr_regular_p(get(x))) top = std::max(top, mpfr_get_exp(get(x)));
  if (top == std::numeric_limits<mpfr_exp_t>::min()) top = 0;
  return static_cast<long>(bits) - static_cast<long>(top);
}

// sum += |z|, exactly.
inline void add_abs(grid_integer& sum, mpz_srcptr z) {
  if (mpz_sgn(z) < 0)
    mpz_sub(sum.get(), sum.get(), z);
  else
    mpz_add(sum.get(), sum.get(), z);
}

// bound += |z| 2^-shift, rounded up (z an integer on the grid).
inline void add_abs_on_grid(mpfr_ptr bound, mpz_srcptr z, long shift, mpfr_ptr scratch) {
  mpfr_set_z_2exp(scratch, z, -shift, MPFR_RNDA);  // away from zero: |scratch| >= |z| 2^-shift
  mpfr_abs(scratch, scratch, MPFR_RNDU);
  mpfr_add(bound, bound, scratch, MPFR_RNDU);
}

// Grid integers of at most L limbs, as a sign and a magnitude, with exact products and sums of
// products in two's complement over 2L + 1 limbs: the residual's products (picard_residual.hpp)
// with the limb loops unrolled at compile time, as GMP's calls cost more than their arithmetic at
// these sizes (three limbs for quad). The top limb holds the sums' growth: up to 2^62 products
// of magnitude below 2^(128 L) each.
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

}  // namespace limbs

}  // namespace eulervop::detail
