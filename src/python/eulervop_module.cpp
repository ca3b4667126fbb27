// The Python module `eulervop` (docs/python.md): the oracle one import away.
//
// Every call runs the program's own commands (`reference`, `check`) in this process, on the same
// code path as the command line, so a value here is the CLI's value cell for cell and a check's
// dictionary is `check --format json`. Arrays cross as NumPy float64: a check's arrays are written
// as the exact decimal of each double, so they are judged at their binary values; the decimal text
// of every cell of a reference is kept. The GIL is released while a command runs; Ctrl-C is
// noticed between segments of the integration (a few per second at the least) and raises
// KeyboardInterrupt. Bad input raises ValueError with the CLI's one-line message in Python's terms
// (keywords for flags, t and y by shape and index for the scratch file), a numerical failure
// eulervop.NumericalFailure (an ArithmeticError) with the time and the cause. Nothing is written
// but scratch files in a private temporary directory, removed before the call returns.
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
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
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
  const fs::path& path() const { return path_; }

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

// ---- messages in Python's terms ---------------------------------------------------------------
//
// The commands' messages name their flags and their files. A caller of the module gave keywords
// and arrays, and the files are scratch files, removed by the time the message is read. So every
// input_error of a command is rewritten in the caller's terms: each flag as its keyword
// (`--attitude-tol 1e-06` as `attitude_tol=1e-06`), the arrays' file as `t` and `y` (a line as a
// row index), a Reference's file as "the Reference", a scene given as text by its name.

void replace_all(std::string& s, std::string_view from, std::string_view to) {
  if (from.empty()) return;
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
}

// A value as Python shows it.
std::string py_repr(const py::handle& o) { return py::repr(o).cast<std::string>(); }
std::string py_repr(double x) { return py_repr(py::float_(x)); }

