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

#include <eulervop/core/limb_arithmetic.hpp>

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

}  // namespace eulervop::detail
