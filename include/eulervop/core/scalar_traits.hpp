// The scalar concept and the functions every scalar type has (epsilon, digits, text I/O,
// conversion, pi), without the wide types themselves: double-only code includes this header and
// never Boost.Multiprecision's float128 and MPFR headers. The wide types, quad and mpfr_real,
// are in core/scalar.hpp, which makes them scalars.
#pragma once

#include <eulervop/core/precision.hpp>

#include <charconv>
#include <cmath>
#include <ios>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

namespace eulervop {

// True for the scalar types: double here, quad and mpfr_real in core/scalar.hpp.
template <class T> inline constexpr bool is_supported_scalar_v = false;
template <> inline constexpr bool is_supported_scalar_v<double> = true;

template <class T>
concept scalar = is_supported_scalar_v<T>;

// True for a scalar whose precision is set at run time, per thread (mpfr_real, core/scalar.hpp).
template <class T> inline constexpr bool has_variable_precision_v = false;

template <class T>
concept variable_precision_scalar = scalar<T> && has_variable_precision_v<T>;

// Significand bits of T at its current precision (for MPFR: the thread's default precision).
template <scalar T>
unsigned significand_bits() {
  if constexpr (variable_precision_scalar<T>)
    return static_cast<unsigned>(boost::multiprecision::detail::digits10_2_2(
        static_cast<unsigned long>(T::thread_default_precision())));
  else
    return static_cast<unsigned>(std::numeric_limits<T>::digits);
}

// Machine epsilon of T at its current precision (for MPFR: the thread's default precision).
template <scalar T>
T epsilon() {
  if constexpr (variable_precision_scalar<T>) {
    T e = 1;
    return ldexp(e, 1 - static_cast<int>(significand_bits<T>()));
  } else {
    return std::numeric_limits<T>::epsilon();
  }
}

// Significant decimal digits written for a value of T: enough to round-trip
// (max_digits10 = ceil(bits log10 2) + 1), which is 17 for double and 36 for quad.
template <scalar T>
unsigned output_digits() {
  return static_cast<unsigned>(std::ceil(significand_bits<T>() * 0.30102999566398120)) + 1;
}

// The tag that selects a scalar type's own functions: pi, and the text of the wide types
// (core/scalar.hpp).
template <class T>
struct scalar_tag {};

// Full-precision scientific text of x, round-trip exact.
template <scalar T>
std::string to_text(const T& x) {
  const unsigned digits = output_digits<T>();
  if constexpr (std::is_same_v<T, double>) {
    char buf[64];
    auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific, digits - 1);
    return std::string(buf, end);
  } else {
    return wide_to_text(x, digits, scalar_tag<T>{});  // core/scalar.hpp
  }
}

// Parses a decimal number into T, correctly rounded. nullopt when the text is not a number.
template <scalar T>
std::optional<T> from_text(std::string_view text) {
  if constexpr (std::is_same_v<T, double>) {
    double v = 0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc{} || end != text.data() + text.size()) return std::nullopt;
    return v;
  } else {
    return wide_from_text(text, scalar_tag<T>{});  // core/scalar.hpp
  }
}

// Converts between scalar types (explicitly, so narrowing is always visible at the call site).
template <scalar To, scalar From>
To convert(const From& x) {
  if constexpr (std::is_same_v<To, From>) {
    return x;
  } else if constexpr (std::is_same_v<To, double>) {
    return static_cast<double>(x);
  } else {
    return To(x);
  }
}


inline double pi_of(scalar_tag<double>) { return std::numbers::pi_v<double>; }

// pi correctly rounded in T, at T's current precision.
template <scalar T>
T pi_in() {
  return pi_of(scalar_tag<T>{});
}

}  // namespace eulervop
