// check() and CheckResult: another tool's trajectory, as NumPy arrays or a CSV file, judged as
// `eulervop check` judges it, its float64 numbers at their exact binary values.
#include "module.hpp"

#include "commands/check/against_file.hpp"
#include "commands/check/against_scene.hpp"
#include "commands/check/check_job.hpp"
#include "commands/check/check_output.hpp"
#include "compute/scene_time.hpp"
#include "io/array_rows.hpp"
#include "io/csv_rows.hpp"
#include "messages.hpp"
#include "reference_object.hpp"

#include <pybind11/stl.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

namespace eulervop::python {

namespace {

struct py_check_result {
  py::dict as_dict;
  int exit_code = 0;
};

// What a check compares against: the form of its scene, whether it has an attitude, and how a
// message names it.
struct against_info {
  std::string form = "normalized";
  bool attitude = false;
  std::string name;
};

// The form of a reference's scene, from its columns: tau first (normalized), t and y1
// (coefficient), else t and omega (physical).
against_info against_of_header(const std::vector<std::string>& header, std::string name) {
  against_info a;
  a.name = std::move(name);
  if (!header.empty() && header[0] == "tau") a.form = "normalized";
  else a.form = header.size() > 1 && header[1] == "y1" ? "coefficient" : "physical";
  a.attitude = std::find(header.begin(), header.end(), "q0") != header.end();
  return a;
}

std::string state_names(const std::string& form) {
  return form == "normalized" ? "Omega1..3" : form == "physical" ? "omega1..3" : "y1..3";
}

// The trajectory's default column names: those of the scene's form, q0..q3 after the rates when
// y has seven columns.
std::vector<std::string> default_columns(const std::string& form, std::size_t width) {
  std::vector<std::string> c = form == "normalized"  ? std::vector<std::string>{"tau", "Omega1", "Omega2", "Omega3"}
                               : form == "physical" ? std::vector<std::string>{"t", "omega1", "omega2", "omega3"}
                                                    : std::vector<std::string>{"t", "y1", "y2", "y3"};
  if (width == 7) c.insert(c.end(), {"q0", "q1", "q2", "q3"});
  return c;
}

std::string names_repr(const std::vector<std::string>& names) { return py_repr(py::cast(names)); }

// Where q0..q3 of `names` sit in y (names[0] is the time's): "y[:, 3:7]".
std::string place_in_y(const std::vector<std::string>& names) {
  std::vector<std::size_t> at;
  for (const char* q : {"q0", "q1", "q2", "q3"}) {
    const auto it = std::find(names.begin(), names.end(), q);
    if (it != names.end() && it != names.begin()) at.push_back(static_cast<std::size_t>(it - names.begin()) - 1);
  }
  if (at.empty()) return "y";
  bool consecutive = true;
  for (std::size_t k = 1; k < at.size(); ++k) consecutive = consecutive && at[k] == at[k - 1] + 1;
  if (consecutive) return fmt::format("y[:, {}:{}]", at.front(), at.back() + 1);
  return fmt::format("y[:, [{}]]", fmt::join(at, ", "));
}

// The arrays t and y, of numbers and of the right shapes.
struct trajectory_arrays {
  float64_array t, y;
  std::vector<std::string> names;
};

void check_names(const std::vector<std::string>& names, std::size_t width, const float64_array& y) {
  if (names.size() != width + 1)
    throw py::value_error(fmt::format("columns has {} names; expected {}: the time's, then one for each column of y "
                                      "(y has shape {})",
                                      names.size(), width + 1, shape_text(y)));
  for (std::size_t c = 0; c < names.size(); ++c) {
    const std::string& name = names[c];
    if (name.empty() || name.find_first_of(",\"\r\n") != std::string::npos || name.front() == '#' ||
        app::trimmed(name) != name)
      throw py::value_error(fmt::format("columns[{}] = {}: not a column name (empty, with a comma, a quote, a line "
                                        "break, blanks around it or a leading '#')",
                                        c, py_repr(py::str(name))));
    if (std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(c), name) !=
        names.begin() + static_cast<std::ptrdiff_t>(c))
      throw py::value_error(fmt::format("columns[{}] = {}: listed twice", c, py_repr(py::str(name))));
  }
}

// Every row checked as the library would, with messages that name t[i] and y[i, k].
void check_rows(const trajectory_arrays& a) {
  const auto tv = a.t.unchecked<1>();
  const auto yv = a.y.unchecked<2>();
  const py::ssize_t n = a.t.shape(0), m = a.y.shape(1);
  for (py::ssize_t i = 0; i < n; ++i) {
    if (!std::isfinite(tv(i))) throw py::value_error(fmt::format("t[{}] = {} is not finite", i, py_repr(tv(i))));
    if (tv(i) < 0)
      throw py::value_error(fmt::format("t[{}] = {} is negative (the reference starts at 0)", i, py_repr(tv(i))));
    if (i > 0 && !(tv(i) > tv(i - 1)))
      throw py::value_error(fmt::format("t[{}] = {} does not increase (t[{}] = {}): the times must increase strictly", i,
                                        py_repr(tv(i)), i - 1, py_repr(tv(i - 1))));
    for (py::ssize_t k = 0; k < m; ++k)
      if (!std::isfinite(yv(i, k)))
        throw py::value_error(fmt::format("y[{}, {}] = {} is not finite", i, k, py_repr(yv(i, k))));
  }
  std::vector<py::ssize_t> q;
  for (const char* name : {"q0", "q1", "q2", "q3"}) {
    const auto it = std::find(a.names.begin() + 1, a.names.end(), name);
    if (it != a.names.end()) q.push_back(static_cast<py::ssize_t>(it - a.names.begin()) - 1);
  }
  if (q.size() == 4)
    for (py::ssize_t i = 0; i < n; ++i)
      if (yv(i, q[0]) == 0 && yv(i, q[1]) == 0 && yv(i, q[2]) == 0 && yv(i, q[3]) == 0)
        throw py::value_error(fmt::format("y[{}] has q0..q3 = 0 ({}), which is no attitude", i, place_in_y(a.names)));
}

trajectory_arrays arrays_of(const py::object& t_obj, const py::object& y_obj,
                            const std::optional<std::vector<std::string>>& columns, const against_info& against) {
  if (y_obj.is_none())
    throw py::value_error("y: missing; give y, shape (n, m), one row per time in t (or t the path of a trajectory CSV)");
  trajectory_arrays a;
  a.t = float64_array::ensure(t_obj);
  if (!a.t) throw py::value_error(fmt::format("t: expected an array of numbers, got {}", short_repr(t_obj)));
  a.y = float64_array::ensure(y_obj);
  if (!a.y) throw py::value_error(fmt::format("y: expected an array of numbers, got {}", short_repr(y_obj)));
  if (a.t.ndim() != 1)
    throw py::value_error(fmt::format("t has shape {}; expected (n,), one time per row of y", shape_text(a.t)));
  const py::ssize_t n = a.t.shape(0);
  if (n == 0) throw py::value_error("t has shape (0,): give at least one time");
  if (a.y.ndim() != 2 || a.y.shape(0) != n)
    throw py::value_error(fmt::format("y has shape {}; expected ({}, m) with one row per time in t{}", shape_text(a.y), n,
                                      a.y.ndim() == 2 && a.y.shape(1) == n ? " (transpose it?)" : ""));
  const auto width = static_cast<std::size_t>(a.y.shape(1));
  if (columns) {
    a.names = *columns;
    check_names(a.names, width, a.y);
  } else {
    if (width != 3 && width != 7) {
      const std::string state = state_names(against.form);
      throw py::value_error(fmt::format(
          "y has shape {}; expected ({}, 3), the rates {}{}, for {} ({} form); or name y's columns with columns=",
          shape_text(a.y), n, state, against.attitude ? fmt::format(", or ({}, 7), {} then q0..q3", n, state) : "",
          against.name, against.form));
    }
    a.names = default_columns(against.form, width);
  }
  check_rows(a);
  return a;
}

// The job's trajectory: the arrays, read in place (the job keeps them alive).
void use_arrays(app::check_job& job, const trajectory_arrays& a, const std::optional<std::vector<std::string>>& columns,
                const against_info& against, python_terms& terms) {
  job.open_trajectory = [a] {
    return std::make_unique<app::array_rows>(a.names, a.t.data(), a.y.data(), static_cast<std::size_t>(a.t.shape(0)),
                                             "trajectory " + std::string(arrays_name));
  };
  job.trajectory_name = "t and y";
  terms.arrays = true;
  terms.header = columns ? "columns=" + names_repr(a.names)
                         : fmt::format("t and y (read as columns {})", fmt::join(a.names, ", "));
  terms.y_named = columns ? "y (columns=" + names_repr(a.names) + ")" : fmt::format("y (shape {})", shape_text(a.y));
  terms.q_place = place_in_y(a.names);
  terms.names_wanted = fmt::format("{}{} for {}", fmt::join(default_columns(against.form, 3), ", "),
                                   against.attitude ? ", then q0..q3" : "", against.name);
  terms.times = a.t.data();
  terms.rows = static_cast<std::size_t>(a.t.shape(0));
}

// The reference a check is against: a Reference, a reference CSV, or a scene (object, path, name).
against_info set_against(app::check_job& job, const py::object& against, const std::optional<std::string>& precision) {
  if (py::isinstance<py_reference>(against)) {
    if (precision)
      throw app::input_error(fmt::format("--precision {}: not used with a reference file (its own precision is used)",
                                         *precision));
    const py_reference& r = against.cast<const py_reference&>();
    job.held = r.held;
    job.reference_path = "the Reference";
    return against_of_header(r.all_columns, "the Reference");
  }
  const std::optional<std::string> path = path_of(against);
  if (path && !app::names_scene(*path)) {  // a reference file: its header says the form
    if (precision)
      throw app::input_error(fmt::format("--precision {}: not used with a reference file (its own precision is used)",
                                         *precision));
    job.reference_path = *path;
    std::ifstream in = app::open_input_file("reference", *path);
    return against_of_header(app::csv_rows(in, "reference " + *path).header(), "reference " + *path);
  }
  const py_scene s = scene_of(against);
  app::check_against(job, s.parsed, precision);
  job.reference_path = s.path.value_or(s.parsed.origin);
  return {s.form(), s.parsed.has_attitude(), "scene " + s.parsed.name};
}

py_check_result check(const py::object& against, const py::object& t, const py::object& y,
                      const std::optional<std::vector<std::string>>& columns, const std::optional<double>& tol,
                      const std::optional<double>& rel_tol, const std::optional<double>& attitude_tol,
                      bool ignore_attitude, const std::optional<std::string>& precision,
                      const std::optional<double>& scd_atol, const std::optional<double>& scd_rtol) {
  const auto text = [](const std::optional<double>& x) {
    return x ? std::optional<std::string>(fmt::format("{}", *x)) : std::nullopt;
  };
  app::check_options o;
  o.tol = text(tol);
  o.rel_tol = text(rel_tol);
  o.attitude_tol = text(attitude_tol);
  o.ignore_attitude = ignore_attitude;
  o.scd_atol = text(scd_atol);
  o.scd_rtol = text(scd_rtol);
  o.format = "json";
  python_terms terms;
  terms.keywords = {number_keyword("--tol", "tol", tol),
                    number_keyword("--rel-tol", "rel_tol", rel_tol),
                    number_keyword("--attitude-tol", "attitude_tol", attitude_tol),
                    switch_keyword("--ignore-attitude", "ignore_attitude"),
                    text_keyword("--precision", "precision", precision),
                    number_keyword("--scd-atol", "scd_atol", scd_atol),
                    number_keyword("--scd-rtol", "scd_rtol", scd_rtol),
                    plain_keyword("--columns", "columns")};
  app::check_job job;
  const against_info a = in_python_terms(terms, [&] {
    app::apply_check_flags(job, o);
    return set_against(job, against, precision);
  });
  const std::optional<std::string> trajectory_path = path_of(t);
  trajectory_arrays arrays;
  if (trajectory_path && y.is_none()) {  // a trajectory file, read as the CLI reads it
    const std::string p = *trajectory_path;
    in_python_terms(terms, [&] { return app::open_input_file("trajectory", p); });
    job.open_trajectory = [p] { return std::make_unique<app::csv_file_rows>("trajectory", p); };
    job.trajectory_name = p;
  } else {
    arrays = arrays_of(t, y, columns, a);
    use_arrays(job, arrays, columns, a, terms);
  }
  std::ostringstream out;
  py_check_result r;
  r.exit_code = run_in_python_terms(terms, [&] {
    const app::check_result result = job.from_scene
                                         ? app::in_scene_time(job.scn, [&] { return app::check_against_scene(job); })
                                         : app::check_against_file(job);
    return app::print_check(job, result, out);
  });
  r.as_dict = py::module_::import("json").attr("loads")(out.str());
  return r;
}

// The dictionary's "pass": True, False or None (no bar given).
py::object verdict_of(const py_check_result& r) { return r.as_dict["pass"]; }

bool truth_of(const py_check_result& r) {
  const py::object v = verdict_of(r);
  if (v.is_none())
    throw py::value_error("a check without a bar has no verdict: give tol= or rel_tol=, or read max_error");
  return v.ptr() == Py_True;
}

}  // namespace

