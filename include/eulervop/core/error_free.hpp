// Error-free transformations: a sum or a product of two floating-point numbers as the rounded
// result plus its exact rounding error, and the double-double arithmetic built on them.
//
//   two_sum       Knuth's TwoSum (TAOCP vol. 2, 4.2.2): s + e = a + b exactly, any order of |a|, |b|;
//   quick_two_sum Dekker's Fast2Sum: the same when |a| >= |b| (or a = 0);
//   split         Dekker's splitting (1971): a = hi + lo with 26-bit halves, so that the products
//                 of halves are exact (no hardware FMA is assumed);
//   two_product   Dekker's exact product: p + e = a b exactly.
//   to_double_double  any wider scalar (quad, MPFR) as hi + lo doubles.
// The generic two_sum and to_double_double serve every scalar type (rounded to nearest); the
// rest is for double.
#pragma once

#include <eulervop/core/scalar.hpp>

#include <cmath>
#include <cstdint>
#include <bit>
#include <cstring>
#include <type_traits>

namespace eulervop {

// A double-double number hi + lo, |lo| <= ulp(hi) / 2 after normalization.
struct double_double {
  double hi, lo;
};

// s + e = a + b exactly (s = fl(a + b)), in any scalar type; `bb` is scratch, so that a type
// whose values allocate (MPFR) reuses one.
template <class T>
void two_sum(const T& a, const T& b, T& s, T& e, T& bb) {
  s = a + b;
  bb = s - a;
  e = (a - (s - bb)) + (b - bb);
}

inline double_double two_sum(double a, double b) {
  const double s = a + b;
  const double bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}

inline double_double quick_two_sum(double a, double b) {
  const double s = a + b;
  return {s, b - (s - a)};
}

inline void split(double a, double& hi, double& lo) {
  const double t = 134217729.0 * a;  // 2^27 + 1
  hi = t - (t - a);
  lo = a - hi;
}

inline double_double two_product(double a, double b) {
  double a1, a2, b1, b2;
  split(a, a1, a2);
  split(b, b1, b2);
  const double p = a * b;
  return {p, ((a1 * b1 - p) + a1 * b2 + a2 * b1) + a2 * b2};
}

// Double-double products and sums, accurate to about 2^-104 relative (Dekker 1971).
inline double_double mul(const double_double& x, double b) {
  const double_double p = two_product(x.hi, b);
  return quick_two_sum(p.hi, p.lo + x.lo * b);
}
inline double_double mul(const double_double& x, const double_double& y) {
  const double_double p = two_product(x.hi, y.hi);
  return quick_two_sum(p.hi, p.lo + (x.hi * y.lo + x.lo * y.hi));
}
inline double_double add(const double_double& x, const double_double& y) {
  const double_double s = two_sum(x.hi, y.hi);
  return quick_two_sum(s.hi, s.lo + (x.lo + y.lo));
}
inline double_double negated(const double_double& x) { return {-x.hi, -x.lo}; }

// p + e = a b exactly for binary128 a and b (Dekker's product, splitting at 57 bits: the
// halves' products are exact in 113 bits), in soft-float: for the few products per segment whose
// rounding must be kept (reference/detail/node_sines.hpp's arguments). No overflow checks: for
// numbers far inside the range.
inline void two_product(const quad& a, const quad& b, quad& p, quad& e) {
  const quad splitter = ldexp(quad(1), 57) + 1;
  const auto split = [&](const quad& x, quad& hi, quad& lo) {
    const quad c = splitter * x;
    hi = c - (c - x);
    lo = x - hi;
  };
  quad ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  p = a * b;
  e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}

namespace detail {
// For binary128 numbers from their bit patterns: the integer conversion to double rounds to
// nearest (ties to even) once, as the soft-float conversion does, so these give its results bit
// for bit at the cost of integer operations. False (the caller takes the soft-float way) outside
// the cases stated.

// v = hi + lo, v normal with hi and lo normal doubles: hi is the 113-bit significand rounded to
// 53 bits, lo the exact rest (at most 60 bits) rounded (four soft-float operations otherwise).
// A zero gives (+-0, +0), as the soft-float way does (-0 - -0 is +0).
inline bool binary128_to_double_double(const __float128& v, double_double& out) {
  unsigned __int128 bits;
  std::memcpy(&bits, &v, sizeof bits);
  const double sign = (bits >> 127) ? -1.0 : 1.0;
  if ((bits << 1) == 0) {
    out = {sign * 0.0, 0.0};
    return true;
  }
  const int e = (static_cast<int>(bits >> 112) & 0x7fff) - 16383;  // v = 1.f 2^e
  if (e < -900 || e > 1000) return false;  // near double's limits, subnormal, inf, NaN
  const unsigned __int128 one = 1;
  const unsigned __int128 significand = (bits & ((one << 112) - 1)) | (one << 112);
  const auto hi = static_cast<double>(significand);  // an integer below 2^114: exact back
  const auto rest = static_cast<std::int64_t>(static_cast<__int128>(significand) -
                                              static_cast<__int128>(static_cast<unsigned __int128>(hi)));
  // 2^(e - 112) is a normal double (e >= -900), and so are both products: exact, as ldexp.
  const double scale = sign * std::bit_cast<double>(static_cast<std::uint64_t>(e - 112 + 1023) << 52);
  out.hi = hi * scale;
  out.lo = rest == 0 ? 0.0 : static_cast<double>(rest) * scale;  // +0 as v - hi gives
  return true;
}

// double(a - b) where a - b is exact in binary128 (the same sign, exponents at most one apart,
// the difference within 113 bits: Sterbenz's case, where the reference integrator's residuals
// fall) and its double is normal.
inline bool binary128_difference_to_double(const __float128& a, const __float128& b, double& out) {
  unsigned __int128 x, y;
  std::memcpy(&x, &a, sizeof x);
  std::memcpy(&y, &b, sizeof y);
  const int ex = static_cast<int>(x >> 112) & 0x7fff, ey = static_cast<int>(y >> 112) & 0x7fff;
  if ((x >> 127) != (y >> 127) || ex == 0 || ey == 0 || ex == 0x7fff || ey == 0x7fff || ex - ey > 1 || ey - ex > 1)
    return false;
  const unsigned __int128 one = 1, fraction = (one << 112) - 1;
  const int e = ex < ey ? ex : ey;  // both significands on the grid of the smaller exponent
  const auto sx = static_cast<__int128>(((x & fraction) | (one << 112)) << (ex - e));
  const auto sy = static_cast<__int128>(((y & fraction) | (one << 112)) << (ey - e));
  const __int128 d = sx - sy;  // a - b = +-d 2^(e - 16383 - 112), |d| < 2^114
  if (d == 0) {
    out = 0.0;  // +0, as x - x is in round to nearest
    return true;
  }
  const auto m = static_cast<unsigned __int128>(d < 0 ? -d : d);
  if (m >> 113) return false;  // not exact in binary128: rounded there first
  const int lead = 127 - (static_cast<std::uint64_t>(m >> 64) ? __builtin_clzll(static_cast<std::uint64_t>(m >> 64))
                                                                : 64 + __builtin_clzll(static_cast<std::uint64_t>(m)));
  const int scale = e - 16383 - 112;
  if (scale + lead + 1 > 1023 || scale + lead < -1022) return false;  // the double would not be normal
  out = std::ldexp(static_cast<double>(m), scale);
  if ((d < 0) != static_cast<bool>(x >> 127)) out = -out;
  return true;
}
}  // namespace detail

// double(a - b), rounded once where a - b is exact in T (binary128 from its bits: see above), in
// T otherwise (`scratch` a value of T, so that MPFR reuses one).
template <class T>
double difference_to_double(const T& a, const T& b, T& scratch) {
  if constexpr (std::is_same_v<T, quad>) {
    double out;
    if (detail::binary128_difference_to_double(a.backend().value(), b.backend().value(), out)) return out;
  }
  scratch = a;
  scratch -= b;
  return static_cast<double>(scratch);
}

// v as hi + lo: its double, and the double of what that leaves (any scalar convertible to double
// whose difference with a double is exact or rounded in its own type: quad, MPFR).
template <class T>
double_double to_double_double(const T& v) {
  if constexpr (std::is_same_v<T, quad>) {
    double_double out;
    if (detail::binary128_to_double_double(v.backend().value(), out)) return out;
  }
  const double hi = static_cast<double>(v);
  return {hi, static_cast<double>(T(v - T(hi)))};
}

}  // namespace eulervop
