#include "commands/check_command.hpp"

#include "io/atomic_file.hpp"
#include "io/csv_rows.hpp"
#include "cli/exit_codes.hpp"
#include "io/output_cells.hpp"
#include "compute/reference_compute.hpp"
#include "io/reference_csv.hpp"
#include "compute/scene_library.hpp"
#include "compute/scene_overrides.hpp"
#include "compute/with_scalar.hpp"

#include <eulervop/reference/integrate.hpp>
#include <eulervop/model/error_measure.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/integrals.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/core/scalar.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace eulervop::app {

namespace fs = std::filesystem;

namespace {


// Trajectory times must equal reference sample times to this relative difference.
constexpr double time_match_rel = 1e-12;

// ---- flags -> a job ------------------------------------------------------------------------------

// The canonical column names and the file's names for them (--columns).
const std::array<std::string, 8> canonical_columns = {"tau", "Omega1", "Omega2", "Omega3",
                                                       "t",   "omega1", "omega2", "omega3"};

struct check_job {
  std::string trajectory_path;
  std::string reference_path;
  bool from_scene = false;
  scene scn;                      // from_scene
  eulervop::precision precision;  // from_scene: --precision, else the scene's
  picard_settings settings;
  std::map<std::string, std::string> names;  // canonical -> the file's column name
  std::map<std::string, bool> renamed;       // canonical -> given by --columns
  std::optional<double> tol, rel_tol;
  double scd_atol = 1e-12, scd_rtol = 1e-12;  // the mixed error of mescd
  std::optional<std::string> errors_out;
  bool json = false;
};

// A scene (.toml) or a reference CSV? By extension, else by the first non-blank line.
bool looks_like_scene(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".toml") return true;
  if (ext == ".csv") return false;
  std::ifstream in = open_input_file("reference", path);
  for (std::string l; std::getline(in, l);) {
    const std::string t = trimmed(l);
    if (t.empty()) continue;
    return !(t.starts_with("#") || t.find(',') != std::string::npos);
  }
  return true;
}

std::optional<double> non_negative_flag(const char* flag, const std::optional<std::string>& text) {
  if (!text) return std::nullopt;
  const decimal d = flag_number(flag, *text);
  if (d.value < 0) throw input_error(fmt::format("{} {}: must be >= 0", flag, *text));
  return d.value;
}

check_job make_job(const check_options& o) {
  check_job job;
  job.trajectory_path = o.trajectory;
  job.reference_path = o.reference;
  for (const std::string& c : canonical_columns) {
    job.names[c] = c;
    job.renamed[c] = false;
  }
  if (o.columns) {
    for (const std::string& item : flag_list("--columns", *o.columns)) {
      const std::size_t eq = item.find('=');
      const std::string key = trimmed(std::string_view(item).substr(0, eq));
      const std::string value = eq == std::string::npos ? "" : trimmed(std::string_view(item).substr(eq + 1));
      if (eq == std::string::npos || value.empty())
        throw input_error(fmt::format("--columns {}: `{}` is not NAME=COLUMN", *o.columns, item));
      if (!job.names.contains(key))
        throw input_error(fmt::format("--columns {}: unknown name `{}` (expected: tau, Omega1..3, t, omega1..3)",
                                      *o.columns, key));
      job.names[key] = value;
      job.renamed[key] = true;
    }
  }
  job.tol = non_negative_flag("--tol", o.tol);
  job.rel_tol = non_negative_flag("--rel-tol", o.rel_tol);
  if (o.scd_atol) job.scd_atol = positive_flag_number("--scd-atol", *o.scd_atol).value;
  if (o.scd_rtol) job.scd_rtol = positive_flag_number("--scd-rtol", *o.scd_rtol).value;
  const std::string format = o.format.value_or("table");
  if (format != "table" && format != "json") throw input_error(fmt::format("--format {}: expected table or json", format));
  job.json = format == "json";
  if (o.errors_out && o.errors_out->empty()) throw input_error("--errors-out: empty path");
  job.errors_out = o.errors_out;

  job.from_scene = looks_like_scene(o.reference);
  if (job.from_scene) {
    job.scn = load_scene_file(o.reference);
    scene_override_flags flags;
    flags.precision = o.precision;
    const applied_overrides applied = apply_scene_overrides(job.scn, flags);
    job.precision = applied.precision;
    job.settings = applied.settings;
  } else if (o.precision) {
    throw input_error(fmt::format("--precision {}: not used with a reference file (its own precision is used)",
                                  *o.precision));
  }
  open_input_file("trajectory", o.trajectory);  // unreadable: bad input before any work
  return job;
}