// What a caller passed where numbers were due, as Python shows it, cut to one short line.
std::string short_repr(const py::handle& o) {
  std::string s = py_repr(o);
  replace_all(s, "\n", " ");
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

// A shape as NumPy prints it: (), (n,), (n, m).
std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// A command's flag and the keyword that set it.
struct keyword {
  std::string flag;                 // "--attitude-tol"
  std::string name;                 // "attitude_tol"
  std::optional<std::string> text;  // the flag's value as the command was given it
  std::string shown;                // that value as Python shows it
  bool is_switch = false;           // a bool keyword: --ignore-attitude is ignore_attitude=True
};

// Every mention of k.flag in `m` as the keyword: with its value where the message quotes it,
// alone where it heads a clause ("attitude_tol: required"), else as "tol=" (a keyword to give).
void put_keyword(std::string& m, const keyword& k) {
  const auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_'; };
  for (std::size_t at = m.find(k.flag); at != std::string::npos; at = m.find(k.flag, at)) {
    std::size_t end = at + k.flag.size();
    if (end < m.size() && word_char(m[end])) {  // a longer flag: --tol in --tolerance
      at = end;
      continue;
    }
    std::string to;
    const auto followed_by = [&](const std::string& s) { return m.compare(end, s.size(), s) == 0; };
    if (k.text && followed_by(" " + *k.text) &&
        (end + 1 + k.text->size() == m.size() || !word_char(m[end + 1 + k.text->size()]))) {
      to = k.name + "=" + k.shown;
      end += 1 + k.text->size();
    } else if (k.flag == "--attitude-tol" && followed_by(" RAD")) {
      to = k.name + "=<radians>";
      end += 4;
    } else if (k.is_switch) {
      to = k.name + "=True";
    } else if (followed_by(":") || followed_by(" and ")) {
      to = k.name;
    } else {
      to = k.name + "=";
    }
    m.replace(at, end - at, to);
    at += to.size();
  }
}

struct python_terms {
  std::string scratch;                    // the scratch directory, with a trailing separator
  std::vector<keyword> keywords;
  std::optional<std::string> trajectory;  // the arrays' scratch file
  std::string header;                     // its columns: "columns=[...]" or "t and y (read as ...)"
  std::string y_named;                    // y with its shape or its columns
  std::string q_place;                    // where q0..q3 are in y: "y[:, 3:7]"
  std::string names_wanted;               // the names the reference is compared by, for columns=
  std::vector<double> times;              // t, to show a row's time
  std::optional<std::string> reference;   // a Reference's scratch file
  std::optional<std::string> scene_file;  // a scene given as text: its scratch file, and its name
  std::string scene_name;

  // A row's line of the arrays' file as the caller's terms; `rest` follows "line N: ".
  std::string row_message(std::size_t line, std::string rest) const {
    if (line <= 1) {  // the header: the column names
      const std::string q = "columns q0..q3: ";
      if (rest.starts_with(q) && rest.find(" has no attitude") != std::string::npos)
        return fmt::format("y has q0..q3 in {}, but {}; give the rates alone", q_place, rest.substr(q.size()));
      replace_all(rest, "the header has no column", "no column");
      // The command's hint is a --columns map of a file's names; here the names are columns=.
      if (const std::size_t hint = rest.find("; the header has "); hint != std::string::npos)
        rest = rest.substr(0, hint) + "; name t's column, then each of y's, in columns= (" + names_wanted + ")";
      return header + ": " + rest;
    }
    const std::size_t row = line - 2;  // the header is line 1, row 0 line 2
    const std::string at = fmt::format("t[{}]", row) + (row < times.size() ? " = " + py_repr(times[row]) : "");
    const std::string sample = " is not a sample time of ";
    const std::size_t k = rest.find(sample);
    if (k == std::string::npos) return fmt::format("row {} of t and y ({}): {}", row, at, rest);
    std::string tail = rest.substr(k + sample.size());
    if (reference && tail.starts_with("reference " + *reference)) {
      // The nearest samples' lines are those of a scratch file: their times say enough.
      for (std::size_t p = tail.find(" (line "); p != std::string::npos; p = tail.find(" (line ", p)) {
        const std::size_t close = tail.find(')', p);
        if (close == std::string::npos) break;
        tail.erase(p, close + 1 - p);
      }
      tail.insert(("reference " + *reference).size(), " (ref.t)");
    }
    return at + sample + tail;
  }

  std::string operator()(std::string m) const {
    if (trajectory) {
      const std::string file = "trajectory " + *trajectory;
      const std::string at = file + ": line ";
      if (m.starts_with(at)) {
        std::size_t end = at.size(), line = 0;
        while (end < m.size() && std::isdigit(static_cast<unsigned char>(m[end]))) line = line * 10 + (m[end++] - '0');
        if (m.compare(end, 2, ": ") == 0) m = row_message(line, m.substr(end + 2));
      }
      replace_all(m, file + " has columns q0..q3", "y has q0..q3 in " + q_place);
      replace_all(m, file + " has no columns q0..q3", y_named + " has no columns q0..q3");
      replace_all(m, file, "t and y");
    }
    if (reference) {
      replace_all(m, "reference " + *reference, "the Reference");
      replace_all(m, *reference, "the Reference");
    }
    if (scene_file) replace_all(m, *scene_file, "scene " + scene_name + " (from TOML text)");
    for (const keyword& k : keywords) put_keyword(m, k);
    replace_all(m, scratch, "");  // nothing else should name it; if anything does, not its directory
    return m;
  }
};

// Runs a command with the GIL released; its bad input is rethrown in the caller's terms.
template <class Run>
int run_in_python_terms(const python_terms& terms, Run&& run) {
  try {
    return run_released(std::forward<Run>(run));
  } catch (const eulervop::scene::input_error& e) {
    throw eulervop::scene::input_error(terms(e.what()));
  }
}

// A keyword with no value to quote: the messages name it as one to give.
keyword plain_keyword(const std::string& flag, const std::string& name) {
  keyword k;
  k.flag = flag;
  k.name = name;
  return k;
}

// A number keyword: the text the command is given (the double's shortest round-trip text, the
// decimal a user types) and its keyword's value as Python shows it.
keyword number_keyword(const std::string& flag, const std::string& name, const std::optional<double>& x) {
  keyword k = plain_keyword(flag, name);
  if (x) k.text = fmt::format("{}", *x), k.shown = py_repr(*x);
  return k;
}

keyword text_keyword(const std::string& flag, const std::string& name, const std::optional<std::string>& x) {
  keyword k = plain_keyword(flag, name);
  if (x) k.text = *x, k.shown = py_repr(py::str(*x));
  return k;
}

keyword switch_keyword(const std::string& flag, const std::string& name) {
  keyword k = plain_keyword(flag, name);
  k.is_switch = true;
  return k;
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
  std::vector<std::string> normalized_columns;      // tau, Omega1..3, when the file has them
  std::optional<py::array_t<double>> normalized;
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
  const auto index = [&](const std::string& name) -> std::optional<std::size_t> {
    const auto it = std::find(r.all_columns.begin(), r.all_columns.end(), name);
    if (it == r.all_columns.end()) return std::nullopt;
    return static_cast<std::size_t>(it - r.all_columns.begin());
  };
  // The time is the first column. y holds the columns `check` reads by default for the scene's
  // form (t, omega1..3 and q0..q3; tau, Omega1..3; t, y1..3), so that check(scene, ref.t, ref.y)
  // judges the reference against itself: a physical file's second time and rates, tau and
  // Omega1..3, go to `normalized` instead, and the radii to their own arrays.
  const bool normalized_time = !r.all_columns.empty() && r.all_columns[0] == "tau";
  const std::vector<std::string> normalized_names = {"tau", "Omega1", "Omega2", "Omega3"};
  std::vector<std::size_t> state;
  for (std::size_t c = 1; c < r.all_columns.size(); ++c) {
    const std::string& name = r.all_columns[c];
    if (name == "radius" || name == "radius_omega" || name == "radius_q") continue;
    if (!normalized_time && std::find(normalized_names.begin(), normalized_names.end(), name) != normalized_names.end())
      continue;
    state.push_back(c), r.columns.push_back(name);
  }
  const auto n = static_cast<py::ssize_t>(r.decimal.size());
  const auto value = [&](py::ssize_t i, std::size_t c) {
    return std::strtod(r.decimal[static_cast<std::size_t>(i)][c].c_str(), nullptr);
  };
  const auto matrix = [&](const std::vector<std::size_t>& cs) {
    py::array_t<double> a({n, static_cast<py::ssize_t>(cs.size())});
    auto v = a.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i)
      for (std::size_t k = 0; k < cs.size(); ++k) v(i, static_cast<py::ssize_t>(k)) = value(i, cs[k]);
    return a;
  };
  const auto column = [&](std::size_t c) {
    py::array_t<double> a(n);
    auto v = a.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i) v(i) = value(i, c);
    return a;
  };
  r.t = column(0);
  r.y = matrix(state);
  std::vector<std::size_t> normalized;
  for (const std::string& name : normalized_names)
    if (const auto c = index(name)) normalized.push_back(*c);
  if (normalized.size() == normalized_names.size()) {
    r.normalized_columns = normalized_names;
    r.normalized = matrix(normalized);
  }
  if (const auto c = index("radius")) r.radius = column(*c);
  if (const auto c = index("radius_omega")) r.radius_omega = column(*c);
  if (const auto c = index("radius_q")) r.radius_q = column(*c);
  return r;
}

