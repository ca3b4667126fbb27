#include <eulervop/scene/scene.hpp>

#include <default_scene.hpp>

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>

namespace eulervop::scene {

namespace {

// Longest value text quoted in a message before it is shortened.
constexpr std::size_t max_quoted_chars = 60;

std::string shorten(std::string text) {
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
      out << toml::toml_formatter(*a);
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

  // A finite number (TOML float or integer) as exact decimal text.
  decimal number(const toml::node& node, std::string_view field) const {
    if (auto i = node.as_integer()) return decimal_from_integer(i->get());
    auto f = node.as_floating_point();
    if (!f) fail_value(node, field, "must be a number");
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
  void read_torque(const toml::table& root, scene& s) const;
  void read_initial(const toml::table& root, scene& s) const;
  void read_span(const toml::table& root, scene& s) const;
  void read_run(const toml::table& root, scene& s) const;
  void read_reference(const toml::table& root, scene& s) const;

  std::string_view text_;
  std::string origin_;
  std::vector<std::size_t> line_starts_;
};

scene scene_reader::read() {
  toml::table root;
  try {
    root = toml::parse(text_, origin_);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw input_error(fmt::format("scene {}:{}:{}: parse error: {}", origin_, b.line, b.column,
                                  e.description()));
  }
  if (root.empty()) fail("empty scene (required field `name` is missing)");
  only_keys(root, "", {"name", "description", "body", "torque", "initial", "span", "run", "reference"});

  scene s;
  s.origin = origin_;
  s.source_text = std::string(text_);

  const toml::node* name = root.get("name");
  if (!name) fail("required field `name` is missing");
  s.name = string(*name, "name");
  if (s.name.empty()) fail_value(*name, "name", "must not be empty");
  // The name is echoed on one metadata line of every output.
  if (s.name.find_first_of("\r\n") != std::string::npos) fail_value(*name, "name", "must be a single line");
  if (const toml::node* d = root.get("description")) s.description = string(*d, "description");

  read_body(root, s);
  read_torque(root, s);
  read_initial(root, s);
  read_span(root, s);
  read_run(root, s);
  read_reference(root, s);
  return s;
}

// [body] inertia = [I1, I2, I3]: positive, in any order (the axes are mapped onto the principal
// order, principal_axes.hpp), equal or not (equal and nearly equal moments are integrated in the
// direct form, scene_problem.hpp), and a rigid body's: the two smaller moments sum to at least
// the largest.
void scene_reader::read_body(const toml::table& root, scene& s) const {
  const toml::table* body = table(root, "body");
  if (!body) return;
  only_keys(*body, "[body]", {"inertia"});
  const toml::node* inertia = body->get("inertia");
  if (!inertia) fail_at(*body, "[body]: required field `inertia` is missing");
  decimal3 I = number3(*inertia, "[body] inertia");
  for (int i = 0; i < 3; ++i)
    if (!(I[i].value > 0)) fail_value(*inertia, "[body] inertia", fmt::format("I{} must be positive", i + 1));
  std::array<double, 3> sorted = {I[0].value, I[1].value, I[2].value};
  std::sort(sorted.begin(), sorted.end());
  if (sorted[0] + sorted[1] < sorted[2])
    fail_value(*inertia, "[body] inertia",
               "the two smaller moments sum to less than the largest, which no rigid body has");
  s.units = scene_units::physical;
  s.inertia = I;
}

void scene_reader::read_torque(const toml::table& root, scene& s) const {
  const toml::table* torque = table(root, "torque");
  if (!torque) return;  // torque-free
  only_keys(*torque, "[torque]", {"G", "M"});
  const toml::node* G = torque->get("G");
  const toml::node* M = torque->get("M");
  if (G && M) fail_at(*M, "[torque]: give G (normalized) or M (physical), not both");
  if (s.is_physical() && G)
    fail_at(*G, "[torque] G: a physical scene (one with [body]) takes its torque as M in N m");
  if (!s.is_physical() && M)
    fail_at(*M, "[torque] M: a physical torque needs [body] inertia (or give the normalized G)");
  if (!G && !M) fail_at(*torque, "[torque]: give G or M, or omit the table for a torque-free scene");
  s.torque = s.is_physical() ? number3(*M, "[torque] M") : number3(*G, "[torque] G");
}

void scene_reader::read_initial(const toml::table& root, scene& s) const {
  const toml::table* initial = table(root, "initial");
  if (!initial) fail("required table [initial] is missing");
  only_keys(*initial, "[initial]", {"Omega", "c1", "c2", "u", "omega"});
  const toml::node* Omega = initial->get("Omega");
  const toml::node* omega = initial->get("omega");
  const toml::node* c1 = initial->get("c1");
  const toml::node* c2 = initial->get("c2");
  const toml::node* u = initial->get("u");
  const bool any_elements = c1 || c2 || u;

  if (s.is_physical()) {
    if (Omega) fail_at(*Omega, "[initial] Omega: a physical scene (one with [body]) gives omega in rad/s");
    if (any_elements)
      fail_at(c1 ? *c1 : c2 ? *c2 : *u, "[initial] c1, c2, u: a physical scene gives omega in rad/s");
    if (!omega) fail_at(*initial, "[initial]: required field `omega` is missing (physical scene)");
    s.initial = initial_rates{number3(*omega, "[initial] omega")};
    return;
  }
  if (omega) fail_at(*omega, "[initial] omega: physical rates need [body] inertia (or give the normalized Omega)");
  if (Omega && any_elements) fail_at(*Omega, "[initial]: give either Omega or c1, c2, u, not both");
  if (Omega) {
    s.initial = initial_rates{number3(*Omega, "[initial] Omega")};
    return;
  }
  if (!any_elements) fail_at(*initial, "[initial]: give Omega = [...] or c1, c2, u");
  if (!c1) fail_at(*initial, "[initial]: required field `c1` is missing (c1, c2, u go together)");
  if (!c2) fail_at(*initial, "[initial]: required field `c2` is missing (c1, c2, u go together)");
  if (!u) fail_at(*initial, "[initial]: required field `u` is missing (c1, c2, u go together)");
  initial_elements e{number(*c1, "[initial] c1"), number(*c2, "[initial] c2"), number(*u, "[initial] u")};
  if (e.c1.value < 0) fail_value(*c1, "[initial] c1", "must be >= 0");
  if (!(e.c2.value > 0)) fail_value(*c2, "[initial] c2", "must be positive");
  // Eqs. 10-12 hold for k = c1/c2 < 1 only; k >= 1 scenes give Omega directly.
  if (!(e.c1.value < e.c2.value))
    fail_value(*c1, "[initial] c1",
               fmt::format("modulus k = c1/c2 must be < 1 (c2 = {}); give Omega directly for k >= 1", e.c2.text));
  s.initial = e;
}

void scene_reader::read_span(const toml::table& root, scene& s) const {
  const toml::table* span = table(root, "span");
  if (!span) fail("required table [span] is missing");
  only_keys(*span, "[span]", {"tau_end", "t_end", "samples", "times"});
  const toml::node* tau_end = span->get("tau_end");
  const toml::node* t_end = span->get("t_end");
  if (s.is_physical() && tau_end)
    fail_at(*tau_end, "[span] tau_end: a physical scene (one with [body]) gives t_end in s");
  if (!s.is_physical() && t_end)
    fail_at(*t_end, "[span] t_end: physical time needs [body] inertia (or give the normalized tau_end)");
  const toml::node* end = s.is_physical() ? t_end : tau_end;
  const std::string end_field = fmt::format("[span] {}", s.span_key());
  if (!end) fail_at(*span, fmt::format("[span]: required field `{}` is missing", s.span_key()));
  s.span_end = positive_number(*end, end_field);

  const toml::node* samples = span->get("samples");
  const toml::node* times = span->get("times");
  if (samples && times) fail_at(*times, "[span]: give samples or times, not both");
  if (!samples && !times) fail_at(*span, "[span]: give samples (a count) or times (a list)");
  if (samples) {
    const std::int64_t n = integer(*samples, "[span] samples");
    if (n < scene_limits::min_samples || n > scene_limits::max_samples)
      fail_value(*samples, "[span] samples", fmt::format("must be between {} and {}", scene_limits::min_samples, scene_limits::max_samples));
    s.samples = n;
    return;
  }
  auto list = times->as_array();
  if (!list) fail_value(*times, "[span] times", "must be an array of numbers");
  if (list->empty()) fail_value(*times, "[span] times", "must not be empty");
  for (const auto& item : *list) {
    decimal t = number(item, "[span] times");
    if (t.value < 0) fail_value(item, "[span] times", "must be >= 0");
    if (t.value > s.span_end.value)
      fail_value(item, "[span] times", fmt::format("beyond {} = {}", s.span_key(), s.span_end.text));
    if (!s.times.empty() && !(t.value > s.times.back().value))
      fail_value(item, "[span] times", fmt::format("must be strictly increasing (follows {})", s.times.back().text));
    s.times.push_back(std::move(t));
  }
}

void scene_reader::read_run(const toml::table& root, scene& s) const {
  const toml::table* run = table(root, "run");
  if (!run) return;
  only_keys(*run, "[run]", {"step", "methods", "formulations"});
  if (const toml::node* step = run->get("step")) {
    step_spec spec;
    if (auto text = step->as_string()) {
      // "K/N": a whole number N >= 1 of steps per quarter period K.
      const std::string& t = text->get();
      std::int64_t n = 0;
      const char* digits = t.data() + 2;
      auto [ptr, ec] = std::from_chars(digits, t.data() + t.size(), n);
      if (!t.starts_with("K/") || ec != std::errc{} || ptr != t.data() + t.size() || n < 1)
        fail_value(*step, "[run] step", "expected \"K/N\" with a whole number N >= 1, or a positive number");
      spec.K_divisor = n;
    } else {
      spec.value = positive_number(*step, "[run] step");
    }
    s.step = spec;
  }
  if (const toml::node* methods = run->get("methods")) s.methods = name_list(*methods, "[run] methods", known_methods);
  if (const toml::node* f = run->get("formulations"))
    s.formulations = name_list(*f, "[run] formulations", known_formulations);
}

void scene_reader::read_reference(const toml::table& root, scene& s) const {
  const toml::table* ref = table(root, "reference");
  if (!ref) return;
  only_keys(*ref, "[reference]", {"precision", "degree", "tolerance"});
  if (const toml::node* p = ref->get("precision")) {
    auto parsed = eulervop::precision::parse(string(*p, "[reference] precision"));
    if (!parsed)
      fail_value(*p, "[reference] precision",
                 fmt::format("expected \"double\", \"quad\" or \"mpfr:BITS\" with {} <= BITS <= {}",
                             eulervop::precision::min_mpfr_bits, eulervop::precision::max_mpfr_bits));
    s.reference_precision = *parsed;
  }
  if (const toml::node* d = ref->get("degree")) {
    const std::int64_t n = integer(*d, "[reference] degree");
    if (n < scene_limits::min_degree || n > scene_limits::max_degree)
      fail_value(*d, "[reference] degree", fmt::format("must be between {} and {}", scene_limits::min_degree, scene_limits::max_degree));
    s.degree = static_cast<unsigned>(n);
  }
  if (const toml::node* t = ref->get("tolerance")) {
    decimal tol = positive_number(*t, "[reference] tolerance");
    if (!(tol.value < 1)) fail_value(*t, "[reference] tolerance", "must be below 1 (it is relative)");
    s.tolerance = tol;
  }
}

}  // namespace

scene parse_scene(std::string_view toml_text, std::string origin) {
  return scene_reader(toml_text, std::move(origin)).read();
}

scene load_scene_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw input_error(fmt::format("scene {}: cannot read: is a directory", path.string()));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw input_error(fmt::format("scene {}: cannot read: {}", path.string(), std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw input_error(fmt::format("scene {}: cannot read: {}", path.string(), std::strerror(errno)));
  return parse_scene(text.str(), path.string());
}

scene load_default_scene() {
  return parse_scene(default_scene_toml, std::string(default_scene_origin));
}

}  // namespace eulervop::scene