// ---- the trajectory's columns ----------------------------------------------------------------------

struct trajectory_columns {
  bool physical = false;  // t, omega1..3
  std::size_t time = 0;
  std::array<std::size_t, 3> value{};
  std::string time_name;  // as in the file
};

std::string column_label(const check_job& job, const std::string& canonical) {
  return job.renamed.at(canonical) ? fmt::format("`{}` (for {} by --columns)", job.names.at(canonical), canonical)
                                   : fmt::format("`{}`", canonical);
}

trajectory_columns find_columns(const check_job& job, const csv_rows& rows) {
  trajectory_columns c;
  const std::string where = fmt::format("{}: line {}", rows.where(), rows.line());
  if (auto tau = rows.column(job.names.at("tau"))) {
    c.time = *tau;
  } else if (auto t = rows.column(job.names.at("t"))) {
    c.physical = true;
    c.time = *t;
  } else {
    throw input_error(fmt::format("{}: the header has no column {} (nor {} for a physical scene)", where,
                                  column_label(job, "tau"), column_label(job, "t")));
  }
  c.time_name = rows.header()[c.time];
  for (int k = 0; k < 3; ++k) {
    const std::string canonical = fmt::format("{}{}", c.physical ? "omega" : "Omega", k + 1);
    const auto col = rows.column(job.names.at(canonical));
    if (!col) throw input_error(fmt::format("{}: the header has no column {}", where, column_label(job, canonical)));
    c.value[k] = *col;
  }
  return c;
}

// ---- the tally ------------------------------------------------------------------------------------

struct tally {
  std::size_t rows = 0;
  std::string first_time, last_time;  // as written in the file
  double max_error = -1;
  std::string max_time;
  std::size_t max_line = 0;
  long double sum_squares = 0;
  std::size_t exceeding = 0;
  std::optional<std::string> first_exceeding_time;
  std::size_t first_exceeding_line = 0;
  // The oracle metrics (IVP Test Set and DiffEqDevTools terms), over rows and components:
  double max_relative = 0;  // max |dy_i| / |y_ref_i| over the components with y_ref_i != 0 (scd)
  double max_mixed = 0;     // max |dy_i| / (atol/rtol + |y_ref_i|) (mescd)
  std::array<double, 3> max_component{};  // max |dy_i| per component
  // c1^2 and c2^2 (Eq. 7) of the trajectory minus the reference's: largest magnitude, and at
  // the last row.
  // Absent (has_invariants false) for a body integrated in the direct form, where Eq. 7 has no
  // meaning.
  bool has_invariants = true;
  double c1_drift_max = 0, c2_drift_max = 0, c1_drift_last = 0, c2_drift_last = 0;
  // The error along the reference's direction of motion (Eq. 5's right-hand side there: a phase
  // error) and across it, largest over the rows; absent without the torque.
  bool has_direction = false;
  double max_along = 0, max_across = 0;
  // Against a certified reference (a `radius` column, docs/certified.md): each row's error is the
  // interval error +- radius. A row fails only when error - radius exceeds the bar, and is
  // uncertain when the bar lies inside its interval.
  bool certified = false;
  double max_radius = 0;
  std::size_t uncertain = 0;
  std::vector<std::size_t> uncertain_lines;  // the first max_listed_lines of them
  static constexpr std::size_t max_listed_lines = 1000;
};

