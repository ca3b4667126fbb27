// A number as the user wrote it: its exact decimal text plus the nearest double.
//
// Quad and MPFR runs must see the decimal the user typed, not the double nearest to it:
// "0.1" has to become 0.1 to 36 digits in quad. So every number from a scene or a flag is kept
// as text and converted once, in the target type, by to_scalar<T>.
#pragma once

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/model/expression_program.hpp>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace eulervop {
// model/expression.hpp, which a unit that calls to_scalar includes: the scene's description parses
// no scalar type of its own.
template <scalar T>
class compiled_expression;
}  // namespace eulervop

namespace eulervop::scene {

struct decimal {
  std::string text;    // canonical decimal text: [-]digits[.digits][e[+-]digits], no '+' or '_'
  double value = 0;    // the nearest double, for validation and messages
  // A constant formula instead of a decimal ("2/3", "cos(1.1)", where a scene allows one): then
  // `text` is the formula as written, `value` its double, and to_scalar evaluates it in T.
  std::shared_ptr<const expression> formula;
  // A binary64 number as a program holds it (a NumPy array's entry): the number is `value`
  // exactly, and `text` only shows it (its shortest round-trip form, or empty).
  bool binary = false;

  // The number in T, correctly rounded from the decimal text (at T's current precision); a
  // formula evaluated in T; a binary number converted exactly.
  template <scalar T>
  T to_scalar() const {
    if (binary) return T(value);
    if (formula) return compiled_expression<T>(*formula)(T(0), vec3<T>{T(0), T(0), T(0)});
    auto v = eulervop::from_text<T>(text);
    if (!v) throw std::logic_error("decimal text does not convert: " + text);
    return *v;
  }
};

// Why a text is not an acceptable decimal.
enum class decimal_problem { none, not_a_number, not_finite, out_of_range };

struct decimal_parse_result {
  std::optional<decimal> number;
  decimal_problem problem = decimal_problem::none;
};

// Parses a plain decimal ("-1.5e3", "0.1", "+2", "136"). Rejects nan/inf (not_finite),
// hexadecimal and anything else (not_a_number), and magnitudes a double cannot hold
// (out_of_range), since every later check is done on the double value too.
// With allow_underscores, TOML's digit separators ("1_000.5") are accepted and dropped.
decimal_parse_result parse_decimal(std::string_view text, bool allow_underscores = false);

// The shortest decimal that round-trips to x (used when the source text is not available).
decimal decimal_from_double(double x);

// x itself (decimal::binary), shown by its shortest round-trip text when `with_text`.
decimal binary_number(double x, bool with_text = true);

// The exact decimal of an integer.
decimal decimal_from_integer(long long x);

// The exact product a b as a decimal (`eulervop map` scales a scene's torque by the text of
// --torque-scales); nullopt if it is out of the range of a double.
std::optional<decimal> decimal_product(const decimal& a, const decimal& b);

// Human-readable reason for a decimal_problem, for error messages.
std::string_view describe(decimal_problem problem);

}  // namespace eulervop::scene
