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
// The same for a binary128 number from its bit pattern, where hi and lo are normal doubles: hi
// is the significand's leading 53 bits rounded to nearest (ties to even), lo the exact rest (at
// most 61 bits) rounded to nearest by the integer conversion: the same two roundings as the
// soft-float way (four soft-float operations, about 0.1 us). False elsewhere.
inline bool binary128_to_double_double(const __float128& v, double_double& out) {
  unsigned __int128 bits;
  std::memcpy(&bits, &v, sizeof bits);
  const int biased = static_cast<int>(bits >> 112) & 0x7fff;
  const int e = biased - 16383;  // v = 1.f 2^e
  if (e < -900 || e > 1000) return false;  // near double's limits, zero, subnormal, inf, NaN
  const unsigned __int128 one = 1;
  const unsigned __int128 significand = (bits & ((one << 112) - 1)) | (one << 112);  // 113 bits
  std::uint64_t top = static_cast<std::uint64_t>(significand >> 60);  // 53 bits
  const std::uint64_t rest = static_cast<std::uint64_t>(significand) & ((std::uint64_t{1} << 60) - 1);
  const std::uint64_t half = std::uint64_t{1} << 59;
  if (rest > half || (rest == half && (top & 1))) ++top;  // may reach 2^53: still exact in double
  // v - hi = (significand - top 2^60) 2^(e - 112), |.| <= 2^59 2^(e - 112): normal in double.
  const auto diff = static_cast<std::int64_t>(static_cast<__int128>(significand) - (static_cast<__int128>(top) << 60));
  const double sign = (bits >> 127) ? -1.0 : 1.0;
  out.hi = sign * std::ldexp(static_cast<double>(top), e - 52);
  out.lo = diff == 0 ? 0.0 : sign * std::ldexp(static_cast<double>(diff), e - 112);  // +0 as v - hi gives
  return true;
}

// double(a - b) for binary128 a and b, from their bit patterns where a - b is exact in binary128
// (the same sign, exponents at most one apart, the difference within 113 bits: Sterbenz's case,
// where the residuals of the reference integrator fall) and its double is normal: the exact
// difference rounded to nearest (ties to even) once, as the soft-float subtraction and
// conversion do. False elsewhere.
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
  __int128 d = sx - sy;  // a - b = +-d 2^(e - 16383 - 112), |d| < 2^114
  if (d == 0) {
    out = 0.0;  // +0, as x - x is in round to nearest
    return true;
  }
  const bool negative = (d < 0) != static_cast<bool>(x >> 127);
  auto m = static_cast<unsigned __int128>(d < 0 ? -d : d);
  if (m >> 113) return false;  // not exact in binary128: rounded there first
  const int lead = 127 - (static_cast<std::uint64_t>(m >> 64) ? __builtin_clzll(static_cast<std::uint64_t>(m >> 64))
                                                                : 64 + __builtin_clzll(static_cast<std::uint64_t>(m)));
  int shift = lead - 52;  // bits below the 53 kept
  std::uint64_t top;
  if (shift > 0) {
    top = static_cast<std::uint64_t>(m >> shift);
    const unsigned __int128 rest = m & ((one << shift) - 1), half = one << (shift - 1);
    if (rest > half || (rest == half && (top & 1))) ++top;
  } else {
    top = static_cast<std::uint64_t>(m);
    shift = 0;
  }
  const int exponent = e - 16383 - 112 + shift;  // value = top 2^exponent, top <= 2^53
  if (exponent + 53 > 1023 || exponent + lead - shift < -1022) return false;
  out = std::ldexp(static_cast<double>(top), exponent);
  if (negative) out = -out;
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
