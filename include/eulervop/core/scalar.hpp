// Scalar types, the command-line precision names, and full-precision text I/O.
//
// eulervop computes in three scalar types:
//   - double                      "double"
//   - quad (IEEE binary128)       "quad"      boost::multiprecision::float128 over __float128
//   - MPFR at run-time precision  "mpfr:BITS" boost::multiprecision::mpfr_float
#pragma once

#include <boost/multiprecision/float128.hpp>
#include <boost/multiprecision/mpfr.hpp>

#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

namespace eulervop {

using quad = boost::multiprecision::float128;
using mpfr_real = boost::multiprecision::mpfr_float;  // variable precision, set per thread

template <class T> inline constexpr bool is_supported_scalar_v = false;
template <> inline constexpr bool is_supported_scalar_v<double> = true;
template <> inline constexpr bool is_supported_scalar_v<quad> = true;
template <> inline constexpr bool is_supported_scalar_v<mpfr_real> = true;

template <class T>
concept scalar = is_supported_scalar_v<T>;

// A precision as named on the command line.
struct precision {
  enum class kind { binary64, binary128, mpfr };
  kind type = kind::binary128;
  unsigned bits = 113;  // significand bits requested (53 and 113 for the IEEE types)

  // MPFR bounds: below 32 bits nothing here makes sense; above 16384 the Chebyshev degree
  // and the run time grow beyond any use we know of.
  static constexpr unsigned min_mpfr_bits = 32;
  static constexpr unsigned max_mpfr_bits = 16384;

  static precision binary64() { return {kind::binary64, 53}; }
  static precision binary128() { return {kind::binary128, 113}; }
  static precision mpfr(unsigned b) { return {kind::mpfr, b}; }

  // Parses "double", "quad" or "mpfr:BITS"; nullopt when the text is none of these or the bits
  // are out of [min_mpfr_bits, max_mpfr_bits].
  static std::optional<precision> parse(std::string_view text) {
    if (text == "double") return binary64();
    if (text == "quad") return binary128();
    constexpr std::string_view prefix = "mpfr:";
    if (!text.starts_with(prefix)) return std::nullopt;
    std::string_view digits = text.substr(prefix.size());
    unsigned b = 0;
    auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), b);
    if (ec != std::errc{} || end != digits.data() + digits.size() || digits.empty()) return std::nullopt;
    if (b < min_mpfr_bits || b > max_mpfr_bits) return std::nullopt;
    return mpfr(b);
  }

  std::string name() const {
    switch (type) {
      case kind::binary64: return "double";
      case kind::binary128: return "quad";
      case kind::mpfr: return "mpfr:" + std::to_string(bits);
    }
    return "?";
  }

  // Decimal digits that a value of this precision carries (used for tolerances and output).
  unsigned digits10() const { return static_cast<unsigned>(std::floor((bits - 1) * 0.30102999566398120)); }
};

// Boost's MPFR backend sets precision in decimal digits and converts with
// digits10_2_2(d) = floor(1000 d / 301) + (1 or 2) bits. This picks the smallest d that gives at
// least `bits` bits, so "mpfr:256" computes with 257 bits: never fewer than asked.
inline unsigned mpfr_digits10_for_bits(unsigned bits) {
  unsigned d = 1;
  while (boost::multiprecision::detail::digits10_2_2(static_cast<unsigned long>(d)) < bits) ++d;
  return d;
}
inline unsigned mpfr_effective_bits(unsigned bits) {
  return static_cast<unsigned>(boost::multiprecision::detail::digits10_2_2(
      static_cast<unsigned long>(mpfr_digits10_for_bits(bits))));
}

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

// Machine epsilon of T at its current precision (for MPFR: the thread's default precision).
template <scalar T>
T epsilon() {
  if constexpr (std::is_same_v<T, mpfr_real>) {
    const auto bits = boost::multiprecision::detail::digits10_2_2(
        static_cast<unsigned long>(mpfr_real::thread_default_precision()));
    T e = 1;
    return ldexp(e, 1 - static_cast<int>(bits));
  } else {
    return std::numeric_limits<T>::epsilon();
  }
}

// Significand bits of T at its current precision.
template <scalar T>
unsigned significand_bits() {
  if constexpr (std::is_same_v<T, mpfr_real>)
    return static_cast<unsigned>(boost::multiprecision::detail::digits10_2_2(
        static_cast<unsigned long>(mpfr_real::thread_default_precision())));
  else
    return static_cast<unsigned>(std::numeric_limits<T>::digits);
}

// Significant decimal digits written for a value of T: enough to round-trip
// (max_digits10 = ceil(bits log10 2) + 1), which is 17 for double and 36 for quad.
template <scalar T>
unsigned output_digits() {
  return static_cast<unsigned>(std::ceil(significand_bits<T>() * 0.30102999566398120)) + 1;
}

// Full-precision scientific text of x, round-trip exact.
template <scalar T>
std::string to_text(const T& x) {
  const unsigned digits = output_digits<T>();
  if constexpr (std::is_same_v<T, double>) {
    char buf[64];
    auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific, digits - 1);
    return std::string(buf, end);
  } else {
    return x.str(static_cast<std::streamsize>(digits), std::ios_base::scientific);
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
    try {
      return T(std::string(text));
    } catch (const std::exception&) {
      return std::nullopt;
    }
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

}  // namespace eulervop