// Streams the per-row errors into an atomic file (so the file appears only when complete).
class errors_writer {
 public:
  errors_writer(const std::optional<std::string>& path) {
    if (path) file_ = std::make_unique<atomic_file>(*path);
  }
  // With a certified reference, a last column `radius`.
  void header(const std::string& time_name, bool certified) {
    if (file_) buffer_ += fmt::format("line,{},error,bar{}\n", time_name, certified ? ",radius" : "");
  }
  void row(std::size_t line, const std::string& time, double error, std::optional<double> bar,
           const std::optional<decimal>& radius) {
    if (!file_) return;
    buffer_ += fmt::format("{},{},{},", line, time, error);
    if (bar) buffer_ += fmt::format("{}", *bar);
    if (radius) buffer_ += "," + radius->text;
    buffer_ += "\n";
    if (buffer_.size() > (1u << 16)) flush();
  }
  void commit() {
    if (!file_) return;
    flush();
    file_->commit();
  }

 private:
  void flush() {
    file_->write(buffer_);
    buffer_.clear();
  }
  std::unique_ptr<atomic_file> file_;
  std::string buffer_;
};

struct check_result {
  tally t;
  std::string time_name;
  std::string reference_text;  // for the table
  nlohmann::ordered_json reference_json;
};

// The oracle metrics of one row (tally's second half). `problem`: the equations, for the
// reference's direction of motion, when known.
template <scalar T>
void record_metrics(const check_job& job, tally& t, const vec3<T>& ref, const vec3<T>& Om,
                    const euler_problem<T>* problem) {
  using std::abs;
  using std::sqrt;
  vec3<T> d;
  for (int i = 0; i < 3; ++i) {
    d[i] = Om[i] - ref[i];
    const double err = static_cast<double>(abs(d[i]));
    t.max_component[i] = std::max(t.max_component[i], err);
    const double y = static_cast<double>(abs(ref[i]));
    if (y > 0) t.max_relative = std::max(t.max_relative, err / y);
    t.max_mixed = std::max(t.max_mixed, err / (job.scd_atol / job.scd_rtol + y));
  }
  const T c1 = (Om[0] * Om[0] + Om[1] * Om[1]) - (ref[0] * ref[0] + ref[1] * ref[1]);
  const T c2 = (Om[1] * Om[1] + Om[2] * Om[2]) - (ref[1] * ref[1] + ref[2] * ref[2]);
  t.c1_drift_last = static_cast<double>(c1);
  t.c2_drift_last = static_cast<double>(c2);
  t.c1_drift_max = std::max(t.c1_drift_max, std::abs(t.c1_drift_last));
  t.c2_drift_max = std::max(t.c2_drift_max, std::abs(t.c2_drift_last));
  if (!problem) return;
  t.has_invariants = problem->normalized();
  vec3<T> v;
  problem->rhs(problem->tau0, ref, v);
  const T speed = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!(speed > 0)) return;  // at rest: no direction of motion (the row is left out of the split)
  t.has_direction = true;
  const T along = (d[0] * v[0] + d[1] * v[1] + d[2] * v[2]) / speed;
  const T across2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - along * along;
  t.max_along = std::max(t.max_along, static_cast<double>(abs(along)));
  t.max_across = std::max(t.max_across, static_cast<double>(across2 > 0 ? sqrt(across2) : T(0)));
}

// `radius`: the reference row's certified radius, if it has one.
template <scalar T>
void record(const check_job& job, tally& t, errors_writer& out, std::size_t line, const decimal& time,
            const vec3<T>& ref, const vec3<T>& Om, const euler_problem<T>* problem,
            const std::optional<decimal>& radius = std::nullopt) {
  const double e = static_cast<double>(eq20_error(ref, Om));
  if (!std::isfinite(e)) throw numerical_failure({outcome_kind::error_non_finite, time.value});
  record_metrics(job, t, ref, Om, problem);
  const double r = radius ? radius->value : 0.0;
  if (radius) t.max_radius = std::max(t.max_radius, r);
  std::optional<double> bar;
  if (job.tol || job.rel_tol) {
    using std::sqrt;
    const double norm = static_cast<double>(sqrt(ref[0] * ref[0] + ref[1] * ref[1] + ref[2] * ref[2]));
    bar = job.tol.value_or(0.0) + job.rel_tol.value_or(0.0) * norm;
    // The true error lies in [e - r, e + r]: failing only if certainly above the bar.
    if (radius && e - r <= *bar && e + r > *bar) {
      ++t.uncertain;
      if (t.uncertain_lines.size() < tally::max_listed_lines) t.uncertain_lines.push_back(line);
    }
    if (e - r > *bar) {
      if (!t.exceeding) {
        t.first_exceeding_time = time.text;
        t.first_exceeding_line = line;
      }
      ++t.exceeding;
    }
  }
  if (!t.rows) t.first_time = time.text;
  t.last_time = time.text;
  ++t.rows;
  if (e > t.max_error) {
    t.max_error = e;
    t.max_time = time.text;
    t.max_line = line;
  }
  t.sum_squares += static_cast<long double>(e) * e;
  out.row(line, time.text, e, bar, radius);
}