using float64_array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A path a caller gave (str or os.PathLike), if `o` is one.
std::optional<std::string> path_of(const py::object& o) {
  if (py::isinstance<py::str>(o)) return o.cast<std::string>();
  if (py::hasattr(o, "__fspath__")) return py::str(py::module_::import("os").attr("fspath")(o)).cast<std::string>();
  return std::nullopt;
}

// Sample times as `--times` takes them: each double's shortest round-trip text, as a user types
// the flag, so that the cells are the CLI's for the same times.
std::string times_text(const py::object& times) {
  const auto a = float64_array::ensure(times);
  if (!a) throw py::value_error(fmt::format("times: expected numbers, got {}", short_repr(times)));
  if (a.ndim() != 1) throw py::value_error(fmt::format("times has shape {}; expected (k,), the sample times", shape_text(a)));
  if (a.shape(0) == 0) throw py::value_error("times has shape (0,): give at least one time");
  std::string text;
  const auto v = a.unchecked<1>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) text += (i ? "," : "") + fmt::format("{}", v(i));
  return text;
}

py_reference reference(const py::object& scene, const py::object& times, const std::optional<std::string>& precision,
                       bool verify, bool certify, const std::optional<int>& samples,
                       const std::optional<double>& t_end, const std::optional<double>& tau_end) {
  const py_scene s = scene_of(scene);
  scratch_dir dir;
  python_terms terms;
  terms.scratch = (dir.path() / "").string();
  app::reference_options o;
  o.scene_path = scene_path(s, dir);
  if (!s.path) terms.scene_file = *o.scene_path, terms.scene_name = s.parsed.name;
  keyword times_keyword = plain_keyword("--times", "times");
  if (!times.is_none()) {
    o.overrides.times = times_text(times);
    times_keyword.text = *o.overrides.times;
    times_keyword.shown = py_repr(float64_array::ensure(times).attr("tolist")());
  }
  if (samples) o.overrides.samples = std::to_string(*samples);
  if (t_end) o.overrides.t_end = fmt::format("{}", *t_end);
  if (tau_end) o.overrides.tau_end = fmt::format("{}", *tau_end);
  o.overrides.precision = precision;
  o.verify = verify;
  o.certify = certify;
  keyword samples_keyword = plain_keyword("--samples", "samples");
  if (samples) samples_keyword.text = samples_keyword.shown = std::to_string(*samples);
  terms.keywords = {times_keyword,
                    samples_keyword,
                    number_keyword("--t-end", "t_end", t_end),
                    number_keyword("--tau-end", "tau_end", tau_end),
                    text_keyword("--precision", "precision", precision),
                    switch_keyword("--verify", "verify"),
                    switch_keyword("--certify", "certify")};
  std::ostringstream out;
  run_in_python_terms(terms, [&] { return app::run_reference(o, out); });
  return reference_of_csv(out.str());
}

