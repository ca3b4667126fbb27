// An arithmetic expression of the time and the state as a program independent of the number
// type: postfix (reverse Polish) code over a stack, with its numbers kept as their exact decimal
// texts (model/expression.hpp compiles it for one number type). Apart from the compiled form, so
// that what only describes a scene (the scene library, model/torque_law.hpp) parses no scalar
// type.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace eulervop {

enum class expression_op : std::uint8_t {
  constant,  // push constants[arg]
  pi,        // push pi
  variable,  // push variable slot arg (0 = time, 1..3 = y1..y3, 4..7 = q0..q3)
  add,       // a b -> a + b
  sub,       // a b -> a - b
  mul,       // a b -> a * b
  div,       // a b -> a / b
  neg,       // a -> -a
  pow,       // a -> a^arg, arg an integer
  sin,
  cos,
  exp,
  log,
  sqrt,
  tanh,
  atan,
  sinh,
  cosh,
};

struct expression_step {
  expression_op op;
  std::int32_t arg = 0;  // constant: index into constants; variable: the slot; pow: the exponent
};

// A parsed expression: postfix code over a stack, independent of the number type.
struct expression {
  // The variable slots a step of kind `variable` reads.
  static constexpr int time_slot = 0;   // t (or tau)
  static constexpr int state_slots = 3;  // slots 1, 2, 3: y1, y2, y3
  // Slots 4..7: the attitude q0..q3 (a body with [initial] q; docs/attitude.md).
  static constexpr int attitude_slot = 4, attitude_slots = 4;
  static constexpr int last_slot = attitude_slot + attitude_slots - 1;

  std::string text;                    // the source as written, for messages
  std::vector<expression_step> code;   // postfix program; leaves one value on the stack
  std::vector<std::string> constants;  // exact canonical decimal texts (scene::parse_decimal)
  unsigned uses = 0;                   // bit s set when variable slot s is read
  std::size_t stack_depth = 0;         // the most values the program holds at once

  bool uses_time() const { return (uses & 1u) != 0; }
  bool uses_state() const { return (uses & 0b1110u) != 0; }
  bool uses_attitude() const { return (uses & 0b11110000u) != 0; }
  bool is_constant() const { return uses == 0; }
};

namespace detail {

// Checks that the code is a well-formed program (every index in range, no step reads an empty
// stack, one value left) and returns the stack depth it needs. An expression can be built by
// hand, so the compiled form does not trust the parser's stack_depth.
inline std::size_t checked_stack_depth(const expression& e) {
  auto bad = [&](const std::string& why) {
    return std::invalid_argument("malformed expression program for `" + e.text + "`: " + why);
  };
  std::size_t depth = 0, most = 0;
  for (const expression_step& s : e.code) {
    switch (s.op) {
      case expression_op::constant:
        if (s.arg < 0 || static_cast<std::size_t>(s.arg) >= e.constants.size())
          throw bad("constant index out of range");
        ++depth;
        break;
      case expression_op::variable:
        if (s.arg < 0 || s.arg > expression::last_slot) throw bad("variable slot out of range");
        ++depth;
        break;
      case expression_op::pi: ++depth; break;
      case expression_op::add:
      case expression_op::sub:
      case expression_op::mul:
      case expression_op::div:
        if (depth < 2) throw bad("an operator lacks an operand");
        --depth;
        break;
      case expression_op::neg:
      case expression_op::pow:
      case expression_op::sin:
      case expression_op::cos:
      case expression_op::exp:
      case expression_op::log:
      case expression_op::sqrt:
      case expression_op::tanh:
      case expression_op::atan:
      case expression_op::sinh:
      case expression_op::cosh:
        if (depth < 1) throw bad("a function lacks its argument");
        break;
      default: throw bad("unknown step");
    }
    if (depth > most) most = depth;
  }
  if (depth != 1) throw bad("the program does not leave exactly one value");
  return most;
}

}  // namespace detail
}  // namespace eulervop
