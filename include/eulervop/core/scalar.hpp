// The wide scalar types (the concept and what every scalar has: scalar_traits.hpp; the precision
// names alone: precision.hpp).
//
// eulervop computes in three scalar types:
//   - double                      "double"
//   - quad (IEEE binary128)       "quad"      boost::multiprecision::float128 over __float128
//   - MPFR at run-time precision  "mpfr:BITS" boost::multiprecision::mpfr_float
#pragma once

#include <eulervop/core/precision.hpp>
#include <eulervop/core/scalar_traits.hpp>

#include <boost/multiprecision/float128.hpp>
#include <boost/multiprecision/mpfr.hpp>
#include <boost/version.hpp>

#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

// Per-thread MPFR precision (mpfr_float::thread_default_precision) and Boost.PFR arrived after
// 1.74, Debian 12's default Boost: tools/setup.sh unpacks 1.81's headers into .deps/ (docs/python.md,
// "Install"), which must come before any system Boost on the include path.
static_assert(BOOST_VERSION >= 108100, "eulervop needs Boost 1.81's headers: run tools/setup.sh (it unpacks them into .deps/)");

namespace eulervop {

using quad = boost::multiprecision::float128;
using mpfr_real = boost::multiprecision::mpfr_float;  // variable precision, set per thread

template <> inline constexpr bool is_supported_scalar_v<quad> = true;
template <> inline constexpr bool is_supported_scalar_v<mpfr_real> = true;
template <> inline constexpr bool has_variable_precision_v<mpfr_real> = true;

// Sets the precision of MPFR values created on this thread for the lifetime of the scope.
class mpfr_precision_scope {
 public:
  explicit mpfr_precision_scope(unsigned bits) : saved_(mpfr_real::thread_default_precision()) {
    mpfr_real::thread_default_precision(mpfr_digits10_for_bits(bits));
  }
  ~mpfr_precision_scope() { mpfr_real::thread_default_precision(saved_); }
  mpfr_precision_scope(const mpfr_precision_scope&) = delete;
  mpfr_precision_scope& operator=(const mpfr_precision_scope&) = delete;

 private:
  unsigned saved_;
};

// pi in quad: libquadmath's M_PIq, a __float128 literal of 37 significant digits, within 1e-37 of
// pi, far below half an ulp of binary128 at pi (2e-34), so it rounds as pi itself does
// (tests/test_expression.cpp compares it with pi from 100 digits).
inline quad pi_of(scalar_tag<quad>) { return quad(M_PIq); }

// pi in MPFR: MPFR's own constant, correctly rounded at the value's precision (the thread's
// default precision, set by mpfr_precision_scope): any precision, never a double or a fixed string.
inline mpfr_real pi_of(scalar_tag<mpfr_real>) {
  mpfr_real pi;
  mpfr_const_pi(pi.backend().data(), MPFR_RNDN);
  return pi;
}

}  // namespace eulervop
