// The precisions as the command line names them ("double", "quad", "mpfr:BITS"), without the
// scalar types themselves (core/scalar.hpp, which brings Boost.Multiprecision's float128 and
// MPFR headers): for the units that only parse, name or count precisions.
#pragma once

#include <climits>  // before digits.hpp, which tests ULONG_MAX
#include <cstdint>

#include <boost/multiprecision/detail/digits.hpp>

#include <charconv>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>

namespace eulervop {

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

}  // namespace eulervop
