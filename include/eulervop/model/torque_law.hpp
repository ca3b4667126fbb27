// A torque given by formulas (docs/scenes.md, "Torques of time and state"): three components,
// each an expression of the time and the state (model/expression_program.hpp; a plain number is an
// expression with one constant), and pieces, time windows [from, to) in which other components
// apply. Outside every piece the base components apply (zero when the scene gives none).
//
// This is the description, independent of the number type: expression_torque.hpp compiles it in
// the run's type, with the change of variables from the scene's form to the integrator's.
#pragma once

#include <eulervop/model/expression_program.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace eulervop {

struct torque_piece {
  expression from, to;             // constant expressions in the scene's time variable; from < to
  std::array<expression, 3> terms;  // the components inside [from, to)
};

struct torque_law {
  std::array<expression, 3> base;   // the components outside every piece
  std::vector<torque_piece> pieces;  // in increasing order, not overlapping (the scene checks)
  // How the components are named in messages: "M" (physical, N m), "G" (normalized) or "f"
  // (the coefficient form); component i is name + (i + 1).
  std::string name = "G";
  std::string time_name = "tau";  // the scene's time variable, for messages

  // True when some component reads the state (its Jacobian enters the reference's correction).
  bool uses_state() const {
    return any_term([](const expression& e) { return e.uses_state(); });
  }

  // True when some component reads the attitude q0..q3: the rates and q are then one problem.
  bool uses_attitude() const {
    return any_term([](const expression& e) { return e.uses_attitude(); });
  }

  // True when `test` holds for some component, of the base or of a piece.
  template <class Test>
  bool any_term(Test test) const {
    for (const expression& e : base)
      if (test(e)) return true;
    for (const torque_piece& p : pieces)
      for (const expression& e : p.terms)
        if (test(e)) return true;
    return false;
  }
};

// The expression of one decimal number (canonical decimal text, scene/decimal.hpp): a plain
// number in a torque is the same program as any formula, with one constant.
inline expression constant_expression(const std::string& decimal_text) {
  expression e;
  e.text = decimal_text;
  e.code = {{expression_op::constant, 0}};
  e.constants = {decimal_text};
  e.stack_depth = 1;
  return e;
}

// The expression `factor` (decimal text) times e: e's program, then the factor and a product.
inline expression scaled_expression(const expression& e, const std::string& factor) {
  expression out = e;
  out.text = factor + "*(" + e.text + ")";
  out.code.push_back({expression_op::constant, static_cast<std::int32_t>(out.constants.size())});
  out.code.push_back({expression_op::mul, 0});
  out.constants.push_back(factor);
  out.stack_depth = std::max<std::size_t>(out.stack_depth, 2);
  return out;
}

// The whole law times `factor` (decimal text): every component, base and pieces (`eulervop map`
// scales a scene's torque).
inline torque_law scaled_law(const torque_law& law, const std::string& factor) {
  torque_law out = law;
  for (expression& e : out.base) e = scaled_expression(e, factor);
  for (torque_piece& p : out.pieces)
    for (expression& e : p.terms) e = scaled_expression(e, factor);
  return out;
}

// "(f1, f2, f3)", and each piece's "; on [from, to): (...)": the law as its formulas read.
inline std::string law_text(const torque_law& law) {
  const auto three = [](const std::array<expression, 3>& t) { return "(" + t[0].text + ", " + t[1].text + ", " + t[2].text + ")"; };
  std::string out = three(law.base);
  for (const torque_piece& p : law.pieces) out += "; on [" + p.from.text + ", " + p.to.text + "): " + three(p.terms);
  return out;
}

}  // namespace eulervop