// A trajectory row: its time and state, checked (numbers, time >= 0 and increasing).
struct row_reader {
  csv_rows& rows;
  const trajectory_columns& cols;
  std::optional<decimal> previous;
  std::size_t previous_line = 0;

  decimal time() {
    const decimal x = rows.number(cols.time);
    if (x.value < 0)
      throw input_error(fmt::format("{}: line {}: column {} = {} is negative (the reference starts at 0)", rows.where(),
                                    rows.line(), cols.time_name, x.text));
    if (previous && !(x.value > previous->value))
      throw input_error(fmt::format("{}: line {}: column {} = {} does not increase (line {} has {})", rows.where(),
                                    rows.line(), cols.time_name, x.text, previous_line, previous->text));
    previous = x;
    previous_line = rows.line();
    return x;
  }
  std::array<decimal, 3> values() {
    return {rows.number(cols.value[0]), rows.number(cols.value[1]), rows.number(cols.value[2])};
  }
};

// ---- against a scene -------------------------------------------------------------------------------

template <scalar T>
check_result check_against_scene(const check_job& job) {
  const scene& s = job.scn;
  std::optional<physical_scaling<T>> scale;
  if (s.is_physical()) scale.emplace(scaling_of<T>(s));
  trajectory_columns cols;
  auto tau_of = [&](const decimal& x) {
    const T v = x.template to_scalar<T>();
    return cols.physical ? scale->tau_of_t(v) : v;
  };
  auto Omega_of = [&](const std::array<decimal, 3>& d) {
    const vec3<T> v = {d[0].template to_scalar<T>(), d[1].template to_scalar<T>(), d[2].template to_scalar<T>()};
    return cols.physical ? scale->Omega_of_omega(v) : v;
  };

  // Pass 1: validate every row and collect its time in tau (the values are not held).
  std::vector<T> taus;
  {
    std::ifstream in = open_input_file("trajectory", job.trajectory_path);
    csv_rows rows(in, "trajectory " + job.trajectory_path);
    cols = find_columns(job, rows);
    if (cols.physical && !s.is_physical())
      throw input_error(fmt::format("{}: line {}: column `{}` is a physical time, but scene {} is normalized (give "
                                    "tau,Omega1,Omega2,Omega3)",
                                    rows.where(), rows.line(), cols.time_name, s.name));
    if (!cols.physical && uses_direct_form(s))
      throw input_error(fmt::format("{}: line {}: scene {} is integrated in the direct form of Eq. 1 (two moments are "
                                    "equal or nearly so), which has no tau or Omega: give t,omega1,omega2,omega3",
                                    rows.where(), rows.line(), s.name));
    row_reader reader{rows, cols};
    while (rows.next()) {
      taus.push_back(tau_of(reader.time()));
      reader.values();
    }
    if (taus.empty()) throw input_error(fmt::format("{}: no data rows", rows.where()));
  }

  T tau_end = taus.back();
  if (!(tau_end > 0)) tau_end = T(1);  // a trajectory at tau = 0 only
  errors_writer out(job.errors_out);    // an unwritable path fails before the integration
  const euler_problem<T> problem = to_problem<T>(s);

  // Pass 2, during the integration: each row is read again as the reference at its time
  // arrives. Pass 1 checked that the times increase, and their conversion to tau in T is
  // monotone, so the reference is evaluated as its segments are accepted and none is kept
  // (integrate_at would fall back to the dense output otherwise).
  check_result r;
  r.time_name = cols.time_name;
  out.header(cols.time_name, false);
  std::ifstream in = open_input_file("trajectory", job.trajectory_path);
  csv_rows rows(in, "trajectory " + job.trajectory_path);
  row_reader reader{rows, cols};
  const auto changed = [&] { return input_error(fmt::format("{}: the file changed while it was read", rows.where())); };
  const reference_run ref = integrate_at<T>(problem, tau_end, taus, job.settings, "reference",
                                            [&](std::size_t i, const vec3<T>& Omega_ref) {
                                              if (!rows.next()) throw changed();
                                              const decimal time = reader.time();
                                              if (tau_of(time) != taus[i]) throw changed();
                                              record<T>(job, r.t, out, rows.line(), time, Omega_ref,
                                                        Omega_of(reader.values()), &problem);
                                            });
  if (rows.next()) throw changed();
  out.commit();

  r.reference_text = fmt::format("scene {} ({}, computed to tau = {:.6g} in {:.2f} s, {} segments)", s.name,
                                 job.precision.name(), static_cast<double>(tau_end), ref.wall_seconds,
                                 ref.stats.segments);
  r.reference_json = {{"source", "scene"},
                      {"path", job.reference_path},
                      {"scene", s.name},
                      {"precision", job.precision.name()},
                      {"tau_end", static_cast<double>(tau_end)},
                      {"seconds", ref.wall_seconds},
                      {"segments", ref.stats.segments}};
  return r;
}

