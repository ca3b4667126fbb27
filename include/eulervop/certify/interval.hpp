// An owning MPFI interval (Revol & Rouillier, "Motivations for an arbitrary precision interval
// arithmetic and the MPFI library", 2005): every operation rounds its end points outward, so the
// exact result of the real operation on any points of the operands lies inside the result.
//
// The certificate of certified_bound.hpp does thousands of operations per segment; the C calls
// on preallocated intervals avoid the temporaries (and their allocations) of Boost's
// mpfi_float expression templates, which cost about twice as much per multiply-add here.
#pragma once

#include <eulervop/core/scalar.hpp>

#include <mpfi.h>
#include <mpfr.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace eulervop::detail {

class interval {
 public:
  explicit interval(mpfr_prec_t bits) {
    mpfi_init2(v_, bits);
    mpfi_set_ui(v_, 0);
  }
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

 private:
  mpfi_t v_;
};

// An owning MPFR number (midpoints at the working precision; bounds at 64 bits, rounded up).
class real {
 public:
  explicit real(mpfr_prec_t bits) {
    mpfr_init2(v_, bits);
    mpfr_set_ui(v_, 0, MPFR_RNDN);
  }
  real(const real& o) {
    mpfr_init2(v_, mpfr_get_prec(o.v_));
    mpfr_set(v_, o.v_, MPFR_RNDN);
  }
  real(real&& o) noexcept {
    mpfr_init2(v_, MPFR_PREC_MIN);
    mpfr_swap(v_, o.v_);
  }
  real& operator=(const real& o) {
    if (this != &o) {
      mpfr_set_prec(v_, mpfr_get_prec(o.v_));
      mpfr_set(v_, o.v_, MPFR_RNDN);
    }
    return *this;
  }
  real& operator=(real&& o) noexcept {
    mpfr_swap(v_, o.v_);
    return *this;
  }
  ~real() { mpfr_clear(v_); }
  mpfr_ptr get() { return v_; }
  mpfr_srcptr get() const { return v_; }

 private:
  mpfr_t v_;
};

// bound += |x|, rounded up.
inline void add_abs_up(real& bound, mpfr_srcptr x) {
  if (mpfr_sgn(x) < 0)
    mpfr_sub(bound.get(), bound.get(), x, MPFR_RNDU);
  else
    mpfr_add(bound.get(), bound.get(), x, MPFR_RNDU);
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
    // binary128 = hi + mid + lo in doubles: each remainder is exact in quad, and 113 bits need
    // at most three doubles (53 + 53 + 7). Checked, as subnormal doubles would lose bits.
    const double hi = static_cast<double>(x);
    const T r1 = x - T(hi);
    const double mid = static_cast<double>(r1);
    const T r2 = r1 - T(mid);
    const double lo = static_cast<double>(r2);
    if (T(hi) + T(mid) + T(lo) != x || r2 != T(lo))
      throw std::domain_error("set_exact: a binary128 value does not split into three doubles");
    mpfi_set_d(out.get(), hi);
    mpfi_add_d(out.get(), out.get(), mid);
    mpfi_add_d(out.get(), out.get(), lo);
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

// An upper bound of max |x| over the interval, as a double rounded up (+inf if it overflows).
inline double magnitude_up(const interval& x) {
  mpfr_t m;
  mpfr_init2(m, mpfi_get_prec(x.get()));
  mpfi_mag(m, x.get());
  const double d = mpfr_get_d(m, MPFR_RNDU);
  mpfr_clear(m);
  return d;
}

}  // namespace eulervop::detail
