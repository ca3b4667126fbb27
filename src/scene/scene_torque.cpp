// The tables of a scene that state its equations: [equations] (the coefficient form) and
// [torque] (numbers, formulas of the time and the state, and pieces on time windows).
#include "scene_reader.hpp"

#include <eulervop/model/expression.hpp>
#include <eulervop/scene/expression_parser.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <vector>

namespace eulervop::scene::detail {

namespace {

// The variables a formula may name in each form: the time, the three state components, and for
// a body the attitude.
expression_variables variables_of(scene_units units) {
  switch (units) {
    case scene_units::normalized: return {{"tau", "Omega1", "Omega2", "Omega3"}};
    case scene_units::physical: return {{"t", "omega1", "omega2", "omega3", "q0", "q1", "q2", "q3"}};
    case scene_units::coefficient: return {{"t", "y1", "y2", "y3"}};
  }
  return {};
}

// The names of `vars` that are in use, for messages.
std::vector<std::string> named(const expression_variables& vars) {
  std::vector<std::string> out;
  for (const std::string& n : vars.names)
    if (!n.empty()) out.push_back(n);
  return out;
}

std::string_view form_name(scene_units units) {
  switch (units) {
    case scene_units::normalized: return "a normalized scene";
    case scene_units::physical: return "a physical scene ([body])";
    case scene_units::coefficient: return "a scene in the coefficient form ([equations])";
  }
  return "";
}

// Why a formula failed, and for a variable of another form, which form has it and which
// variables this one has.
std::string formula_problem(const expression_error& e, scene_units units) {
  const expression_variables mine = variables_of(units);
  for (scene_units other : {scene_units::normalized, scene_units::physical, scene_units::coefficient}) {
    if (other == units) continue;
    const expression_variables theirs = variables_of(other);
    if (std::find(theirs.names.begin(), theirs.names.end(), e.culprit()) == theirs.names.end()) continue;
    if (std::find(mine.names.begin(), mine.names.end(), e.culprit()) != mine.names.end()) continue;
    return fmt::format("{} (`{}` is a variable of {}; {} has {})", e.what(), e.culprit(), form_name(other),
                       form_name(units), fmt::join(named(mine), ", "));
  }
  return fmt::format("{} (the variables here: {})", e.what(), fmt::join(named(mine), ", "));
}

}  // namespace

void scene_reader::constants_into(const toml::node& node, std::string_view field, decimal* out, std::size_t n) const {
  auto a = node.as_array();
  if (!a || a->size() != n) fail_value(node, field, fmt::format("must be an array of {} numbers", n));
  for (std::size_t i = 0; i < n; ++i) {
    const toml::node& item = (*a)[i];
    out[i] = item.is_string() ? formula_constant(item, fmt::format("{}{}", field, i + (n == 4 ? 0 : 1)))
                              : number(item, field);
  }
}

decimal scene_reader::formula_constant(const toml::node& node, std::string_view field) const {
  std::shared_ptr<const expression> e;
  try {
    e = std::make_shared<const expression>(parse_expression(node.as_string()->get(), expression_variables{}));
  } catch (const expression_error& x) {
    fail_value(node, field,
               fmt::format("{} (a constant formula here: numbers, pi, + - * / ^ and sin cos exp log sqrt tanh "
                           "atan sinh cosh)",
                           x.what()));
  }
  const double v = compiled_expression<double>(*e)(0.0, {0.0, 0.0, 0.0});
  if (!std::isfinite(v)) fail_value(node, field, "must be finite");
  return decimal{e->text, v, e};
}

// [equations] a = [a1, a2, a3]: the coefficient form y_i' = a_i y_j y_k + f_i, any finite a.
void scene_reader::read_equations(const toml::table& root, scene& s) const {
  const toml::table* eq = table(root, "equations");
  if (!eq) return;
  if (s.is_physical())
    fail_at(*eq, "[equations]: a scene gives either [body] (physical) or [equations] (the coefficient form), not both");
  only_keys(*eq, "[equations]", {"a"});
  const toml::node* a = eq->get("a");
  if (!a) fail_at(*eq, "[equations]: required field `a` is missing (y_i' = a_i y_j y_k + f_i, (i, j, k) cyclic)");
  s.coefficients = constants<3>(*a, "[equations] a");
  s.units = scene_units::coefficient;
}

// One component of the torque: a number, or a formula string. `numeric` is set for a number.
expression scene_reader::torque_term(const toml::node& node, const std::string& field, const scene& s,
                                     std::optional<decimal>& numeric) const {
  numeric.reset();
  if (node.is_number()) {
    numeric = number(node, field);
    return constant_expression(numeric->text);
  }
  const auto* text = node.as_string();
  if (!text) fail_value(node, field, "must be a number or a formula (a string)");
  expression e;
  try {
    e = parse_expression(text->get(), variables_of(s.units));
  } catch (const expression_error& x) {
    fail_value(node, field, formula_problem(x, s.units));
  }
  if (e.uses_attitude() && !attitude_given_) {
    int slot = expression::attitude_slot;
    while (!(e.uses & (1u << slot))) ++slot;
    fail_value(node, field,
               fmt::format("`q{}` is the attitude, which this scene does not give (add [initial] q = [q0, q1, q2, q3])",
                           slot - expression::attitude_slot));
  }
  return e;
}

// The three components of `key` ("[torque] M", or a piece's); `numbers` is set when all are numbers.
std::array<expression, 3> scene_reader::torque_terms(const toml::node& node, const std::string& key, const scene& s,
                                                     std::optional<decimal3>& numbers) const {
  auto a = node.as_array();
  if (!a || a->size() != 3) fail_value(node, key, "must be an array of 3 numbers or formulas");
  std::array<expression, 3> terms;
  decimal3 values;
  bool all_numbers = true;
  for (int i = 0; i < 3; ++i) {
    std::optional<decimal> numeric;
    terms[i] = torque_term((*a)[i], fmt::format("{}{}", key, i + 1), s, numeric);
    if (numeric) values[i] = *numeric;
    else all_numbers = false;
  }
  numbers.reset();
  if (all_numbers) numbers = values;
  return terms;
}

// A piece's bound: a constant number or formula, finite.
expression scene_reader::piece_bound(const toml::table& piece, std::string_view key, const std::string& where,
                                     const scene& s, double& value) const {
  const toml::node* node = piece.get(key);
  if (!node) fail_at(piece, fmt::format("{}: required field `{}` is missing", where, key));
  const std::string field = fmt::format("{} {}", where, key);
  std::optional<decimal> numeric;
  expression e = torque_term(*node, field, s, numeric);
  if (!e.is_constant())
    fail_value(*node, field, fmt::format("must be a constant (a bound may not name {})", s.time_name()));
  value = compiled_expression<double>(e)(0.0, {0.0, 0.0, 0.0});
  if (!std::isfinite(value)) fail_value(*node, field, "must be finite");
  return e;
}

// [[torque.piece]]: from, to and the components; bounds increasing, pieces not overlapping.
std::vector<torque_piece> scene_reader::read_pieces(const toml::node& node, const scene& s) const {
  const auto* list = node.as_array();
  if (!list || !list->is_array_of_tables()) fail_value(node, "[torque] piece", "must be tables ([[torque.piece]])");
  const std::string key(s.torque_key());
  struct placed {
    torque_piece piece;
    double from, to;
    const toml::table* table;
  };
  std::vector<placed> pieces;
  for (std::size_t n = 0; n < list->size(); ++n) {
    const toml::table& t = *(*list)[n].as_table();
    const std::string where = fmt::format("[[torque.piece]] {}", n + 1);
    only_keys(t, where, {"from", "to", key});
    placed p{{}, 0, 0, &t};
    p.piece.from = piece_bound(t, "from", where, s, p.from);
    p.piece.to = piece_bound(t, "to", where, s, p.to);
    if (!(p.from < p.to))
      fail_at(*t.get("to"), fmt::format("{}: from = {} must be below to = {}", where, p.piece.from.text, p.piece.to.text));
    const toml::node* g = t.get(key);
    if (!g) fail_at(t, fmt::format("{}: required field `{}` is missing", where, key));
    std::optional<decimal3> numbers;
    p.piece.terms = torque_terms(*g, fmt::format("{} {}", where, key), s, numbers);
    pieces.push_back(std::move(p));
  }
  std::stable_sort(pieces.begin(), pieces.end(), [](const placed& a, const placed& b) { return a.from < b.from; });
  for (std::size_t n = 1; n < pieces.size(); ++n)
    if (pieces[n].from < pieces[n - 1].to)
      fail_at(*pieces[n].table,
              fmt::format("[[torque.piece]]: [{}, {}) overlaps [{}, {})", pieces[n].piece.from.text,
                          pieces[n].piece.to.text, pieces[n - 1].piece.from.text, pieces[n - 1].piece.to.text));
  std::vector<torque_piece> out;
  for (placed& p : pieces) out.push_back(std::move(p.piece));
  return out;
}

// [torque.gravity_gradient] mean_motion = n (rad/s): the torque of a circular orbit
// (model/gravity_gradient.hpp). It turns the body by its attitude, so it needs [body] and
// [initial] q.
void scene_reader::read_gravity_gradient(const toml::table& gravity, scene& s) const {
  constexpr std::string_view where = "[torque.gravity_gradient]";
  if (!s.is_physical())
    fail_at(gravity, fmt::format("{}: the gravity gradient acts on a body: give [body] inertia and [initial] q", where));
  if (!attitude_given_)
    fail_at(gravity, fmt::format("{}: the gravity gradient depends on the attitude: give [initial] q = [q0, q1, q2, q3]",
                                 where));
  only_keys(gravity, where, {"mean_motion"});
  const toml::node* n = gravity.get("mean_motion");
  if (!n) fail_at(gravity, fmt::format("{}: required field `mean_motion` is missing (the orbit's rate, rad/s)", where));
  s.gravity_gradient = positive_number(*n, fmt::format("{} mean_motion", where));
}

// [torque]: G (normalized), M (physical) or f (coefficient form), and [[torque.piece]]. All
// numbers and no pieces: the constant torque of Eq. 5, as before formulas existed.
void scene_reader::read_torque(const toml::table& root, scene& s) const {
  const toml::table* torque = table(root, "torque");
  if (!torque) return;  // torque-free
  only_keys(*torque, "[torque]", {"G", "M", "f", "piece", "gravity_gradient"});
  if (const toml::table* gravity = table(*torque, "gravity_gradient")) read_gravity_gradient(*gravity, s);
  const toml::node* G = torque->get("G");
  const toml::node* M = torque->get("M");
  const toml::node* f = torque->get("f");
  if ((G != nullptr) + (M != nullptr) + (f != nullptr) > 1)
    fail_at(*torque, "[torque]: give one of G (normalized), M (physical) or f (coefficient form)");
  if (s.is_physical() && G) fail_at(*G, "[torque] G: a physical scene (one with [body]) takes its torque as M in N m");
  if (s.is_physical() && f) fail_at(*f, "[torque] f: a physical scene (one with [body]) takes its torque as M in N m");
  if (s.units == scene_units::normalized && M)
    fail_at(*M, "[torque] M: a physical torque needs [body] inertia (or give the normalized G)");
  if (s.units == scene_units::normalized && f)
    fail_at(*f, "[torque] f: the coefficient form's torque needs [equations] a (or give the normalized G)");
  if (s.is_coefficient_form() && (G || M))
    fail_at(G ? *G : *M, "[torque]: a scene in the coefficient form ([equations]) takes its torque as f");
  const toml::node* base = G ? G : M ? M : f;
  const toml::node* pieces = torque->get("piece");
  if (!base && !pieces) {
    if (s.gravity_gradient) return;  // the gravity gradient alone
    fail_at(*torque, fmt::format("[torque]: give {} or [[torque.piece]], or omit the table for a torque-free scene",
                                 s.torque_key()));
  }
  auto law = std::make_shared<torque_law>();
  law->name = std::string(s.torque_key());
  law->time_name = std::string(s.time_name());
  law->base = {constant_expression("0"), constant_expression("0"), constant_expression("0")};
  std::optional<decimal3> numbers;
  if (base) law->base = torque_terms(*base, fmt::format("[torque] {}", s.torque_key()), s, numbers);
  if (pieces) law->pieces = read_pieces(*pieces, s);
  if (numbers && law->pieces.empty())
    s.torque = *numbers;
  else
    s.torque_law = std::move(law);
}

}  // namespace eulervop::scene::detail
