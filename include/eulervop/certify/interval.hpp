// An owning MPFI interval (Revol & Rouillier, "Motivations for an arbitrary precision interval
// arithmetic and the MPFI library", 2005): every operation rounds its end points outward, so the
// exact result of the real operation on any points of the operands lies inside the result.
//
// Two ways to compute with it:
//   - value semantics (+, -, *, /, sqrt, abs, max), for the setup code and the bounds of the
//     model (model/physical_scaling.hpp, model/euler_problem.hpp instantiated with this type):
//     each operation allocates its result, at the larger precision of its operands;
//   - the MPFI C calls on preallocated intervals (get()), in the certifier's loops (thousands of
//     operations per segment), where the temporaries would cost about twice as much.
// Constants of generic code (T(0), T(1), T(3)) take the thread's interval precision, set by an
// interval_precision_scope (like MPFR values and mpfr_precision_scope, core/scalar.hpp).
#pragma once

#include <eulervop/core/scalar.hpp>

#include <mpfi.h>
#include <mpfr.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace eulervop {

namespace detail {
inline mpfr_prec_t& interval_thread_bits() {
  thread_local mpfr_prec_t bits = 64;
  return bits;
}
}  // namespace detail

// The precision of the intervals that generic code creates (constants, default values) on this
// thread while the scope lives; 64 bits outside any scope (exact for every int).
class interval_precision_scope {
 public:
  explicit interval_precision_scope(mpfr_prec_t bits) : saved_(detail::interval_thread_bits()) {
    detail::interval_thread_bits() = bits;
  }
  ~interval_precision_scope() { detail::interval_thread_bits() = saved_; }
  interval_precision_scope(const interval_precision_scope&) = delete;
  interval_precision_scope& operator=(const interval_precision_scope&) = delete;

 private:
  mpfr_prec_t saved_;
};

class interval {
 public:
  // [0, 0] at the given precision.
  static interval zero(mpfr_prec_t bits) { return interval(bits, 0); }
  // The exact integer at the thread's interval precision: generic code's T(0), T(1), T(3), and
  // implicit as for the scalars (`T tau0 = 0`).
  interval(int value) : interval(detail::interval_thread_bits(), value) {}
  interval() : interval(0) {}
  // Not a precision: interval::zero(bits) is.
  interval(long) = delete;

  interval(const interval& o) {
    mpfi_init2(v_, mpfi_get_prec(o.v_));
    mpfi_set(v_, o.v_);
  }
  interval(interval&& o) noexcept {
    mpfi_init2(v_, MPFR_PREC_MIN);
    mpfi_swap(v_, o.v_);
  }
  interval& operator=(const interval& o) {
    if (this != &o) {
      mpfi_set_prec(v_, mpfi_get_prec(o.v_));
      mpfi_set(v_, o.v_);
    }
    return *this;
  }
  interval& operator=(interval&& o) noexcept {
    mpfi_swap(v_, o.v_);
    return *this;
  }
  ~interval() { mpfi_clear(v_); }

  mpfi_ptr get() { return v_; }
  mpfi_srcptr get() const { return v_; }
  mpfr_prec_t bits() const { return mpfi_get_prec(v_); }

  friend interval operator+(const interval& x, const interval& y) { return binary(mpfi_add, x, y); }
  friend interval operator-(const interval& x, const interval& y) { return binary(mpfi_sub, x, y); }
  friend interval operator*(const interval& x, const interval& y) { return binary(mpfi_mul, x, y); }
  friend interval operator/(const interval& x, const interval& y) { return binary(mpfi_div, x, y); }
  friend interval operator-(const interval& x) { return unary(mpfi_neg, x); }
  friend interval sqrt(const interval& x) { return unary(mpfi_sqrt, x); }
  friend interval abs(const interval& x) { return unary(mpfi_abs, x); }
  // The interval extension of max: [max of the left ends, max of the right ends].
  friend interval max(const interval& x, const interval& y) {
    interval out = zero(std::max(x.bits(), y.bits()));
    mpfr_t l, r, t;  // at out's bits: the end points are copied exactly
    mpfr_inits2(out.bits(), l, r, t, static_cast<mpfr_ptr>(nullptr));
    mpfi_get_left(l, x.get());
    mpfi_get_left(t, y.get());
    mpfr_max(l, l, t, MPFR_RNDD);
    mpfi_get_right(r, x.get());
    mpfi_get_right(t, y.get());
    mpfr_max(r, r, t, MPFR_RNDU);
    mpfi_interv_fr(out.get(), l, r);
    mpfr_clears(l, r, t, static_cast<mpfr_ptr>(nullptr));
    return out;
  }