// ---- against a reference file ---------------------------------------------------------------------

bool same_time(double a, double b) { return std::abs(a - b) <= time_match_rel * std::max(std::abs(a), std::abs(b)); }

// Walks a reference file's rows (times increasing) alongside a trajectory's: each trajectory
// time must be one of the reference's sample times.
class reference_cursor {
 public:
  reference_cursor(reference_csv_reader& ref, std::size_t time_column) : ref_(ref), time_(time_column) {}

  // Advances to the sample at `time`; input_error naming the nearest samples if there is none.
  void seek(const decimal& time, const csv_rows& rows, const std::string& time_name) {
    while (load() && current_->value < time.value && !same_time(current_->value, time.value)) consume();
    if (!pending_ || !same_time(current_->value, time.value)) {
      std::string nearest;
      if (below_) nearest += fmt::format("{} (line {})", below_->text, below_line_);
      if (pending_) nearest += fmt::format("{}{} (line {})", nearest.empty() ? "" : " and ", current_->text, current_line_);
      throw input_error(fmt::format("{}: line {}: {} = {} is not a sample time of {}{}", rows.where(), rows.line(),
                                    time_name, time.text, ref_.rows().where(),
                                    nearest.empty() ? " (it has no samples there)" : "; nearest: " + nearest));
    }
    consume();
  }

 private:
  // Reads the next reference row unless one is pending; false at the end of the file.
  bool load() {
    if (pending_) return true;
    csv_rows& r = ref_.rows();
    if (!r.next()) return false;
    const decimal t = r.number(time_);
    if (current_ && !(t.value > current_->value))
      throw input_error(fmt::format("{}: line {}: column {} = {} does not increase", r.where(), r.line(),
                                    r.header()[time_], t.text));
    current_ = t;
    current_line_ = r.line();
    pending_ = true;
    return true;
  }
  // The current row is matched or passed: no later trajectory row can match it.
  void consume() {
    pending_ = false;
    below_ = current_;
    below_line_ = current_line_;
  }

  reference_csv_reader& ref_;
  std::size_t time_;
  std::optional<decimal> current_;  // the last reference time read, and its line
  std::size_t current_line_ = 0;
  bool pending_ = false;            // the current row is neither matched nor passed yet
  std::optional<decimal> below_;    // the last reference time consumed, and its line
  std::size_t below_line_ = 0;
};

