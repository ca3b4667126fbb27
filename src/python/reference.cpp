// reference() and Reference: a run held in memory (held_reference.hpp), its columns as NumPy
// arrays of binary64 numbers, and its decimal text only when asked for.
#include "module.hpp"

#include "commands/reference/held_reference.hpp"
#include "commands/reference/reference_job.hpp"
#include "io/csv_rows.hpp"
#include "messages.hpp"
#include "reference_object.hpp"

#include <pybind11/stl.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <memory>
#include <sstream>

namespace eulervop::python {

namespace {

// The '#' lines as a dict: "key: value" lines by key (scene_text joined, note a list).
py::dict metadata_of(const std::string& header) {
  py::dict meta;
  std::string scene_text;
  py::list notes;
  std::istringstream lines(header);
  for (std::string l; std::getline(lines, l);) {
    if (!l.starts_with("#")) continue;
    const std::string body = l.substr(l.size() > 1 && l[1] == ' ' ? 2 : 1);
    const std::size_t colon = body.find(':');
    if (colon == std::string::npos) {
      meta["version"] = body;  // "# eulervop 0.1.0"
      continue;
    }
    const std::string key = body.substr(0, colon);
    std::string value = body.substr(colon + 1);
    if (!value.empty() && value[0] == ' ') value.erase(0, 1);
    if (key == "scene_text") scene_text += value + "\n";
    else if (key == "note") notes.append(value);
    else meta[py::str(key)] = value;
  }
  if (!scene_text.empty()) meta["scene_text"] = scene_text;
  if (py::len(notes)) meta["note"] = notes;
  return meta;
}

py::array_t<double> column_array(const app::held_reference& r, std::size_t c) {
  py::array_t<double> a(static_cast<py::ssize_t>(r.size()));
  r.column_values(c, a.mutable_data(), 1);
  return a;
}

py::array_t<double> matrix_array(const app::held_reference& r, const std::vector<std::size_t>& cs) {
  py::array_t<double> a({static_cast<py::ssize_t>(r.size()), static_cast<py::ssize_t>(cs.size())});
  for (std::size_t k = 0; k < cs.size(); ++k) r.column_values(cs[k], a.mutable_data() + k, cs.size());
  return a;
}

}  // namespace

py_reference reference_of(std::shared_ptr<const app::held_reference> held) {
  const app::held_reference& h = *held;
  py_reference r;
  r.held = std::move(held);
  r.all_columns = h.columns();
  r.t = py::array_t<double>(static_cast<py::ssize_t>(h.size()), h.times().data());
  // y holds the columns `check` reads by default for the scene's form (t, omega1..3 and q0..q3;
  // tau, Omega1..3; t, y1..3), so that check(scene, ref.t, ref.y) judges the reference against
  // itself: a physical reference's second time and rates, tau and Omega1..3, go to `normalized`.
  const std::vector<std::string> normalized_names = {"tau", "Omega1", "Omega2", "Omega3"};
  const bool normalized_time = r.all_columns[0] == "tau";
  std::vector<std::size_t> state, normalized;
  for (std::size_t c = 0; c < r.all_columns.size(); ++c) {
    const std::string& name = r.all_columns[c];
    const bool is_normalized = std::find(normalized_names.begin(), normalized_names.end(), name) != normalized_names.end();
    if (is_normalized) normalized.push_back(c);
    if (c == 0 || name.starts_with("radius") || (!normalized_time && is_normalized)) continue;
    state.push_back(c);
    r.columns.push_back(name);
  }
  r.y = matrix_array(h, state);
  if (normalized.size() == normalized_names.size()) {
    r.normalized_columns = normalized_names;
    r.normalized = matrix_array(h, normalized);
  }
  const auto radius = [&](const char* name) -> std::optional<py::array_t<double>> {
    const auto it = std::find(r.all_columns.begin(), r.all_columns.end(), name);
    if (it == r.all_columns.end()) return std::nullopt;
    return column_array(h, static_cast<std::size_t>(it - r.all_columns.begin()));
  };
  r.radius = radius("radius");
  r.radius_omega = radius("radius_omega");
  r.radius_q = radius("radius_q");
  r.meta = metadata_of(app::reference_csv_header(h.metadata(), h.layout()));
  return r;
}

namespace {

std::vector<double> times_of(const py::object& times) {
  const auto a = float64_array::ensure(times);
  if (!a) throw py::value_error(fmt::format("times: expected numbers, got {}", short_repr(times)));
  if (a.ndim() != 1) throw py::value_error(fmt::format("times has shape {}; expected (k,), the sample times", shape_text(a)));
  if (a.shape(0) == 0) throw py::value_error("times has shape (0,): give at least one time");
  return {a.data(), a.data() + a.shape(0)};
}

py_reference reference(const py::object& scene, const py::object& times, const std::optional<std::string>& precision,
                       bool verify, bool certify, const std::optional<int>& samples, const std::optional<double>& t_end,
                       const std::optional<double>& tau_end) {
  const py_scene s = scene_of(scene);
  std::optional<std::vector<double>> binary;
  if (!times.is_none()) {
    if (samples) throw py::value_error("samples and times: give one or the other");
    binary = times_of(times);
  }
  app::reference_options o;
  if (samples) o.overrides.samples = std::to_string(*samples);
  if (t_end) o.overrides.t_end = fmt::format("{}", *t_end);
  if (tau_end) o.overrides.tau_end = fmt::format("{}", *tau_end);
  o.overrides.precision = precision;
  o.verify = verify;
  o.certify = certify;
  python_terms terms;
  keyword samples_keyword = plain_keyword("--samples", "samples");
  if (samples) samples_keyword.text = samples_keyword.shown = std::to_string(*samples);
  terms.keywords = {samples_keyword,
                    number_keyword("--t-end", "t_end", t_end),
                    number_keyword("--tau-end", "tau_end", tau_end),
                    text_keyword("--precision", "precision", precision),
                    switch_keyword("--verify", "verify"),
                    switch_keyword("--certify", "certify")};
  std::shared_ptr<app::held_reference> held = run_in_python_terms(terms, [&] {
    app::reference_job job = app::reference_job_of(s.parsed, o, binary.has_value());
    app::use_binary_times(job, std::move(binary));
    auto h = std::make_shared<app::held_reference>(job);
    h->finish(app::run_reference_job(job, *h));
    return h;
  });
  return reference_of(std::move(held));
}

// Every cell's text, row by row: made once, on the first call.
const py::object& decimal_of(const py_reference& r) {
  if (!r.decimal_cache) {
    py::list rows;
    for (std::size_t i = 0; i < r.held->size(); ++i) rows.append(py::cast(r.held->row_text(i)));
    r.decimal_cache = std::move(rows);
  }
  return *r.decimal_cache;
}

const py::object& csv_of(const py_reference& r) {
  if (!r.csv_cache) r.csv_cache = py::str(r.held->csv_text());
  return *r.csv_cache;
}

}  // namespace

namespace {

void bind_reference_class(py::module_& m) {
  py::class_<py_reference>(m, "Reference", "A reference solution held in memory: its columns as float64 arrays.")
      .def_readonly("t", &py_reference::t,
                    "float64 (n,): the sample times (t, or tau of a normalized scene), each exactly the binary64 "
                    "number the reference was computed at.")
      .def_readonly("y", &py_reference::y,
                    "float64 (n, m): the columns `check` reads by default, each value rounded to nearest: omega1..3 "
                    "(and q0..q3 with an attitude) for a physical scene, Omega1..3 for a normalized one, y1..3 for "
                    "the coefficient form; so check(scene, ref.t, ref.y) judges the reference against itself.")
      .def_readonly("columns", &py_reference::columns, "The names of y's columns.")
      .def_readonly("normalized", &py_reference::normalized,
                    "float64 (n, 4): the columns tau, Omega1..3, the normalized time and rates of Eqs. 2-4 (a physical "
                    "scene's reference carries them after its own; a normalized scene's are t and y); None when it "
                    "has none (the coefficient form, the direct form).")
      .def_readonly("normalized_columns", &py_reference::normalized_columns,
                    "The names of normalized's columns: ['tau', 'Omega1', 'Omega2', 'Omega3'], or [] when it is None.")
      .def_readonly("all_columns", &py_reference::all_columns, "Every column, in the order of the CSV's.")
      .def_property_readonly("decimal", &decimal_of,
                             "Every cell's text, row by row in all_columns' order, as `eulervop reference` prints "
                             "them: every digit of the precision (made on first use).")
      .def_readonly("meta", &py_reference::meta, "The '#' lines as a dict (scene_text joined, note a list).")
      .def_readonly("radius", &py_reference::radius,
                    "With certify=True, float64 (n,): for each row, a proven bound on the 2-norm of the distance of "
                    "the printed state (Omega, or y in the coefficient form) from the exact solution at that row's "
                    "time, in the state's units, rounded up to float64; else None (a body in the direct form has "
                    "radius_omega alone).")
      .def_readonly("radius_omega", &py_reference::radius_omega,
                    "With certify=True on a physical scene: the same bound for the printed omega1..3, in rad/s.")
      .def_readonly("radius_q", &py_reference::radius_q,
                    "With certify=True on a scene with an attitude: a bound on |q - q*|_2 of the printed quaternion "
                    "(no unit).")
      .def_property_readonly("csv", &csv_of, "The CSV `eulervop reference` would write for these rows (made on first use).")
      .def_property_readonly("scene", [](const py_reference& r) {
        return py_scene{r.held->source_scene(), std::nullopt};
      }, "The scene it was computed for (with the keywords' changes: span, samples).")
      .def("__len__", [](const py_reference& r) { return r.held->size(); })
      .def("__repr__", [](const py_reference& r) {
        return fmt::format("<eulervop.Reference {} rows: {}>", r.held->size(), fmt::join(r.all_columns, ","));
      });
}

}  // namespace

void bind_reference(py::module_& m) {
  bind_reference_class(m);
  m.def("_reference", &reference, py::arg("scene"), py::arg("times") = py::none(), py::arg("precision") = py::none(),
        py::arg("verify") = false, py::arg("certify") = false, py::arg("samples") = py::none(),
        py::arg("t_end") = py::none(), py::arg("tau_end") = py::none());
  def_checked(m, "reference",
              {{"scene", takes::anything, "a Scene, a scene file's path or a shipped scene's name", true},
               {"times", takes::anything, "an array of float64 or None"},
               {"precision", takes::text, "'double', 'quad' or 'mpfr:BITS'"},
               {"verify", takes::boolean, "True or False"},
               {"certify", takes::boolean, "True or False"},
               {"samples", takes::integer, "an int or None"},
               {"t_end", takes::number, "a float or None"},
               {"tau_end", takes::number, "a float or None"}},
              "reference(scene, times=None, precision=None, verify=False, certify=False, samples=None, t_end=None, "
              "tau_end=None) -> Reference\n\n"
              "The scene's reference solution. `scene`: a Scene, a scene file's path or a shipped scene's name. "
              "`times`: sample times in the scene's own time (t in s for a physical scene, tau for a normalized one), "
              "each taken at its exact binary value; without them the scene's samples (or `samples`, a count), each "
              "rounded to float64 first, so that ref.t holds the very times computed at. `t_end` (physical and "
              "coefficient forms) or `tau_end` (normalized) moves the end of the span. `precision`: 'double', 'quad' "
              "or 'mpfr:BITS'. `verify`: recompute one precision up and record meta['estimated_max_error']. "
              "`certify`: prove a radius per row. Raises ValueError for bad input, NumericalFailure when the "
              "integrator gives up, KeyboardInterrupt on Ctrl-C. The GIL is released while it runs.");
}

}  // namespace eulervop::python