void bind_check(py::module_& m) {
  py::class_<py_check_result>(m, "CheckResult", "The verdict and the figures of `check`.")
      .def_property_readonly("passed", &verdict_of,
                             "True when every row is within the bars given, False when one is not; None when no bar "
                             "was given (tol=, rel_tol=): then there is no verdict.")
      .def_property_readonly("verdict", &verdict_of, "The same as passed: True, False, or None without a bar.")
      .def_property_readonly("max_error", [](const py_check_result& r) { return py::object(r.as_dict["max_error"]); },
                             "The largest error (rad/s for a physical trajectory in t, omega1..3).")
      .def_readonly("exit_code", &py_check_result::exit_code,
                    "The CLI's exit code: 0 within the bars or without any, 1 outside.")
      .def("as_dict", [](const py_check_result& r) { return py::module_::import("copy").attr("deepcopy")(r.as_dict); },
           "Every key and value of `eulervop check --format json` on the same inputs.")
      .def("__bool__", &truth_of, "The verdict; ValueError when no bar was given (there is none).")
      .def("__repr__", [](const py_check_result& r) {
        return fmt::format("<eulervop.CheckResult pass={} max_error={}>", py::str(verdict_of(r)).cast<std::string>(),
                           py::str(py::object(r.as_dict["max_error"])).cast<std::string>());
      });

  m.def("_check", &check, py::arg("against"), py::arg("t"), py::arg("y") = py::none(), py::arg("columns") = py::none(),
        py::arg("tol") = py::none(), py::arg("rel_tol") = py::none(), py::arg("attitude_tol") = py::none(),
        py::arg("ignore_attitude") = false, py::arg("precision") = py::none(), py::arg("scd_atol") = py::none(),
        py::arg("scd_rtol") = py::none());
  def_checked(m, "check",
              {{"against", takes::anything, "a Scene, a Reference, a path or a shipped scene's name", true},
               {"t", takes::anything, "an array of times, or a trajectory CSV's path", true},
               {"y", takes::anything, "an array (n, m) or None"},
               {"columns", takes::texts, "a list of column names or None"},
               {"tol", takes::number, "a float or None"},
               {"rel_tol", takes::number, "a float or None"},
               {"attitude_tol", takes::number, "a float (radians) or None"},
               {"ignore_attitude", takes::boolean, "True or False"},
               {"precision", takes::text, "'double', 'quad' or 'mpfr:BITS'"},
               {"scd_atol", takes::number, "a float or None"},
               {"scd_rtol", takes::number, "a float or None"}},
              "check(against, t, y=None, columns=None, tol=None, rel_tol=None, attitude_tol=None, "
              "ignore_attitude=False, precision=None, scd_atol=None, scd_rtol=None) -> CheckResult\n\n"
              "Another tool's trajectory against the reference, as `eulervop check` judges it (docs/check.md). "
              "`against`: a Scene, a Reference, a scene file's path, a shipped scene's name, or a reference CSV's "
              "path. `t` (n,) and `y` (n, m) arrays, with `columns` naming the time and y's columns (default: the "
              "scene's form, q0..q3 added when y has 7 columns); or `t` a trajectory CSV's path and y None. Each float64 "
              "is judged at its exact binary value: against a scene, the reference is evaluated at that very time; "
              "against a Reference, a time must be one of ref.t exactly. `tol` is in the trajectory's units (rad/s for "
              "t, omega1..3); with q0..q3 give `attitude_tol` (rad) or ignore_attitude=True. Without a bar there is no "
              "verdict (passed is None). Raises ValueError for bad input (naming the keywords, and t and y by shape "
              "and index), NumericalFailure, KeyboardInterrupt.");
}

}  // namespace eulervop::python