// The physical scaling of the reference's scene (from its "# scene_text:" lines).
template <scalar T>
physical_scaling<T> scaling_of_reference(const reference_csv_reader& ref) {
  const std::string& where = ref.rows().where();
  if (ref.metadata().scene_text.empty())
    throw input_error(fmt::format("{}: no `# scene_text:` lines, so omega cannot be mapped to Omega", where));
  const scene s = parse_scene(ref.metadata().scene_text, where + " (scene_text)");
  if (!s.is_physical()) throw input_error(fmt::format("{}: the scene is not physical", where));
  return scaling_of<T>(s);
}

void describe_reference_file(const check_job& job, const reference_metadata& meta, check_result& r) {
  const auto& error = meta.estimated_max_error;
  r.reference_text = fmt::format("file {} (scene {}, {}, estimated max error {})", job.reference_path,
                                 meta.scene_name.empty() ? "?" : meta.scene_name, meta.precision.name(),
                                 error ? error->text : "-");
  r.reference_json = {
      {"source", "file"},
      {"path", job.reference_path},
      {"scene", meta.scene_name.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(meta.scene_name)},
      {"precision", meta.precision.name()},
      {"estimated_max_error", number_or_null(error ? std::optional<double>(error->value) : std::nullopt)}};
}

template <scalar T>
check_result check_against_file(const check_job& job, reference_csv_reader& ref) {
  std::ifstream in = open_input_file("trajectory", job.trajectory_path);
  csv_rows rows(in, "trajectory " + job.trajectory_path);
  const trajectory_columns cols = find_columns(job, rows);
  // The reference's columns are always the canonical names of `eulervop reference`.
  const std::size_t ref_time =
      cols.physical ? ref.column("t", " (the trajectory has physical times; the reference is normalized)")
                    : ref.column("tau");
  std::optional<physical_scaling<T>> scale;
  if (cols.physical) scale.emplace(scaling_of_reference<T>(ref));
  // The equations, for the direction of motion: from the reference's scene text, if it has one.
  std::optional<euler_problem<T>> problem;
  if (!ref.metadata().scene_text.empty())
    problem = to_problem<T>(parse_scene(ref.metadata().scene_text, ref.rows().where() + " (scene_text)"));

  check_result r;
  r.time_name = cols.time_name;
  // A certified reference: each row's radius (of Omega, the state compared here).
  const std::optional<std::size_t> radius_column = ref.rows().column("radius");
  r.t.certified = radius_column.has_value();
  errors_writer out(job.errors_out);
  out.header(cols.time_name, r.t.certified);
  row_reader reader{rows, cols};
  reference_cursor cursor(ref, ref_time);
  while (rows.next()) {
    const decimal time = reader.time();
    const std::array<decimal, 3> d = reader.values();
    cursor.seek(time, rows, cols.time_name);
    vec3<T> Om = {d[0].template to_scalar<T>(), d[1].template to_scalar<T>(), d[2].template to_scalar<T>()};
    if (scale) Om = scale->Omega_of_omega(Om);
    std::optional<decimal> radius;
    if (radius_column) radius = ref.rows().number(*radius_column);
    record<T>(job, r.t, out, rows.line(), time, ref.template Omega<T>(), Om, problem ? &*problem : nullptr, radius);
  }
  if (!r.t.rows) throw input_error(fmt::format("{}: no data rows", rows.where()));
  out.commit();
  describe_reference_file(job, ref.metadata(), r);
  return r;
}

// ---- output -----------------------------------------------------------------------------------------

double time_value(const std::string& text) { return std::strtod(text.c_str(), nullptr); }

// -log10 of a largest error: significant correct digits (infinite for an exact match).
double digits_of(double max_error) {
  return max_error > 0 ? -std::log10(max_error) : std::numeric_limits<double>::infinity();
}

