// Upper bounds of sums of magnitudes, sum_k |x_k| for balls (|mid| + rad) and for integers: the
// sup bounds of Chebyshev models (|T_k| <= 1) and the moves of models to their grids take one over
// every coefficient, and Arb's mag_add (each partial sum rounded up to 30 bits, with exponents of
// any size) was the larger part of that at a few dozen coefficients (7% of a certified run).
//
// Here each term is bounded above by a double (the top 53 bits of its mantissa plus one unit in
// the last place, times a power of two) and added in double, each partial sum moved up by one
// unit in its last place: round-to-nearest errs by at most half of that (IEEE 754-2008, 4.3.1),
// so every partial sum stays at or above the exact one. mag_set_d then rounds the double up to a
// mag. A term outside the doubles' normal range sends the whole sum to Arb's mag arithmetic. The
// result is the exact sum rounded up to a mag's 30 bits, within a few units of the double's last
// place: no looser than mag_add's chain.
#pragma once

#include <arb.h>
#include <flint/fmpz.h>

#include <bit>
#include <cstdint>

namespace eulervop::detail {

namespace magnitude {

// 2^p as a double, for p in the normal range [-1022, 1023].
inline double power_of_two(slong p) { return std::bit_cast<double>(static_cast<std::uint64_t>(p + 1023) << 52); }

// Scales 2^p for which a product with an integer below 2^54 is a normal double, and sums of a
// few million of them stay finite.
inline bool in_range(slong p) { return p >= -1022 && p <= 940; }

// A running upper bound of a sum of nonnegative doubles.
struct upper_sum {
  double s = 0;
  void add(double t) {
    if (t != 0) s = std::bit_cast<double>(std::bit_cast<std::uint64_t>(s + t) + 1);  // one ulp up
  }
};

// An upper bound of |x| as a double; false where x is not finite or outside the range.
inline bool bound(const arf_struct* x, double& out) {
  out = 0;
  if (ARF_IS_SPECIAL(x)) return arf_is_zero(x);
  const fmpz e = ARF_EXP(x);
  if (COEFF_IS_MPZ(e) || !in_range(e - 53)) return false;
  const mp_size_t n = ARF_SIZE(x);
  const mp_limb_t top = (n <= ARF_NOPTR_LIMBS ? ARF_NOPTR_D(x) : ARF_PTR_D(x))[n - 1];
  // |x| = 0.top... 2^e < ((top >> 11) + 1) 2^(e - 53): the integer is at most 2^53, exact.
  out = static_cast<double>((top >> 11) + 1) * power_of_two(e - 53);
  return true;
}
inline bool bound(const mag_struct* r, double& out) {
  out = 0;
  if (MAG_MAN(r) == 0) return mag_is_zero(r);
  const fmpz e = MAG_EXP(r);
  if (COEFF_IS_MPZ(e) || !in_range(e - MAG_BITS)) return false;
  out = static_cast<double>(MAG_MAN(r)) * power_of_two(e - MAG_BITS);  // exact: 30 bits
  return true;
}
// An upper bound of |n| 2^e as a double.
inline bool bound(const fmpz* n, slong e, double& out) {
  out = 0;
  const fmpz c = *n;
  if (c == 0) return true;
  mp_limb_t head;  // |n|'s leading bits, its top bit at bit 63
  slong top_e;     // |n| < 2^top_e
  if (COEFF_IS_MPZ(c)) {
    const __mpz_struct* z = COEFF_TO_PTR(c);
    const mp_size_t size = z->_mp_size < 0 ? -z->_mp_size : z->_mp_size;
    const mp_limb_t top = z->_mp_d[size - 1];
    const int lead = FLINT_BIT_COUNT(top);
    top_e = 64 * (size - 1) + lead;
    head = top << (64 - lead);
    if (lead < 64 && size > 1) head |= z->_mp_d[size - 2] >> lead;
  } else {
    const mp_limb_t a = static_cast<mp_limb_t>(c < 0 ? -c : c);
    const int lead = FLINT_BIT_COUNT(a);
    top_e = lead;
    head = a << (64 - lead);
  }
  // |n| < ((head >> 11) + 1) 2^(top_e - 53), the bits below head's counted as a whole unit.
  if (!in_range(top_e + e - 53)) return false;
  out = static_cast<double>((head >> 11) + 1) * power_of_two(top_e + e - 53);
  return true;
}

// sum += an upper bound of |x| (midpoint and radius) for a ball x; false where either part is
// out of range (sum then unspecified).
inline bool add_ball(upper_sum& sum, arb_srcptr x) {
  double mid = 0, r = 0;
  if (!bound(arb_midref(x), mid) || !bound(arb_radref(x), r)) return false;
  sum.add(mid);
  sum.add(r);
  return true;
}

// Whether x is 0 or within [2^-500, 2^500], where a sum or a product of two such numbers is a
// normal double (the units in the last place below hold).
inline bool moderate(double x) { return x == 0 || (x >= 0x1p-500 && x <= 0x1p500); }
// Upper bounds of a + b and a b for moderate nonnegative a, b: the rounded result moved up by one
// unit in its last place.
inline double up(double x) { return x == 0 ? 0 : std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) + 1); }
inline double add_up(double a, double b) { return up(a + b); }
inline double mul_up(double a, double b) { return up(a * b); }

// sum_k of the terms bound(k, t) gives, in doubles rounded up; where a term cannot be bounded
// (false), the whole sum by `slow` (Arb's mag arithmetic).
template <class Bound, class Slow>
void sum_or(mag_t out, slong n, Bound bound, Slow slow) {
  upper_sum sum;
  for (slong k = 0; k < n; ++k)
    if (!bound(k, sum)) return slow();
  mag_set_d(out, sum.s);
}

}  // namespace magnitude

// out >= sum_k |x_k| (midpoint and radius) over n balls.
inline void magnitude_sum(mag_t out, arb_srcptr x, slong n) {
  const auto bound = [x](slong k, magnitude::upper_sum& sum) { return magnitude::add_ball(sum, x + k); };
  magnitude::sum_or(out, n, bound, [&] {
    mag_t m;
    mag_init(m);
    mag_zero(out);
    for (slong k = 0; k < n; ++k) {
      arb_get_mag(m, x + k);
      mag_add(out, out, m);
    }
    mag_clear(m);
  });
}

// out >= sum_k rad(x_k) over n balls.
inline void radius_sum(mag_t out, arb_srcptr x, slong n) {
  const auto bound = [x](slong k, magnitude::upper_sum& sum) {
    double r = 0;
    if (!magnitude::bound(arb_radref(x + k), r)) return false;
    sum.add(r);
    return true;
  };
  magnitude::sum_or(out, n, bound, [&] {
    mag_zero(out);
    for (slong k = 0; k < n; ++k) mag_add(out, out, arb_radref(x + k));
  });
}

// out >= sum_k |c_k| 2^e over n integers.
inline void magnitude_sum(mag_t out, const fmpz* c, slong n, slong e) {
  const auto bound = [c, e](slong k, magnitude::upper_sum& sum) {
    double t = 0;
    if (!magnitude::bound(c + k, e, t)) return false;
    sum.add(t);
    return true;
  };
  magnitude::sum_or(out, n, bound, [&] {
    mag_t m;
    mag_init(m);
    mag_zero(out);
    for (slong k = 0; k < n; ++k) {
      mag_set_fmpz(m, c + k);
      mag_add(out, out, m);
    }
    mag_mul_2exp_si(out, out, e);
    mag_clear(m);
  });
}

}  // namespace eulervop::detail