// ---- check ------------------------------------------------------------------------------------

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

// The form of a reference file's scene, from its header: tau first (normalized), t and y1
// (coefficient), else t and omega (physical).
against_info against_of_header(const std::vector<std::string>& header, std::string name) {
  against_info a;
  a.name = std::move(name);
  if (!header.empty() && header[0] == "tau")
    a.form = "normalized";
  else
    a.form = header.size() > 1 && header[1] == "y1" ? "coefficient" : "physical";
  a.attitude = std::find(header.begin(), header.end(), "q0") != header.end();
  return a;
}

// The names of a form's state, for messages: "omega1..3".
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

// Every binary64 is a dyadic rational, so its decimal expansion is finite (767 significant
// digits at most): written in full, it is read back as the very double in double, quad or MPFR.
// The shortest round-trip text would be read in quad or MPFR as another number, up to half an
// ulp away, and the arrays judged at values the caller never computed.
std::string exact_decimal(double x) {
  if (x == 0) return std::signbit(x) ? "-0" : "0";
  char buf[800];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific, 766);
  if (ec != std::errc{}) throw std::logic_error("eulervop: no exact decimal for " + fmt::format("{}", x));
  const std::string s(buf, end);
  const std::size_t e = s.find('e');
  std::size_t last = s.find_last_not_of('0', e - 1);
  if (s[last] == '.') --last;
  return s.substr(0, last + 1) + s.substr(e);
}

// The column names as the caller wrote them in Python.
std::string names_repr(const std::vector<std::string>& names) {
  py::list l;
  for (const std::string& n : names) l.append(n);
  return py_repr(l);
}

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