int report(const check_job& job, const check_result& r, std::ostream& standard_output) {
  const tally& t = r.t;
  const double rms = static_cast<double>(std::sqrt(t.sum_squares / static_cast<long double>(t.rows)));
  const bool has_bar = job.tol || job.rel_tol;
  const bool pass = t.exceeding == 0;
  if (job.json) {
    nlohmann::ordered_json j;
    j["trajectory"] = job.trajectory_path;
    j["reference"] = r.reference_json;
    j["time_column"] = r.time_name;
    j["rows"] = t.rows;
    j["first_time"] = time_value(t.first_time);
    j["last_time"] = time_value(t.last_time);
    j["max_error"] = t.max_error;
    j["max_error_time"] = time_value(t.max_time);
    j["max_error_line"] = t.max_line;
    j["rms_error"] = rms;
    j["tol"] = number_or_null(job.tol);
    j["rel_tol"] = number_or_null(job.rel_tol);
    j["exceeding_rows"] = t.exceeding;
    j["first_exceeding_time"] = t.first_exceeding_time ? nlohmann::ordered_json(time_value(*t.first_exceeding_time))
                                                       : nlohmann::ordered_json(nullptr);
    j["first_exceeding_line"] = t.first_exceeding_time ? nlohmann::ordered_json(t.first_exceeding_line)
                                                       : nlohmann::ordered_json(nullptr);
    j["pass"] = pass;
    // Against a certified reference: the rows whose verdict the radius leaves open.
    j["certified_reference"] = t.certified;
    j["max_reference_radius"] = t.certified ? nlohmann::ordered_json(t.max_radius) : nlohmann::ordered_json(nullptr);
    j["uncertain_rows"] = t.certified && has_bar ? nlohmann::ordered_json(t.uncertain) : nlohmann::ordered_json(nullptr);
    j["uncertain_lines"] = t.certified && has_bar ? nlohmann::ordered_json(t.uncertain_lines) : nlohmann::ordered_json(nullptr);
    j["all_rows_certain"] = t.certified && has_bar ? nlohmann::ordered_json(t.uncertain == 0) : nlohmann::ordered_json(nullptr);
    const auto digits = [](double max_error) {
      const double d = digits_of(max_error);
      return std::isfinite(d) ? nlohmann::ordered_json(d) : nlohmann::ordered_json(nullptr);  // null: exact
    };
    j["scd"] = digits(t.max_relative);
    j["mescd"] = digits(t.max_mixed);
    j["scd_atol"] = job.scd_atol;
    j["scd_rtol"] = job.scd_rtol;
    j["max_component_errors"] = {t.max_component[0], t.max_component[1], t.max_component[2]};
    const auto drift = [&](double max, double last) {
      return t.has_invariants ? nlohmann::ordered_json{{"max", max}, {"last", last}} : nlohmann::ordered_json(nullptr);
    };
    j["c1_squared_drift"] = drift(t.c1_drift_max, t.c1_drift_last);
    j["c2_squared_drift"] = drift(t.c2_drift_max, t.c2_drift_last);
    j["max_error_along_motion"] = t.has_direction ? nlohmann::ordered_json(t.max_along) : nlohmann::ordered_json(nullptr);
    j["max_error_across_motion"] = t.has_direction ? nlohmann::ordered_json(t.max_across) : nlohmann::ordered_json(nullptr);
    standard_output << j.dump(2) << "\n";
  } else {
    fmt::memory_buffer b;
    auto put = [&]<class... Args>(fmt::format_string<Args...> f, Args&&... args) {
      fmt::format_to(std::back_inserter(b), f, std::forward<Args>(args)...);
    };
    put("trajectory: {} ({} rows, {} from {} to {})\n", job.trajectory_path, t.rows, r.time_name, t.first_time,
        t.last_time);
    put("reference: {}\n", r.reference_text);
    put("max error: {} at {} = {} (line {})\n", t.max_error, r.time_name, t.max_time, t.max_line);
    put("rms error: {:.6e}\n", rms);
    put("per component: max |dOmega_i| = {:.3e}, {:.3e}, {:.3e}\n", t.max_component[0], t.max_component[1],
        t.max_component[2]);
    put("scd: {:.2f}   mescd: {:.2f} (atol {}, rtol {})\n", digits_of(t.max_relative), digits_of(t.max_mixed),
        job.scd_atol, job.scd_rtol);
    if (t.has_invariants)
      put("invariant drift (Eq. 7, against the reference): c1^2 max {:.3e} last {:.3e}; c2^2 max {:.3e} last {:.3e}\n",
          t.c1_drift_max, t.c1_drift_last, t.c2_drift_max, t.c2_drift_last);
    else
      put("invariant drift: none (the body is integrated in the direct form of Eq. 1, where Eq. 7 does not apply)\n");
    if (t.has_direction)
      put("error along the motion (phase): max {:.3e}; across it: max {:.3e}\n", t.max_along, t.max_across);
    if (has_bar) {
      std::string bar;
      if (job.tol) bar = fmt::format("{}", *job.tol);
      if (job.rel_tol) bar += fmt::format("{}{} |Omega_ref|", bar.empty() ? "" : " + ", *job.rel_tol);
      put("tolerance: error <= {}\n", bar);
      if (t.certified)
        put("certified reference: each error is +- its row's radius (max {:.3g}); a row fails only if error - "
            "radius > bar; {} of {} rows uncertain\n",
            t.max_radius, t.uncertain, t.rows);
      if (pass)
        put("result: PASS (every row within tolerance)\n");
      else
        put("result: FAIL ({} of {} rows exceed; first at {} = {}, line {})\n", t.exceeding, t.rows, r.time_name,
            *t.first_exceeding_time, t.first_exceeding_line);
    } else {
      put("tolerance: none given (--tol, --rel-tol)\n");
    }
    standard_output << fmt::to_string(b);
  }
  standard_output << std::flush;
  return pass ? exit_success : exit_check_outside;
}

}  // namespace

