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

// v as hi + lo: its double, and the double of what that leaves (any scalar convertible to double
// whose difference with a double is exact or rounded in its own type: quad, MPFR).
template <class T>
double_double to_double_double(const T& v) {
  const double hi = static_cast<double>(v);
  return {hi, static_cast<double>(T(v - T(hi)))};
}

}  // namespace eulervop
