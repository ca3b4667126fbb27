#include <eulervop/scene/decimal.hpp>

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <vector>

namespace eulervop::scene {

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
  if (s.empty() || !std::isalpha(static_cast<unsigned char>(s[0]))) return false;  // a number, most often
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

decimal binary_number(double x, bool with_text) {
  decimal d;
  if (with_text) d = decimal_from_double(x);
  d.value = x;
  d.binary = true;
  return d;
}

decimal decimal_from_integer(long long x) { return {std::to_string(x), static_cast<double>(x)}; }

namespace {
// A canonical decimal as sign, integer digits M and exponent E: value = sign M 10^E.
struct scaled_integer {
  bool negative = false;
  std::string digits;  // no leading zeros ("" for zero)
  long long exponent = 0;
};
scaled_integer split_decimal(const std::string& text) {
  scaled_integer out;
  std::size_t i = 0;
  if (text[i] == '-') {
    out.negative = true;
    ++i;
  }
  const std::size_t e = text.find_first_of("eE", i);
  const std::string mantissa = text.substr(i, e == std::string::npos ? std::string::npos : e - i);
  if (e != std::string::npos) out.exponent = std::stoll(text.substr(e + 1));
  const std::size_t dot = mantissa.find('.');
  std::string digits = mantissa;
  if (dot != std::string::npos) {
    digits = mantissa.substr(0, dot) + mantissa.substr(dot + 1);
    out.exponent -= static_cast<long long>(mantissa.size() - dot - 1);
  }
  const std::size_t first = digits.find_first_not_of('0');
  out.digits = first == std::string::npos ? "" : digits.substr(first);
  return out;
}
}  // namespace

std::optional<decimal> decimal_product(const decimal& a, const decimal& b) {
  const scaled_integer x = split_decimal(a.text), y = split_decimal(b.text);
  if (x.digits.empty() || y.digits.empty()) return decimal{"0", 0.0};
  // Schoolbook product of the digit strings.
  std::vector<int> prod(x.digits.size() + y.digits.size(), 0);
  for (std::size_t i = x.digits.size(); i-- > 0;)
    for (std::size_t j = y.digits.size(); j-- > 0;) {
      const std::size_t k = i + j + 1;
      const int v = (x.digits[i] - '0') * (y.digits[j] - '0') + prod[k];
      prod[k] = v % 10;
      prod[k - 1] += v / 10;
    }
  std::string digits;
  for (int d : prod)
    if (!(digits.empty() && d == 0)) digits += static_cast<char>('0' + d);
  long long exponent = x.exponent + y.exponent;
  while (digits.size() > 1 && digits.back() == '0') {
    digits.pop_back();
    ++exponent;
  }
  // Scientific with one leading digit ("1e-4", "2.5e-3"), plain when the exponent is 0.
  const long long e = exponent + static_cast<long long>(digits.size()) - 1;
  std::string text = x.negative != y.negative ? "-" : "";
  text += digits.substr(0, 1);
  if (digits.size() > 1) text += "." + digits.substr(1);
  if (e != 0) text += fmt::format("e{}", e);
  return parse_decimal(text).number;
}

std::string_view describe(decimal_problem problem) {
  switch (problem) {
    case decimal_problem::none: return "ok";
    case decimal_problem::not_a_number: return "not a decimal number";
    case decimal_problem::not_finite: return "not finite";
    case decimal_problem::out_of_range: return "out of the range of a double";
  }
  return "invalid";
}

}  // namespace eulervop::scene
