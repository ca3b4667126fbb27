// Plain MPFR numbers beside the intervals (interval.hpp): the midpoints that the certificate's
// large sums run on (rounded to nearest, then widened by a bound of their roundings), the bounds
// of those roundings (at 64 bits, rounded up).
#pragma once

#include <eulervop/certify/interval.hpp>

#include <mpfi.h>
#include <mpfr.h>

#include <cmath>
#include <cstddef>
#include <limits>

namespace eulervop::detail {

// An owning MPFR number.
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

// out = the width of x, rounded up, from its end points in place.
inline void width_up(real& out, const interval& x) {
  mpfr_sub(out.get(), &x.get()->right, &x.get()->left, MPFR_RNDU);
}

// out = an interval holding the exact sum of the n doubles x[0..n): their sum in
// double, widened by gamma_(n-1) sum |x_k| (Higham 2002, section 3.1; sums of doubles do not
// underflow), the bound itself rounded up by a relative 1e-12. One interval operation instead of
// n exact additions, for sums whose last bits do not matter (the variational matrix and the
// integral term at a segment's end, certifier.hpp).
inline void enclose_double_sum(interval& out, const double* x, std::size_t n, interval& scratch) {
  double sum = 0, magnitude = 0;
  for (std::size_t k = 0; k < n; ++k) {
    sum += x[k];
    magnitude += std::abs(x[k]);
  }
  const double nu = static_cast<double>(n) * std::numeric_limits<double>::epsilon() / 2;
  const double error = nu / (1 - nu) * magnitude * (1 + 1e-12);
  mpfi_set_d(out.get(), sum);
  mpfi_interv_d(scratch.get(), -error, error);
  mpfi_add(out.get(), out.get(), scratch.get());
}

}  // namespace eulervop::detail
