// The Python module `eulervop` (docs/python.md): the oracle one import away.
//
// Every call runs the program's own commands (`reference`, `check`) in this process, on the same
// code path as the command line, so a value here is the CLI's value cell for cell and a check's
// dictionary is `check --format json`. Arrays cross as NumPy float64; the decimal text of every
// cell is kept. The GIL is released while a command runs; Ctrl-C is noticed between segments of
// the integration (a few per second at the least) and raises KeyboardInterrupt. Bad input raises
// ValueError with the CLI's one-line message, a numerical failure eulervop.NumericalFailure (an
// ArithmeticError) with the time and the cause. Nothing is written but scratch files in a private
// temporary directory, removed before the call returns.
#include "commands/check/check_command.hpp"
#include "commands/reference/reference_command.hpp"
#include "compute/progress.hpp"
#include "compute/scene_library.hpp"
#include "io/csv_rows.hpp"

#include <eulervop/core/numerical_failure.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace py = pybind11;
namespace fs = std::filesystem;
namespace app = eulervop::app;

namespace {

// ---- errors, interruption, scratch files -----------------------------------------------------

// Thrown by the progress display when Ctrl-C was pressed; becomes KeyboardInterrupt.
struct interrupted {};

// The display the module installs for compute/'s progress: shows nothing, and every 100 ms takes
// the GIL to let Python see a pending signal.
class interrupt_check final : public app::progress_display {
 public:
  void update(double, std::size_t) override {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    bool signalled = false;
    {
      const py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) {
        PyErr_Clear();
        signalled = true;
      }
    }
    if (signalled) throw interrupted{};
  }
  void clear() override {}

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

// A private temporary directory, removed with everything in it.
class scratch_dir {
 public:
  scratch_dir() {
    std::string pattern = (fs::temp_directory_path() / "eulervop-py-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("eulervop: cannot create a temporary directory");
    path_ = pattern;
  }
  ~scratch_dir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  scratch_dir(const scratch_dir&) = delete;
  scratch_dir& operator=(const scratch_dir&) = delete;
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

// eulervop.NumericalFailure: created once and never freed (it lives as long as the interpreter).
PyObject* numerical_failure_type = nullptr;

// Runs a command with the GIL released. What it throws reaches Python through the module's
// exception translator (bad input, numerical failure, Ctrl-C), as does what the module throws.
template <class Run>
int run_released(Run&& run) {
  const py::gil_scoped_release nogil;
  return run();
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("eulervop: cannot write " + path.string());
}

// ---- Scene ------------------------------------------------------------------------------------

struct py_scene {
  app::scene parsed;
  std::optional<std::string> path;  // the file it was loaded from

  std::string form() const {
    if (parsed.is_coefficient_form()) return "coefficient";
    return parsed.is_physical() ? "physical" : "normalized";
  }
};

py_scene scene_load(const std::string& path) {
  return {eulervop::scene::load_scene_file(path), path};
}

py_scene scene_from_toml(const std::string& text) {
  return {eulervop::scene::parse_scene(text, "<from_toml>"), std::nullopt};
}

// The scene as a path the commands take: its own file, or its text written to `dir`.
std::string scene_path(const py_scene& s, const scratch_dir& dir) {
  if (s.path) return *s.path;
  const fs::path p = dir / (s.parsed.name + ".toml");
  write_text(p, s.parsed.source_text);
  return p.string();
}

// A scene argument: a Scene, or a path to one.
py_scene scene_of(const py::object& o) {
  if (py::isinstance<py_scene>(o)) return o.cast<py_scene>();
  if (py::isinstance<py::str>(o) || py::hasattr(o, "__fspath__"))
    return scene_load(py::str(py::module_::import("os").attr("fspath")(o)).cast<std::string>());
  throw py::type_error("expected an eulervop.Scene or a path to a scene file");
}

// ---- Reference --------------------------------------------------------------------------------

struct py_reference {
  std::string csv;                                  // the file `eulervop reference` writes
  std::vector<std::string> all_columns;             // every CSV column
  std::vector<std::vector<std::string>> decimal;    // every cell's text, row by row
  std::vector<std::string> columns;                 // the state columns of y
  py::array_t<double> t, y;
  std::optional<py::array_t<double>> radius, radius_omega, radius_q;
  py::dict meta;
};

// The '#' lines as a dict: "key: value" lines by key (scene_text joined, note a list).
py::dict metadata_of(const std::vector<std::string>& lines) {
  py::dict meta;
  std::string scene_text;
  py::list notes;
  for (const std::string& l : lines) {
    const std::string body = l.substr(l.size() > 1 && l[1] == ' ' ? 2 : 1);
    const std::size_t colon = body.find(':');
    if (colon == std::string::npos) {
      meta["version"] = body;  // "# eulervop 0.1.0"
      continue;
    }
    const std::string key = body.substr(0, colon);
    std::string value = body.substr(colon + 1);
    if (!value.empty() && value[0] == ' ') value.erase(0, 1);
    if (key == "scene_text")
      scene_text += value + "\n";
    else if (key == "note")
      notes.append(value);
    else
      meta[py::str(key)] = value;
  }
  if (!scene_text.empty()) meta["scene_text"] = scene_text;
  if (py::len(notes)) meta["note"] = notes;
  return meta;
}

py_reference reference_of_csv(std::string csv) {
  py_reference r;
  r.csv = std::move(csv);
  std::istringstream in(r.csv);
  app::csv_rows rows(in, "reference");  // the program's own reader of its files
  r.all_columns = rows.header();
  const std::vector<std::string>& comments = rows.comments();
  while (rows.next()) {
    std::vector<std::string> cells;
    for (std::size_t c = 0; c < r.all_columns.size(); ++c) cells.push_back(rows.cell(c));
    r.decimal.push_back(std::move(cells));
  }
  r.meta = metadata_of(comments);
  // The time is the first column; y holds the state columns after it, but tau (a second time)
  // and the radii.
  std::vector<std::size_t> state;
  std::optional<std::size_t> radius, radius_omega, radius_q;
  for (std::size_t c = 1; c < r.all_columns.size(); ++c) {
    const std::string& name = r.all_columns[c];
    if (name == "radius")
      radius = c;
    else if (name == "radius_omega")
      radius_omega = c;
    else if (name == "radius_q")
      radius_q = c;
    else if (name != "tau")
      state.push_back(c), r.columns.push_back(name);
  }
  const auto n = static_cast<py::ssize_t>(r.decimal.size());
  r.t = py::array_t<double>(n);
  r.y = py::array_t<double>({n, static_cast<py::ssize_t>(state.size())});
  auto t = r.t.mutable_unchecked<1>();
  auto y = r.y.mutable_unchecked<2>();
  const auto column = [&](std::size_t c) {
    py::array_t<double> a(n);
    auto v = a.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i) v(i) = std::strtod(r.decimal[static_cast<std::size_t>(i)][c].c_str(), nullptr);
    return a;
  };
  for (py::ssize_t i = 0; i < n; ++i) {
    const auto& row = r.decimal[static_cast<std::size_t>(i)];
    t(i) = std::strtod(row[0].c_str(), nullptr);
    for (std::size_t k = 0; k < state.size(); ++k)
      y(i, static_cast<py::ssize_t>(k)) = std::strtod(row[state[k]].c_str(), nullptr);
  }
  if (radius) r.radius = column(*radius);
  if (radius_omega) r.radius_omega = column(*radius_omega);
  if (radius_q) r.radius_q = column(*radius_q);
  return r;
}

// Sample times as `--times` takes them: each double's shortest round-trip text.
std::string times_text(const py::object& times) {
  std::string text;
  for (const double x : times.cast<std::vector<double>>()) text += (text.empty() ? "" : ",") + fmt::format("{}", x);
  if (text.empty()) throw py::value_error("times: empty");
  return text;
}

py_reference reference(const py::object& scene, const py::object& times, const std::optional<std::string>& precision,
                       bool verify, bool certify, const std::optional<int>& samples,
                       const std::optional<double>& t_end, const std::optional<double>& tau_end) {
  const py_scene s = scene_of(scene);
  scratch_dir dir;
  app::reference_options o;
  o.scene_path = scene_path(s, dir);
  if (!times.is_none()) o.overrides.times = times_text(times);
  if (samples) o.overrides.samples = std::to_string(*samples);
  if (t_end) o.overrides.t_end = fmt::format("{}", *t_end);
  if (tau_end) o.overrides.tau_end = fmt::format("{}", *tau_end);
  o.overrides.precision = precision;
  o.verify = verify;
  o.certify = certify;
  std::ostringstream out;
  run_released([&] { return app::run_reference(o, out); });
  return reference_of_csv(out.str());
}

// ---- check ------------------------------------------------------------------------------------

struct py_check_result {
  py::dict as_dict;
  int exit_code = 0;
};

// The form of a reference file's scene, from its header: tau first (normalized), t and y1
// (coefficient), else t and omega (physical).
std::string form_of_header(const std::vector<std::string>& header) {
  if (!header.empty() && header[0] == "tau") return "normalized";
  if (header.size() > 1 && header[1] == "y1") return "coefficient";
  return "physical";
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

// The trajectory as a CSV file in `dir`, every number as its shortest round-trip text.
std::string write_trajectory(const scratch_dir& dir, const py::array_t<double, py::array::c_style | py::array::forcecast>& t,
                             const py::array_t<double, py::array::c_style | py::array::forcecast>& y,
                             const std::vector<std::string>& columns) {
  if (t.ndim() != 1) throw py::value_error(fmt::format("t: expected a 1-d array, got {} dimensions", t.ndim()));
  if (y.ndim() != 2 || y.shape(0) != t.shape(0))
    throw py::value_error(fmt::format("y: expected shape ({}, m), got {} dimensions", t.shape(0), y.ndim()));
  if (columns.size() != static_cast<std::size_t>(y.shape(1)) + 1)
    throw py::value_error(fmt::format("columns: {} names for a time and {} state columns", columns.size(), y.shape(1)));
  std::string text;
  for (std::size_t c = 0; c < columns.size(); ++c) text += (c ? "," : "") + columns[c];
  text += "\n";
  auto tv = t.unchecked<1>();
  auto yv = y.unchecked<2>();
  for (py::ssize_t i = 0; i < t.shape(0); ++i) {
    text += fmt::format("{}", tv(i));
    for (py::ssize_t k = 0; k < y.shape(1); ++k) text += fmt::format(",{}", yv(i, k));
    text += "\n";
  }
  const fs::path p = dir / "trajectory.csv";
  write_text(p, text);
  return p.string();
}

py_check_result check(const py::object& against, const py::object& t, const py::object& y,
                      const std::optional<std::vector<std::string>>& columns, const std::optional<double>& tol,
                      const std::optional<double>& rel_tol, const std::optional<double>& attitude_tol,
                      bool ignore_attitude, const std::optional<std::string>& precision,
                      const std::optional<double>& scd_atol, const std::optional<double>& scd_rtol) {
  scratch_dir dir;
  app::check_options o;
  std::string form = "normalized";
  if (py::isinstance<py_reference>(against)) {
    const py_reference& r = against.cast<const py_reference&>();
    const fs::path p = dir / "reference.csv";
    write_text(p, r.csv);
    o.reference = p.string();
    form = form_of_header(r.all_columns);
  } else if (py::isinstance<py::str>(against) && !against.cast<std::string>().ends_with(".toml")) {
    o.reference = against.cast<std::string>();  // a reference CSV: its header says the form
    std::ifstream in = app::open_input_file("reference", o.reference);
    form = form_of_header(app::csv_rows(in, "reference " + o.reference).header());
  } else {
    const py_scene s = scene_of(against);
    o.reference = scene_path(s, dir);
    form = s.form();
  }
  if (py::isinstance<py::str>(t) && y.is_none()) {
    o.trajectory = t.cast<std::string>();  // a trajectory file, read as the CLI reads it
  } else {
    const auto ta = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(t);
    const auto ya = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(y);
    if (!ta || !ya) throw py::value_error("t and y: expected arrays of numbers");
    const std::vector<std::string> names =
        columns ? *columns : default_columns(form, ya.ndim() == 2 ? static_cast<std::size_t>(ya.shape(1)) : 0);
    o.trajectory = write_trajectory(dir, ta, ya, names);
  }
  const auto text = [](const std::optional<double>& x) {
    return x ? std::optional<std::string>(fmt::format("{}", *x)) : std::nullopt;
  };
  o.tol = text(tol);
  o.rel_tol = text(rel_tol);
  o.attitude_tol = text(attitude_tol);
  o.ignore_attitude = ignore_attitude;
  o.precision = precision;
  o.scd_atol = text(scd_atol);
  o.scd_rtol = text(scd_rtol);
  o.format = "json";
  std::ostringstream out;
  py_check_result r;
  r.exit_code = run_released([&] { return app::run_check(o, out); });
  r.as_dict = py::module_::import("json").attr("loads")(out.str());
  return r;
}

// The dictionary's "pass": True, False or None (no bar given).
py::object verdict_of(const py_check_result& r) { return r.as_dict["pass"]; }
bool passed_of(const py_check_result& r) { return verdict_of(r).ptr() == Py_True; }

// ---- the shipped scenes -----------------------------------------------------------------------

py::dict problems() {
  py::dict out;
  const fs::path root = EULERVOP_SCENES_DIR;
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(root, ec))
    if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) out[py::str(f.stem().string())] = f.string();
  return out;
}

// Scene, Reference and CheckResult.
void bind_classes(py::module_& m) {
  py::class_<py_scene>(m, "Scene", "A parsed scene (docs/scenes.md).")
      .def_static("load", &scene_load, py::arg("path"), "Reads and validates the scene file at `path`.")
      .def_static("from_toml", &scene_from_toml, py::arg("text"), "Parses and validates a scene given as TOML text.")
      .def_property_readonly("name", [](const py_scene& s) { return s.parsed.name; }, "The scene's name.")
      .def_property_readonly("form", &py_scene::form, "'normalized', 'physical' or 'coefficient'.")
      .def_property_readonly("text", [](const py_scene& s) { return s.parsed.source_text; }, "The TOML text.")
      .def_property_readonly("path", [](const py_scene& s) { return s.path; }, "The file it was loaded from, or None.")
      .def("__repr__", [](const py_scene& s) { return fmt::format("<eulervop.Scene {} ({})>", s.parsed.name, s.form()); });

  py::class_<py_reference>(m, "Reference", "A reference solution, as `eulervop reference` writes it.")
      .def_readonly("t", &py_reference::t, "float64 (n,): the time column (t, or tau of a normalized scene).")
      .def_readonly("y", &py_reference::y, "float64 (n, m): the state columns, in the CSV's order (not tau).")
      .def_readonly("columns", &py_reference::columns, "The names of y's columns.")
      .def_readonly("all_columns", &py_reference::all_columns, "Every column of the CSV, in its order.")
      .def_readonly("decimal", &py_reference::decimal,
                    "Every cell's text, row by row in all_columns' order: every digit of the precision.")
      .def_readonly("meta", &py_reference::meta, "The CSV's '#' lines as a dict (scene_text joined, note a list).")
      .def_readonly("radius", &py_reference::radius,
                    "With certify=True: each row's proven radius of the integrator's state (Omega, or y in the "
                    "coefficient form), else None (a body in the direct form has radius_omega alone).")
      .def_readonly("radius_omega", &py_reference::radius_omega,
                    "With certify=True on a physical scene: the radius of omega in rad/s, else None.")
      .def_readonly("radius_q", &py_reference::radius_q,
                    "With certify=True on a scene with an attitude: the radius of |q - q*|_2 of the printed "
                    "quaternion, else None.")
      .def_readonly("csv", &py_reference::csv, "The whole CSV text.")
      .def("__len__", [](const py_reference& r) { return r.decimal.size(); })
      .def("__repr__", [](const py_reference& r) {
        return fmt::format("<eulervop.Reference {} rows: {}>", r.decimal.size(), fmt::join(r.all_columns, ","));
      });

  py::class_<py_check_result>(m, "CheckResult", "The verdict of `check`.")
      .def_property_readonly(
          "passed", &passed_of,
          "True when a bar was given and every row is within it; False otherwise (no bar: no verdict).")
      .def_property_readonly("verdict", &verdict_of,
                             "True, False, or None when no bar was given.")
      .def_property_readonly("max_error", [](const py_check_result& r) { return py::object(r.as_dict["max_error"]); },
                             "The largest error (rad/s for a physical trajectory in t, omega1..3).")
      .def_readonly("exit_code", &py_check_result::exit_code, "The CLI's exit code: 0 within, 1 outside.")
      .def("as_dict", [](const py_check_result& r) { return py::module_::import("copy").attr("deepcopy")(r.as_dict); },
           "Every key and value of `eulervop check --format json` on the same inputs.")
      .def("__bool__", &passed_of)
      .def("__repr__", [](const py_check_result& r) {
        return fmt::format("<eulervop.CheckResult pass={} max_error={}>", py::str(verdict_of(r)).cast<std::string>(),
                           py::str(py::object(r.as_dict["max_error"])).cast<std::string>());
      });

}

// reference, check and problems.
void bind_functions(py::module_& m) {
  m.def("reference", &reference, py::arg("scene"), py::arg("times") = py::none(), py::arg("precision") = py::none(),
        py::arg("verify") = false, py::arg("certify") = false, py::arg("samples") = py::none(),
        py::arg("t_end") = py::none(), py::arg("tau_end") = py::none(),
        "reference(scene, times=None, precision=None, verify=False, certify=False, samples=None, t_end=None, "
        "tau_end=None) -> Reference\n\n"
        "The scene's reference solution, exactly as `eulervop reference` computes it. `scene` is a Scene or a path. "
        "`times`: sample times in the scene's own time (t in s for a physical scene, tau for a normalized one); "
        "without them the scene's samples (or `samples`, a count). `t_end` (physical and coefficient forms) or "
        "`tau_end` (normalized) moves the end of the span, as --t-end and --tau-end do. `precision`: 'double', 'quad' or 'mpfr:BITS'. "
        "`verify`: recompute one precision up and record meta['estimated_max_error']. `certify`: prove a radius "
        "per row. Raises ValueError for bad input, NumericalFailure when the integrator gives up, "
        "KeyboardInterrupt on Ctrl-C. The GIL is released while it runs.");
  m.def("check", &check, py::arg("against"), py::arg("t"), py::arg("y") = py::none(), py::arg("columns") = py::none(),
        py::arg("tol") = py::none(), py::arg("rel_tol") = py::none(), py::arg("attitude_tol") = py::none(),
        py::arg("ignore_attitude") = false, py::arg("precision") = py::none(), py::arg("scd_atol") = py::none(),
        py::arg("scd_rtol") = py::none(),
        "check(against, t, y=None, columns=None, tol=None, rel_tol=None, attitude_tol=None, ignore_attitude=False, "
        "precision=None, scd_atol=None, scd_rtol=None) -> CheckResult\n\n"
        "Another tool's trajectory against the reference, as `eulervop check` judges it (docs/check.md). `against`: "
        "a Scene, a scene path, a Reference, or a reference CSV path. `t` (n,) and `y` (n, m) NumPy arrays, with "
        "`columns` naming the time and y's columns (default: the scene's form, q0..q3 added when y has 7 columns); "
        "or `t` a path to a trajectory CSV and y None. `tol` is in the trajectory's units (rad/s for t, omega1..3); "
        "with q0..q3 give `attitude_tol` (rad) or ignore_attitude=True. Raises ValueError for bad input, "
        "NumericalFailure, KeyboardInterrupt.");
  m.def("problems", &problems,
        "problems() -> dict: the shipped scenes by name (e.g. 'sciml-rigid-body') to their file paths, for "
        "Scene.load.");
}

}  // namespace

PYBIND11_MODULE(eulervop, m) {
  m.doc() =
      "eulervop: high-precision reference solutions of Euler's rigid-body equations, and an oracle "
      "for other integrators' trajectories (docs/python.md).";
  m.attr("__version__") = EULERVOP_VERSION;
  numerical_failure_type = PyErr_NewExceptionWithDoc(
      "eulervop.NumericalFailure",
      "The reference integrator gave up; the message gives the time (in the scene's own units first) and the cause.",
      PyExc_ArithmeticError, nullptr);
  m.attr("NumericalFailure") = py::handle(numerical_failure_type);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const interrupted&) {
      PyErr_SetNone(PyExc_KeyboardInterrupt);
    } catch (const eulervop::scene::input_error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const eulervop::numerical_failure& e) {
      PyErr_SetString(numerical_failure_type, e.what());
    }
  });
  // Progress is never drawn here; the display only lets Ctrl-C through.
  app::set_progress_display([](const std::string&, double, const app::progress_unit&) {
    return std::make_unique<interrupt_check>();
  });

  bind_classes(m);
  bind_functions(m);
}