CLI::App* add_check_command(CLI::App& app, check_options& o) {
  CLI::App* sub = app.add_subcommand(
      "check", "Check another tool's trajectory (CSV) against the reference: Eq. 20 errors, pass/fail by tolerance");
  sub->add_option("reference", o.reference, "A scene (.toml), or a reference CSV written by `eulervop reference`")
      ->required()
      ->type_name("SCENE_OR_REFERENCE");
  sub->add_option("trajectory", o.trajectory, "The trajectory: CSV with header tau,Omega1,Omega2,Omega3 (or t,omega1..3)")
      ->required()
      ->type_name("TRAJECTORY");
  auto bind = [&](const std::string& name, std::optional<std::string>& target, const std::string& help) {
    return add_text_option(*sub, name, target, help);
  };
  bind("--columns", o.columns, "Column names of the file: tau=time,Omega1=w1,... (default: the canonical names)")
      ->type_name("MAP");
  bind("--precision", o.precision, "Scene only: double, quad or mpfr:BITS (default: the scene's [reference])")
      ->type_name("P");
  bind("--tol", o.tol, "Pass if every row's Eq. 20 error <= ABS (+ R |Omega_ref| with --rel-tol)")->type_name("ABS");
  bind("--rel-tol", o.rel_tol, "Pass if every row's Eq. 20 error <= R |Omega_ref| (+ ABS with --tol)")->type_name("R");
  bind("--errors-out", o.errors_out, "Write the per-row errors to FILE (CSV: line,time,error,bar)")->type_name("FILE");
  bind("--format", o.format, "Standard output: table (default) or json")->type_name("F");
  bind("--scd-atol", o.scd_atol, "atol of the mixed error |dy| / (atol/rtol + |y_ref|) behind mescd (default 1e-12)")
      ->type_name("A");
  bind("--scd-rtol", o.scd_rtol, "rtol of that mixed error (default 1e-12)")->type_name("R");
  return sub;
}

int run_check(const check_options& options, std::ostream& standard_output) {
  const check_job job = make_job(options);
  if (job.from_scene)
    return with_scalar(job.precision,
                       [&](auto zero) { return report(job, check_against_scene<decltype(zero)>(job), standard_output); });
  std::ifstream in = open_input_file("reference", job.reference_path);
  reference_csv_reader ref(in, "reference " + job.reference_path);
  return with_scalar(ref.metadata().reading_precision(), [&](auto zero) -> int {
    using T = decltype(zero);
    if constexpr (std::is_same_v<T, double>)
      throw std::logic_error("a reference file is read in quad or MPFR");
    else
      return report(job, check_against_file<T>(job, ref), standard_output);
  });
}

}  // namespace eulervop::app
