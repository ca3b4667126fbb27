#include "decimal.hpp"

#include <cctype>
#include <charconv>
#include <cmath>

namespace eulervop::app {

namespace {

// The grammar of a plain decimal: [+-]? digits? [. digits?] ([eE] [+-]? digits)?, with at
// least one mantissa digit. std::from_chars also accepts "inf", "nan" and hex forms, which we
// must reject, so the grammar is checked first.
bool is_plain_decimal(std::string_view s) {
  std::size_t i = 0;
  auto digits = [&] {
    std::size_t start = i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
    return i - start;
  };
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t mantissa = digits();
  if (i < s.size() && s[i] == '.') {
    ++i;
    mantissa += digits();
  }
  if (mantissa == 0) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (digits() == 0) return false;
  }
  return i == s.size();
}

bool names_non_finite(std::string_view s) {
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) s.remove_prefix(1);
  std::string lower;
  for (char c : s) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower == "nan" || lower == "inf" || lower == "infinity";
}

}  // namespace

decimal_parse_result parse_decimal(std::string_view raw, bool allow_underscores) {
  std::string text;
  text.reserve(raw.size());
  for (char c : raw) {
    if (allow_underscores && c == '_') continue;
    text += c;
  }
  if (names_non_finite(text)) return {std::nullopt, decimal_problem::not_finite};
  if (!is_plain_decimal(text)) return {std::nullopt, decimal_problem::not_a_number};
  if (text[0] == '+') text.erase(0, 1);

  double value = 0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec == std::errc::result_out_of_range || !std::isfinite(value))
    return {std::nullopt, decimal_problem::out_of_range};
  if (ec != std::errc{} || end != text.data() + text.size())
    return {std::nullopt, decimal_problem::not_a_number};
  // A non-zero decimal that underflows to 0 in double would pass "> 0" checks in T but not in
  // double; out of range keeps the two views consistent.
  if (value == 0) {
    const std::string_view mantissa = std::string_view(text).substr(0, text.find_first_of("eE"));
    if (mantissa.find_first_of("123456789") != std::string_view::npos)
      return {std::nullopt, decimal_problem::out_of_range};
  }
  return {decimal{std::move(text), value}, decimal_problem::none};
}

decimal decimal_from_double(double x) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  return {std::string(buf, end), x};
}

decimal decimal_from_integer(long long x) { return {std::to_string(x), static_cast<double>(x)}; }

std::string_view describe(decimal_problem problem) {
  switch (problem) {
    case decimal_problem::none: return "ok";
    case decimal_problem::not_a_number: return "not a decimal number";
    case decimal_problem::not_finite: return "must be finite";
    case decimal_problem::out_of_range: return "out of the range of a double";
  }
  return "invalid";
}

}  // namespace eulervop::app