 private:
  interval(mpfr_prec_t bits, int value) {
    mpfi_init2(v_, bits);
    mpfi_set_si(v_, value);
  }

  template <class Op>
  static interval binary(Op op, const interval& x, const interval& y) {
    interval out = zero(std::max(x.bits(), y.bits()));
    op(out.get(), x.get(), y.get());
    return out;
  }
  template <class Op>
  static interval unary(Op op, const interval& x) {
    interval out = zero(x.bits());
    op(out.get(), x.get());
    return out;
  }

  mpfi_t v_;
};

namespace detail {

// A binary128 number through three doubles (hi + mid + lo, each remainder exact in quad; 113
// bits need at most 53 + 53 + 7), MPFI rounding outward where `out` has fewer bits.
inline void set_exact_rounded(interval& out, __float128 x) {
  const double hi = static_cast<double>(x);
  if (!std::isfinite(hi)) {
    mpfi_set_d(out.get(), hi);
    return;
  }
  const __float128 r1 = x - hi;
  const double mid = static_cast<double>(r1);
  const __float128 r2 = r1 - mid;
  const double lo = static_cast<double>(r2);
  if (static_cast<__float128>(hi) + mid + lo != x || r2 != lo)
    throw std::domain_error("set_exact: a binary128 value does not split into three doubles");
  mpfi_set_d(out.get(), hi);
  mpfi_add_d(out.get(), out.get(), mid);
  mpfi_add_d(out.get(), out.get(), lo);
}

// A binary128 number from its fields (IEEE 754-2008, 3.4): sign, a 15-bit biased exponent and a
// 112-bit fraction, so |x| = (2^112 + fraction) 2^(e - 16383 - 112), or
// fraction 2^(1 - 16383 - 112) for e = 0. The 113-bit integer enters MPFR in one exact step, read
// in place as two limbs, and no temporary is allocated (the reference stores thousands of these
// per second). False, and `out` untouched, for infinities, NaN, or fewer than 113 bits.
inline bool set_exact_binary128(mpfr_ptr out, __float128 x) {
  static_assert(std::endian::native == std::endian::little, "binary128 fields read as little-endian words");
  static_assert(sizeof(mp_limb_t) == 8, "two 64-bit limbs");
  std::uint64_t w[2];
  std::memcpy(w, &x, sizeof w);
  const unsigned biased = static_cast<unsigned>(w[1] >> 48) & 0x7fffu;
  if (mpfr_get_prec(out) < 113 || biased == 0x7fffu) return false;
  mp_limb_t significand[2] = {static_cast<mp_limb_t>(w[0]), static_cast<mp_limb_t>(w[1] & ((std::uint64_t{1} << 48) - 1))};
  long exponent = 1 - 16383 - 112;
  if (biased != 0) {
    significand[1] |= mp_limb_t{1} << 48;
    exponent = static_cast<long>(biased) - 16383 - 112;
  }
  const mp_size_t size = significand[1] != 0 ? 2 : (significand[0] != 0 ? 1 : 0);
  mpz_t view;
  mpfr_set_z_2exp(out, mpz_roinit_n(view, significand, (w[1] >> 63) ? -size : size), exponent, MPFR_RNDN);
  if (size == 0 && (w[1] >> 63)) mpfr_neg(out, out, MPFR_RNDN);  // -0
  return true;
}

inline void set_exact_binary128(interval& out, __float128 x) {
  if (!set_exact_binary128(&out.get()->left, x)) {
    set_exact_rounded(out, x);
    return;
  }
  mpfr_set(&out.get()->right, &out.get()->left, MPFR_RNDN);
}

// The exact value of x (quad, MPFR or double) as an MPFR number of at least its bits (quad: 113);
// false for one that is not finite or has more bits.
template <scalar T>
[[nodiscard]] bool set_exact(mpfr_ptr out, const T& x) {
  bool exact = false;
  if constexpr (std::is_same_v<T, double>) {
    exact = mpfr_set_d(out, x, MPFR_RNDN) == 0;
  } else if constexpr (std::is_same_v<T, mpfr_real>) {
    exact = mpfr_set(out, x.backend().data(), MPFR_RNDN) == 0;
  } else {
    exact = set_exact_binary128(out, x.backend().value());
  }
  return exact && mpfr_number_p(out);
}

// The exact value of x (quad or MPFR) as a point interval. Exact when `out` has at least the
// bits of x (quad: 113); otherwise rounded outward.
template <scalar T>
void set_exact(interval& out, const T& x) {
  if constexpr (std::is_same_v<T, double>) {
    mpfi_set_d(out.get(), x);
  } else if constexpr (std::is_same_v<T, mpfr_real>) {
    mpfi_set_fr(out.get(), x.backend().data());
  } else {
    set_exact_binary128(out, x.backend().value());
  }
}

// The interval of a decimal text, rounded outward: it holds the real number the text denotes.
inline void set_decimal(interval& out, const std::string& text) {
  if (mpfi_set_str(out.get(), text.c_str(), 10) != 0)
    throw std::invalid_argument("set_decimal: not a decimal: " + text);
}

// x becomes the point at its right end (an upper bound, used as a number), or [0, right end].
inline void to_upper_point(interval& x) {
  mpfr_t r;
  mpfr_init2(r, x.bits());
  mpfi_get_right(r, x.get());
  mpfi_set_fr(x.get(), r);
  mpfr_clear(r);
}
inline void to_zero_hull(interval& x) {
  to_upper_point(x);
  mpfi_put_si(x.get(), 0);
}
// x = [-b, b] for b its right end (a ball of that radius).
inline void to_symmetric_hull(interval& x, interval& scratch) {
  to_upper_point(x);
  mpfi_neg(scratch.get(), x.get());
  mpfi_put(x.get(), scratch.get());
}

// Whether x and y are the same single point.
inline bool same_point(const interval& x, const interval& y) {
  mpfr_t a, b, c, d;
  mpfr_inits2(std::max(x.bits(), y.bits()), a, b, c, d, static_cast<mpfr_ptr>(nullptr));
  mpfi_get_left(a, x.get());
  mpfi_get_right(b, x.get());
  mpfi_get_left(c, y.get());
  mpfi_get_right(d, y.get());
  const bool same = mpfr_equal_p(a, b) && mpfr_equal_p(c, d) && mpfr_equal_p(a, c);
  mpfr_clears(a, b, c, d, static_cast<mpfr_ptr>(nullptr));
  return same;
}

// x = exp(x), enclosed at 64 bits (x first rounded outward to them): for the growth factors of
// the bounds (exp(mu h) and the like), which multiply quantities far below the state and need no
// more than a few digits. At the working precision (~180 bits for quad) each exponential costs
// two MPFR exponentials of that size, a few per segment and one per row.
inline void exp_at_64_bits(interval& x) {
  mpfi_t t;
  mpfi_init2(t, 64);
  mpfi_set(t, x.get());
  mpfi_exp(t, t);
  mpfi_set(x.get(), t);
  mpfi_clear(t);
}

// An upper bound of max |x| over the interval, as a double rounded up (+inf if it overflows).
inline double magnitude_up(const interval& x) {
  mpfr_t m;
  mpfr_init2(m, mpfi_get_prec(x.get()));
  mpfi_mag(m, x.get());
  const double d = mpfr_get_d(m, MPFR_RNDU);
  mpfr_clear(m);
  return d;
}

}  // namespace detail
}  // namespace eulervop
