// The text of an expression ("0.25*sin(t)^2", "-0.1*omega1", "exp(-t/10)*cos(2*tau)") turned
// into the postfix program of model/expression.hpp.
//
// Grammar, loosest binding first (whitespace ignored):
//   sum     := product (('+' | '-') product)*           left-associative
//   product := signed (('*' | '/') signed)*              left-associative
//   signed  := ('+' | '-')* power                        so -x^2 is -(x^2)
//   power   := primary ('^' integer)?                    one '^' only: (x^2)^3, never x^2^3
//   integer := ['+' | '-'] digits | '(' ['+' | '-'] digits ')'    |value| <= max_power
//   primary := number | 'pi' | variable | function '(' sum ')' | '(' sum ')'
//   function := 'sin' | 'cos' | 'exp' | 'log' | 'sqrt' | 'tanh' | 'atan' | 'sinh' | 'cosh'
//   number  := digits ['.' digits] [('e' | 'E') ['+' | '-'] digits], also '.5'; a finite double
// Numbers keep their exact decimal text (scene/decimal.hpp). A power's exponent must be an
// integer as written, so x^2 is the exact product x x in every number type.
#pragma once

#include <eulervop/model/expression_program.hpp>

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace eulervop::scene {

// The variables an expression may name: names[0] the time ("t" or "tau"), names[1..3] the state
// components ("omega1".."omega3", "Omega1".."Omega3" or "y1".."y3"), names[4..7] the attitude
// ("q0".."q3", a body's only). An empty name means the slot is not available; naming it is an
// unknown identifier.
struct expression_variables {
  std::array<std::string, expression::last_slot + 1> names;
};

// Why a text is not an expression. what() is one line that names the culprit and its 1-based
// column (in characters), e.g. "unknown identifier `omega1` at column 6".
class expression_error : public std::runtime_error {
 public:
  expression_error(const std::string& message, std::string culprit, std::size_t column)
      : std::runtime_error(message), culprit_(std::move(culprit)), column_(column) {}

  // The offending text as the message quotes it (control characters escaped as \xHH); empty for
  // an empty expression.
  const std::string& culprit() const noexcept { return culprit_; }
  // 1-based column of the culprit's first character.
  std::size_t column() const noexcept { return column_; }

 private:
  std::string culprit_;
  std::size_t column_;
};

// Limits that keep any input, a fuzzer's too, cheap and the recursive parser's stack shallow.
inline constexpr std::size_t max_expression_length = 4096;  // bytes
inline constexpr std::size_t max_expression_nesting = 64;   // parentheses, calls included
inline constexpr int max_expression_power = 1000;           // |n| in x^n

// Parses text; throws expression_error.
expression parse_expression(std::string_view text, const expression_variables& vars);

}  // namespace eulervop::scene
