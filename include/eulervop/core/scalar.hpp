// The wide scalar types (the concept and what every scalar has: scalar_traits.hpp; the precision
// names alone: precision.hpp).
//
// eulervop computes in three scalar types:
//   - double                      "double"
//   - quad (IEEE binary128)       "quad"      boost::multiprecision::float128 over __float128
//   - MPFR at run-time precision  "mpfr:BITS" boost::multiprecision::mpfr_float
#pragma once

#include <eulervop/core/detail/quad_text.hpp>
#include <eulervop/core/precision.hpp>
#include <eulervop/core/scalar_traits.hpp>

#include <boost/multiprecision/float128.hpp>
#include <boost/multiprecision/mpfr.hpp>
#include <boost/version.hpp>

#include <array>
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

// Decimal text to quad, correctly rounded. A decimal of at most 34 significant digits whose
// exponent, after moving the point behind the last digit, lies in [-48, 48] is M 10^E with M and
// 10^|E| both exact in binary128 (M < 10^34 < 2^113, 10^48 = 2^48 5^48 with 5^48 < 2^113): one
// correctly rounded product or quotient gives the correctly rounded value (Clinger's fast path,
// "How to read floating point numbers accurately", PLDI 1990). That covers every number a
// trajectory file holds, at a small part of strtoflt128's cost; other texts take Boost's way.
inline std::optional<quad> quad_fast_path(std::string_view text) {
  std::size_t i = 0;
  const bool negative = !text.empty() && text[0] == '-';
  if (negative || (!text.empty() && text[0] == '+')) ++i;
  unsigned __int128 m = 0;
  int digits = 0, exponent = 0;
  bool any = false, point = false;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '.' && !point) {
      point = true;
    } else if (c >= '0' && c <= '9') {
      any = true;
      if (m == 0 && c == '0') {  // leading zeros carry no digit
        if (point) --exponent;
        continue;
      }
      if (++digits > 34) return std::nullopt;
      m = m * 10 + static_cast<unsigned>(c - '0');
      if (point) --exponent;
    } else {
      break;
    }
  }
  if (!any) return std::nullopt;
  if (i < text.size()) {
    if (text[i] != 'e' && text[i] != 'E') return std::nullopt;
    int e = 0;
    const char* first = text.data() + i + 1;
    if (first < text.data() + text.size() && *first == '+') ++first;
    const auto [end, ec] = std::from_chars(first, text.data() + text.size(), e);
    if (ec != std::errc{} || end != text.data() + text.size()) return std::nullopt;
    if (e > 100000 || e < -100000) return std::nullopt;
    exponent += e;
  }
  __float128 x = static_cast<__float128>(m);  // exact: m < 10^34 < 2^113
  if (m != 0) {
    if (exponent < -48 || exponent > 48) return std::nullopt;
    static const std::array<__float128, 49> powers = [] {
      std::array<__float128, 49> p{};
      p[0] = 1;
      for (std::size_t k = 1; k < p.size(); ++k) p[k] = p[k - 1] * 10;  // exact: 10^48 = 2^48 5^48
      return p;
    }();
    x = exponent < 0 ? x / powers[static_cast<std::size_t>(-exponent)] : x * powers[static_cast<std::size_t>(exponent)];
  }
  return quad(negative ? -x : x);
}

inline std::optional<quad> wide_from_text(std::string_view text, scalar_tag<quad>) {
  if (auto v = quad_fast_path(text)) return v;
  try {
    return quad(std::string(text));
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

inline std::optional<mpfr_real> wide_from_text(std::string_view text, scalar_tag<mpfr_real>) {
  try {
    return mpfr_real(std::string(text));
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// x in scientific notation with `digits` digits after the point, correctly rounded (ties to even),
// as printf's %.*e (libquadmath's quadmath_snprintf, which Boost's str() calls) writes it, but by
// exact integer arithmetic: x = m 2^e, so the digits are round(m 2^e 10^(digits - E)) for the
// decimal exponent E, one GMP product or quotient of integers of a few hundred bits. libquadmath
// spends several microseconds a number here, which a million-row reference felt
// (tests/test_decimal_to_quad.cpp holds the two equal on random numbers of every magnitude).
inline std::string quad_text(const quad& x, unsigned digits) { return detail::quad_text_exact(x, digits); }

inline std::string wide_to_text(const quad& x, unsigned digits, scalar_tag<quad>) { return quad_text(x, digits); }

inline std::string wide_to_text(const mpfr_real& x, unsigned digits, scalar_tag<mpfr_real>) {
  return x.str(static_cast<std::streamsize>(digits), std::ios_base::scientific);
}

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
