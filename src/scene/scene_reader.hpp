// The reader of a scene's TOML (scene.hpp): one parsed document into a validated scene, with
// messages that name the field, its place in the file and the value as written. Shared by the
// files that read its tables: scene.cpp (the scene's form, initial state, span, runs and
// reference) and scene_torque.cpp ([equations] and [torque]).
#pragma once

#include <eulervop/scene/scene.hpp>

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace eulervop::scene::detail {

// Longest value text quoted in a message before it is shortened.
constexpr std::size_t max_quoted_chars = 60;

inline std::string shorten(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  if (text.size() > max_quoted_chars) text = text.substr(0, max_quoted_chars - 3) + "...";
  return text;
}

// Reads one parsed TOML document into a scene, remembering the source text so numbers keep
// their exact decimal spelling (toml++ gives us only the double).
class scene_reader {
 public:
  scene_reader(std::string_view text, std::string origin) : text_(text), origin_(std::move(origin)) {
    line_starts_.push_back(0);
    for (std::size_t i = 0; i < text_.size(); ++i)
      if (text_[i] == '\n') line_starts_.push_back(i + 1);
  }

  scene read();

 private:
  // ---- messages ----------------------------------------------------------------------------
  [[noreturn]] void fail(std::string_view what) const {
    throw input_error(fmt::format("scene {}: {}", origin_, what));
  }
  // "scene x.toml:12:11: [span] tau_end = -1: must be positive"
  [[noreturn]] void fail_value(const toml::node& node, std::string_view field, std::string_view why) const {
    throw input_error(fmt::format("scene {}{}: {} = {}: {}", origin_, where(node), field, quoted(node), why));
  }
  [[noreturn]] void fail_at(const toml::node& node, std::string_view what) const {
    throw input_error(fmt::format("scene {}{}: {}", origin_, where(node), what));
  }

  std::string where(const toml::node& node) const {
    const auto& b = node.source().begin;
    if (b.line == 0) return {};
    return fmt::format(":{}:{}", b.line, b.column);
  }

  // The value as the user wrote it (numbers and other one-line values), else as toml++ formats it.
  std::string quoted(const toml::node& node) const {
    if (node.is_number()) {
      if (auto token = token_at(node); !token.empty()) return shorten(std::string(token));
    }
    std::ostringstream out;
    if (auto s = node.as_string()) {
      return shorten(fmt::format("{:?}", s->get()));  // double-quoted, escaped as in TOML
    } else if (auto a = node.as_array()) {
      // Element by element, so that numbers keep the text the user wrote (0.9, not 0.9000...02).
      std::string items;
      for (const toml::node& item : *a) items += (items.empty() ? "" : ", ") + quoted(item);
      return shorten("[" + items + "]");
    } else if (node.is_table()) {
      return "(a table)";
    } else {
      node.visit([&](const auto& v) { out << v; });
    }
    return shorten(out.str());
  }

  // ---- exact decimal text ----------------------------------------------------------------
  // The number token starting at the node's source position. toml++ counts columns in code
  // points, so the byte offset is found by walking the line's UTF-8.
  std::string_view token_at(const toml::node& node) const {
    const auto& b = node.source().begin;
    if (b.line == 0 || b.line > line_starts_.size()) return {};
    std::size_t i = line_starts_[b.line - 1];
    for (std::size_t col = 1; col < b.column && i < text_.size() && text_[i] != '\n'; ++col) {
      ++i;
      while (i < text_.size() && (static_cast<unsigned char>(text_[i]) & 0xC0) == 0x80) ++i;
    }
    std::size_t j = i;
    while (j < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[j])) || text_[j] == '_' ||
                                text_[j] == '+' || text_[j] == '-' || text_[j] == '.'))
      ++j;
    return text_.substr(i, j - i);
  }

  // A finite number: a TOML float or integer as exact decimal text, or a constant formula written
  // as a string ("6*pi/0.00113"), evaluated in the run's precision (formula_constant).
  decimal number(const toml::node& node, std::string_view field) const {
    if (auto i = node.as_integer()) return decimal_from_integer(i->get());
    if (node.is_string()) return formula_constant(node, field);
    auto f = node.as_floating_point();
    if (!f) fail_value(node, field, "must be a number or a constant formula (a string)");
    const double v = f->get();
    if (!std::isfinite(v)) fail_value(node, field, "must be finite");
    // Prefer the source token; if it cannot be found or does not denote this double (which
    // would mean the position mapping went wrong), fall back to the shortest round-trip text,
    // which is what the user typed whenever that had at most 15 significant digits.
    const auto parsed = parse_decimal(token_at(node), /*allow_underscores=*/true);
    if (parsed.number && parsed.number->value == v) return *parsed.number;
    return decimal_from_double(v);
  }

  decimal positive_number(const toml::node& node, std::string_view field) const {
    decimal d = number(node, field);
    if (!(d.value > 0)) fail_value(node, field, "must be positive");
    return d;
  }

  decimal3 number3(const toml::node& node, std::string_view field) const {
    auto a = node.as_array();
    if (!a || a->size() != 3) fail_value(node, field, "must be an array of 3 numbers");
    return {number((*a)[0], field), number((*a)[1], field), number((*a)[2], field)};
  }

  std::int64_t integer(const toml::node& node, std::string_view field) const {
    auto i = node.as_integer();
    if (!i) fail_value(node, field, "must be an integer");
    return i->get();
  }

  std::string string(const toml::node& node, std::string_view field) const {
    auto s = node.as_string();
    if (!s) fail_value(node, field, "must be a string");
    return s->get();
  }

  // A list of names drawn from `allowed`, without repeats.
  template <std::size_t N>
  std::vector<std::string> name_list(const toml::node& node, std::string_view field,
                                     const std::array<std::string_view, N>& allowed) const {
    auto a = node.as_array();
    if (!a) fail_value(node, field, "must be an array of strings");
    if (a->empty()) fail_value(node, field, "must not be empty");
    std::vector<std::string> names;
    for (const auto& item : *a) {
      std::string name = string(item, field);
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
        fail_value(item, field, fmt::format("unknown name (expected one of: {})", fmt::join(allowed, ", ")));
      if (std::find(names.begin(), names.end(), name) != names.end())
        fail_value(item, field, "listed twice");
      names.push_back(std::move(name));
    }
    return names;
  }

  // ---- structure ---------------------------------------------------------------------------
  // Rejects keys other than `allowed` in `table`: a misspelt key must not be silently ignored.
  void only_keys(const toml::table& table, std::string_view table_name,
                 std::initializer_list<std::string_view> allowed) const {
    for (const auto& [key, node] : table) {
      if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
      const std::string where_text = table_name.empty() ? "at top level" : fmt::format("in {}", table_name);
      const auto& at = key.source().begin;
      const std::string key_where = at.line ? fmt::format(":{}:{}", at.line, at.column) : where(node);
      throw input_error(fmt::format("scene {}{}: unknown key `{}` {} (expected one of: {})", origin_,
                                    key_where, shorten(std::string(key.str())), where_text,
                                    fmt::join(allowed, ", ")));
    }
  }

  // An optional sub-table; a key holding anything but a table is a type error.
  const toml::table* table(const toml::table& root, std::string_view key) const {
    const toml::node* node = root.get(key);
    if (!node) return nullptr;
    auto t = node->as_table();
    if (!t) fail_value(*node, fmt::format("[{}]", key), "must be a table");
    return t;
  }

  void read_body(const toml::table& root, scene& s) const;
  void read_equations(const toml::table& root, scene& s) const;
  void read_torque(const toml::table& root, scene& s) const;
  void read_gravity_gradient(const toml::table& gravity, scene& s) const;
  void read_initial(const toml::table& root, scene& s) const;
  void read_span(const toml::table& root, scene& s) const;
  void read_attitude(const toml::table& initial, scene& s) const;
  // N numbers, each of which may also be a constant formula ("2/3", "cos(1.1)"), evaluated in
  // the run's precision (scene_torque.cpp; N = 3 or 4). A formula's message names the component
  // (field1..3, or field0..3 for a quaternion).
  template <std::size_t N>
  std::array<decimal, N> constants(const toml::node& node, std::string_view field) const {
    std::array<decimal, N> out;
    constants_into(node, field, out.data(), N);
    return out;
  }
  void constants_into(const toml::node& node, std::string_view field, decimal* out, std::size_t n) const;
  // A constant formula (a TOML string: numbers, pi, + - * / ^ and functions), finite.
  decimal formula_constant(const toml::node& node, std::string_view field) const;
  // [torque]'s parts (scene_torque.cpp).
  expression torque_term(const toml::node& node, const std::string& field, const scene& s,
                         std::optional<decimal>& numeric) const;
  std::array<expression, 3> torque_terms(const toml::node& node, const std::string& key, const scene& s,
                                         std::optional<decimal3>& numbers) const;
  expression piece_bound(const toml::table& piece, std::string_view key, const std::string& where, const scene& s,
                         double& value) const;
  std::vector<torque_piece> read_pieces(const toml::node& node, const scene& s) const;
  void read_run(const toml::table& root, scene& s) const;
  void read_reference(const toml::table& root, scene& s) const;

  std::string_view text_;
  std::string origin_;
  bool attitude_given_ = false;  // [initial] q is in the scene: formulas may name q0..q3
  std::vector<std::size_t> line_starts_;
};

}  // namespace eulervop::scene::detail
