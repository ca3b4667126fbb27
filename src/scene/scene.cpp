#include <eulervop/scene/scene.hpp>

#include "scene_reader.hpp"

#include <default_scene.hpp>

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace eulervop::scene {

scene::scene() = default;
scene::scene(const scene&) = default;
scene::scene(scene&&) noexcept = default;
scene& scene::operator=(const scene&) = default;
scene& scene::operator=(scene&&) noexcept = default;
scene::~scene() = default;

namespace detail {

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
  only_keys(root, "", {"name", "description", "body", "equations", "torque", "initial", "span", "run", "reference"});

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
  read_equations(root, s);
  if (const toml::node* initial = root.get("initial"))
    attitude_given_ = initial->is_table() && initial->as_table()->contains("q");
  read_torque(root, s);
  read_initial(root, s);
  read_span(root, s);
  read_run(root, s);
  read_reference(root, s);
  return s;
}

// [body] inertia = [I1, I2, I3]: positive, in any order (the axes are mapped onto the principal
// order, principal_axes.hpp), equal or not (equal and nearly equal moments are integrated in the
// direct form, scene_problem.hpp). Moments whose two smaller sum to less than the largest belong
// to no rigid body, but Euler's equations are well defined for them (published test problems use
// such moments): they are integrated, with a note.
void scene_reader::read_body(const toml::table& root, scene& s) const {
  const toml::table* body = table(root, "body");
  if (!body) return;
  only_keys(*body, "[body]", {"inertia"});
  const toml::node* inertia = body->get("inertia");
  if (!inertia) fail_at(*body, "[body]: required field `inertia` is missing");
  decimal3 I = constants<3>(*inertia, "[body] inertia");
  for (int i = 0; i < 3; ++i)
    if (!(I[i].value > 0)) fail_value(*inertia, "[body] inertia", fmt::format("I{} must be positive", i + 1));
  std::array<double, 3> sorted = {I[0].value, I[1].value, I[2].value};
  std::sort(sorted.begin(), sorted.end());
  if (sorted[0] + sorted[1] < sorted[2])
    s.notes.push_back(fmt::format("[body] inertia = [{}, {}, {}]: no rigid body has these moments (the two smaller sum "
                                  "to less than the largest); Euler's equations are integrated all the same",
                                  I[0].text, I[1].text, I[2].text));
  s.units = scene_units::physical;
  s.inertia = I;
}

void scene_reader::read_initial(const toml::table& root, scene& s) const {
  const toml::table* initial = table(root, "initial");
  if (!initial) fail("required table [initial] is missing");
  only_keys(*initial, "[initial]", {"Omega", "c1", "c2", "u", "omega", "y", "q"});
  read_attitude(*initial, s);
  const toml::node* Omega = initial->get("Omega");
  const toml::node* omega = initial->get("omega");
  const toml::node* y = initial->get("y");
  const toml::node* c1 = initial->get("c1");
  const toml::node* c2 = initial->get("c2");
  const toml::node* u = initial->get("u");
  const bool any_elements = c1 || c2 || u;

  if (s.is_coefficient_form()) {
    if (Omega || omega || any_elements)
      fail_at(Omega ? *Omega : omega ? *omega : c1 ? *c1 : c2 ? *c2 : *u,
              "[initial]: a scene in the coefficient form ([equations]) gives its state as y = [y1, y2, y3]");
    if (!y) fail_at(*initial, "[initial]: required field `y` is missing (coefficient form)");
    s.initial = initial_rates{constants<3>(*y, "[initial] y")};
    return;
  }
  if (y) fail_at(*y, "[initial] y: the state y belongs to the coefficient form, which needs [equations] a");
  if (s.is_physical()) {
    if (Omega) fail_at(*Omega, "[initial] Omega: a physical scene (one with [body]) gives omega in rad/s");
    if (any_elements)
      fail_at(c1 ? *c1 : c2 ? *c2 : *u, "[initial] c1, c2, u: a physical scene gives omega in rad/s");
    if (!omega) fail_at(*initial, "[initial]: required field `omega` is missing (physical scene)");
    s.initial = initial_rates{constants<3>(*omega, "[initial] omega")};
    return;
  }
  if (omega) fail_at(*omega, "[initial] omega: physical rates need [body] inertia (or give the normalized Omega)");
  if (Omega && any_elements) fail_at(*Omega, "[initial]: give either Omega or c1, c2, u, not both");
  if (Omega) {
    s.initial = initial_rates{constants<3>(*Omega, "[initial] Omega")};
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

// [initial] q = [q0, q1, q2, q3]: the attitude, a Hamilton quaternion, scalar first, mapping the
// body's axes (as the scene lists them) to inertial ones (docs/attitude.md). Only a body has an
// attitude. Its norm must be 1 to 1e-6 (a quaternion rounded to six digits passes); it is
// normalized in the run's precision, with a note when the norm is visibly off 1.
void scene_reader::read_attitude(const toml::table& initial, scene& s) const {
  const toml::node* q = initial.get("q");
  if (!q) return;
  if (!s.is_physical())
    fail_at(*q, fmt::format("[initial] q: an attitude needs a body ([body] inertia); {} has none",
                            s.is_coefficient_form() ? "a scene in the coefficient form" : "a normalized scene"));
  const std::array<decimal, 4> v = constants<4>(*q, "[initial] q");
  double n2 = 0;
  for (const decimal& d : v) n2 += d.value * d.value;
  const double norm = std::sqrt(n2);
  if (!(std::abs(norm - 1) <= 1e-6))
    fail_value(*q, "[initial] q", fmt::format("its norm is {:.17g}, not 1 (to 1e-6)", norm));
  if (std::abs(norm - 1) > 1e-12)
    s.notes.push_back(fmt::format("[initial] q: its norm is {:.10g}; it is divided by it (in the run's precision)", norm));
  s.attitude = v;
}

void scene_reader::read_span(const toml::table& root, scene& s) const {
  const toml::table* span = table(root, "span");
  if (!span) fail("required table [span] is missing");
  only_keys(*span, "[span]", {"tau_end", "t_end", "samples", "times"});
  const toml::node* tau_end = span->get("tau_end");
  const toml::node* t_end = span->get("t_end");
  if (s.is_physical() && tau_end)
    fail_at(*tau_end, "[span] tau_end: a physical scene (one with [body]) gives t_end in s");
  if (s.is_coefficient_form() && tau_end)
    fail_at(*tau_end, "[span] tau_end: a scene in the coefficient form ([equations]) gives t_end");
  if (s.units == scene_units::normalized && t_end)
    fail_at(*t_end, "[span] t_end: physical time needs [body] inertia (or give the normalized tau_end)");
  const toml::node* end = s.units == scene_units::normalized ? tau_end : t_end;
  const std::string end_field = fmt::format("[span] {}", s.span_key());
  if (!end) fail_at(*span, fmt::format("[span]: required field `{}` is missing", s.span_key()));
  s.span_end = positive_number(*end, end_field);

  const toml::node* samples = span->get("samples");
  const toml::node* times = span->get("times");
  if (samples && times) fail_at(*times, "[span]: give samples or times, not both");
  // Neither: the command line may complete the scene (--samples, --times); sample_times_of
  // refuses a scene that is still without them.
  if (!samples && !times) return;
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
    if (auto text = step->as_string(); text && text->get().starts_with("K")) {
      // "K/N": a whole number N >= 1 of steps per quarter period K. Any other string is a
      // constant formula of the step itself ("0.01*pi").
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

}  // namespace detail

scene parse_scene(std::string_view toml_text, std::string origin) {
  return detail::scene_reader(toml_text, std::move(origin)).read();
}

std::map<std::string, std::filesystem::path> shipped_scenes() {
  namespace fs = std::filesystem;
  std::map<std::string, fs::path> out;
  for (const char* root : {EULERVOP_SOURCE_SCENES_DIR, EULERVOP_INSTALLED_SCENES_DIR}) {
    std::error_code ec;
    if (!fs::is_directory(root, ec)) continue;
    for (fs::recursive_directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec))
      if (it->path().extension() == ".toml") out.emplace(it->path().stem().string(), it->path());
    if (!out.empty()) break;  // the source tree's, else the installed ones
  }
  return out;
}

namespace {
// A path that names no file: a shipped scene's name, or an input_error that says what exists.
std::filesystem::path shipped_or_missing(const std::filesystem::path& path) {
  const std::map<std::string, std::filesystem::path> shipped = shipped_scenes();
  const bool bare = !path.has_parent_path() && !path.has_extension();
  if (bare) {
    if (const auto it = shipped.find(path.string()); it != shipped.end()) return it->second;
  }
  std::string names;
  for (const auto& [name, file] : shipped) names += (names.empty() ? "" : ", ") + name;
  throw input_error(fmt::format("scene {}: cannot read: no such file{}", path.string(),
                                bare && !names.empty() ? fmt::format(", nor a shipped scene ({})", names) : ""));
}
}  // namespace

scene load_scene_file(const std::filesystem::path& given) {
  std::error_code ec;
  const std::filesystem::path path = std::filesystem::exists(given, ec) ? given : shipped_or_missing(given);
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