// The arrays t and y as the trajectory CSV of `check`, in `dir`, every number exact. Everything
// about the arrays that the command would reject row by row is checked here first, so that the
// message names t and y by index and shape (the command would name a line of a scratch file).
// `terms` learns how to name the file, its header and its rows in the command's other messages.
std::string write_trajectory(const scratch_dir& dir, const py::object& t_obj, const py::object& y_obj,
                             const std::optional<std::vector<std::string>>& columns, const against_info& against,
                             python_terms& terms) {
  if (y_obj.is_none())
    throw py::value_error("y: missing; give y, shape (n, m), one row per time in t (or t the path of a trajectory CSV)");
  const auto t = float64_array::ensure(t_obj);
  if (!t) throw py::value_error(fmt::format("t: expected an array of numbers, got {}", short_repr(t_obj)));
  const auto y = float64_array::ensure(y_obj);
  if (!y) throw py::value_error(fmt::format("y: expected an array of numbers, got {}", short_repr(y_obj)));
  if (t.ndim() != 1) throw py::value_error(fmt::format("t has shape {}; expected (n,), one time per row of y", shape_text(t)));
  const py::ssize_t n = t.shape(0);
  if (n == 0) throw py::value_error("t has shape (0,): give at least one time");
  if (y.ndim() != 2 || y.shape(0) != n)
    throw py::value_error(fmt::format("y has shape {}; expected ({}, m) with one row per time in t{}", shape_text(y), n,
                                      y.ndim() == 2 && y.shape(1) == n ? " (transpose it?)" : ""));
  const py::ssize_t m = y.shape(1);
  const auto width = static_cast<std::size_t>(m);
  std::vector<std::string> names;
  if (columns) {
    names = *columns;
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
  } else {
    if (m != 3 && m != 7) {
      const std::string state = state_names(against.form);
      throw py::value_error(fmt::format(
          "y has shape {}; expected ({}, 3), the rates {}{}, for {} ({} form); or name y's columns with columns=",
          shape_text(y), n, state, against.attitude ? fmt::format(", or ({}, 7), {} then q0..q3", n, state) : "",
          against.name, against.form));
    }
    names = default_columns(against.form, width);
  }

  const auto tv = t.unchecked<1>();
  const auto yv = y.unchecked<2>();
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
  // q0..q3 all zero is no attitude: the command says so of a row, here of y's row.
  std::vector<py::ssize_t> q;
  for (const char* name : {"q0", "q1", "q2", "q3"}) {
    const auto it = std::find(names.begin() + 1, names.end(), name);
    if (it != names.end()) q.push_back(static_cast<py::ssize_t>(it - names.begin()) - 1);
  }
  if (q.size() == 4)
    for (py::ssize_t i = 0; i < n; ++i)
      if (yv(i, q[0]) == 0 && yv(i, q[1]) == 0 && yv(i, q[2]) == 0 && yv(i, q[3]) == 0)
        throw py::value_error(fmt::format("y[{}] has q0..q3 = 0 ({}), which is no attitude", i, place_in_y(names)));

  std::string text = fmt::format("{}\n", fmt::join(names, ","));
  for (py::ssize_t i = 0; i < n; ++i) {
    text += exact_decimal(tv(i));
    for (py::ssize_t k = 0; k < m; ++k) text += "," + exact_decimal(yv(i, k));
    text += "\n";
  }
  const fs::path p = dir / "trajectory.csv";
  write_text(p, text);

  terms.trajectory = p.string();
  terms.header = columns ? "columns=" + names_repr(names)
                         : fmt::format("t and y (read as columns {})", fmt::join(names, ", "));
  terms.y_named = columns ? "y (columns=" + names_repr(names) + ")" : fmt::format("y (shape {})", shape_text(y));
  terms.q_place = place_in_y(names);
  terms.names_wanted = fmt::format("{}{} for {}", fmt::join(default_columns(against.form, 3), ", "),
                                   against.attitude ? ", then q0..q3" : "", against.name);
  terms.times.assign(tv.data(0), tv.data(0) + n);
  return p.string();
}

py_check_result check(const py::object& against, const py::object& t, const py::object& y,
                      const std::optional<std::vector<std::string>>& columns, const std::optional<double>& tol,
                      const std::optional<double>& rel_tol, const std::optional<double>& attitude_tol,
                      bool ignore_attitude, const std::optional<std::string>& precision,
                      const std::optional<double>& scd_atol, const std::optional<double>& scd_rtol) {
  scratch_dir dir;
  python_terms terms;
  terms.scratch = (dir.path() / "").string();
  app::check_options o;
  against_info a;
  const std::optional<std::string> against_path = path_of(against);
  if (py::isinstance<py_reference>(against)) {
    const py_reference& r = against.cast<const py_reference&>();
    const fs::path p = dir / "reference.csv";
    write_text(p, r.csv);
    o.reference = p.string();
    terms.reference = o.reference;
    a = against_of_header(r.all_columns, "the Reference");
  } else if (against_path && !against_path->ends_with(".toml")) {
    o.reference = *against_path;  // a reference CSV: its header says the form
    std::ifstream in = app::open_input_file("reference", o.reference);
    a = against_of_header(app::csv_rows(in, "reference " + o.reference).header(), "reference " + o.reference);
  } else {
    const py_scene s = scene_of(against);
    o.reference = scene_path(s, dir);
    if (!s.path) terms.scene_file = o.reference, terms.scene_name = s.parsed.name;
    a.form = s.form();
    a.attitude = s.parsed.has_attitude();
    a.name = "scene " + s.parsed.name;
  }
  const std::optional<std::string> trajectory_path = path_of(t);
  if (trajectory_path && y.is_none())
    o.trajectory = *trajectory_path;  // a trajectory file, read as the CLI reads it
  else
    o.trajectory = write_trajectory(dir, t, y, columns, a, terms);
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
  terms.keywords = {number_keyword("--tol", "tol", tol),
                    number_keyword("--rel-tol", "rel_tol", rel_tol),
                    number_keyword("--attitude-tol", "attitude_tol", attitude_tol),
                    switch_keyword("--ignore-attitude", "ignore_attitude"),
                    text_keyword("--precision", "precision", precision),
                    number_keyword("--scd-atol", "scd_atol", scd_atol),
                    number_keyword("--scd-rtol", "scd_rtol", scd_rtol),
                    plain_keyword("--columns", "columns")};
  std::ostringstream out;
  py_check_result r;
  r.exit_code = run_in_python_terms(terms, [&] { return app::run_check(o, out); });
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
      .def_readonly("y", &py_reference::y,
                    "float64 (n, m): the columns `check` reads by default, in the CSV's order: omega1..3 (and q0..q3 "
                    "with an attitude) for a physical scene, Omega1..3 for a normalized one, y1..3 for the coefficient "
                    "form; so check(scene, ref.t, ref.y) judges the reference against itself.")
      .def_readonly("columns", &py_reference::columns, "The names of y's columns.")
      .def_readonly("normalized", &py_reference::normalized,
                    "float64 (n, 4): the columns tau, Omega1..3, the normalized time and rates of Eqs. 2-4 (a physical "
                    "scene's file carries them after its own; a normalized scene's are t and y); None when the file "
                    "has none (the coefficient form, the direct form).")
      .def_readonly("normalized_columns", &py_reference::normalized_columns,
                    "The names of normalized's columns: ['tau', 'Omega1', 'Omega2', 'Omega3'], or [] when it is None.")
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
        "or `t` a path to a trajectory CSV and y None. Each float64 is judged at its exact binary value. `tol` is in "
        "the trajectory's units (rad/s for t, omega1..3); with q0..q3 give `attitude_tol` (rad) or "
        "ignore_attitude=True. Raises ValueError for bad input (naming the keywords, and t and y by shape and index), "
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
