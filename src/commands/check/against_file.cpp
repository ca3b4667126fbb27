#include "commands/check/against_file.hpp"

#include "commands/check/reference_table.hpp"
#include "commands/check/scene_terms.hpp"
#include "commands/check/trajectory_columns.hpp"
#include "commands/reference/held_reference.hpp"
#include "compute/with_scalar.hpp"
#include "io/csv_rows.hpp"
#include "io/output_cells.hpp"
#include "io/reference_csv.hpp"

#include <eulervop/model/physical_scaling.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <cmath>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <type_traits>

namespace eulervop::app {

namespace {

// Trajectory times must equal reference sample times to this relative difference.
constexpr double time_match_rel = 1e-12;

bool same_time(double a, double b) { return std::abs(a - b) <= time_match_rel * std::max(std::abs(a), std::abs(b)); }

// Walks a reference's rows (times increasing) alongside a trajectory's: each trajectory time
// must be one of the reference's sample times: the same binary64 number when the reference was
// sampled at binary64 times, else the same to time_match_rel (a decimal in both files).
template <scalar T>
class reference_cursor {
 public:
  reference_cursor(reference_table<T>& ref, std::size_t time_column) : ref_(ref), time_(time_column) {}

  // Advances to the sample at `time`; input_error naming the nearest samples if there is none.
  void seek(const decimal& time, const table_rows& rows, const std::string& time_name) {
    while (load() && current_->value < time.value && !matches(*current_, time)) consume();
    if (!pending_ || !matches(*current_, time)) {
      std::string nearest;
      if (below_) nearest += fmt::format("{} (line {})", shown(*below_), below_line_);
      if (pending_)
        nearest += fmt::format("{}{} (line {})", nearest.empty() ? "" : " and ", shown(*current_), current_line_);
      throw input_error(fmt::format("{}: line {}: {} = {} is not a sample time of {}{}", rows.where(), rows.line(),
                                    time_name, time.text, ref_.where(),
                                    nearest.empty() ? " (it has no samples there)" : "; nearest: " + nearest));
    }
    consume();
  }

 private:
  bool matches(const decimal& sample, const decimal& time) const {
    return ref_.binary_times() ? sample.value == time.value : same_time(sample.value, time.value);
  }
  // A sample's time in a message: binary64 samples by every digit that tells them apart.
  std::string shown(const decimal& sample) const {
    return ref_.binary_times() ? fmt::format("{:.17g}", sample.value) : sample.text;
  }
  // Reads the next reference row unless one is pending; false at the end of the file.
  bool load() {
    if (pending_) return true;
    if (!ref_.next()) return false;
    const decimal t = ref_.number(time_);
    if (current_ && !(t.value > current_->value))
      throw input_error(fmt::format("{}: line {}: column {} = {} does not increase", ref_.where(), ref_.line(),
                                    ref_.header()[time_], t.text));
    current_ = t;
    current_line_ = ref_.line();
    pending_ = true;
    return true;
  }
  // The current row is matched or passed: no later trajectory row can match it.
  void consume() {
    pending_ = false;
    below_ = current_;
    below_line_ = current_line_;
  }

  reference_table<T>& ref_;
  std::size_t time_;
  std::optional<decimal> current_;  // the last reference time read, and its line
  std::size_t current_line_ = 0;
  bool pending_ = false;            // the current row is neither matched nor passed yet
  std::optional<decimal> below_;    // the last reference time consumed, and its line
  std::size_t below_line_ = 0;
};

// A reference file, read as it streams.
template <scalar T>
class file_table final : public reference_table<T> {
 public:
  explicit file_table(reference_csv_reader& ref) : ref_(ref) {}
  const std::vector<std::string>& header() const override { return ref_.rows().header(); }
  const reference_metadata& metadata() const override { return ref_.metadata(); }
  const std::string& where() const override { return ref_.rows().where(); }
  bool next() override { return ref_.rows().next(); }
  std::size_t line() const override { return ref_.rows().line(); }
  decimal number(std::size_t c) const override { return ref_.rows().number(c); }
  T value(std::size_t c) const override { return ref_.rows().number(c).template to_scalar<T>(); }

 private:
  reference_csv_reader& ref_;
};

// A reference held in memory: its rows numbered as the lines of its CSV would be (after the
// metadata and header lines).
template <scalar T>
class held_table final : public reference_table<T> {
 public:
  held_table(const held_reference& ref, std::string where) : ref_(ref), where_(std::move(where)) {
    const std::string header = reference_csv_header(ref.metadata(), ref.layout());
    first_line_ = static_cast<std::size_t>(std::count(header.begin(), header.end(), '\n'));
  }
  const std::vector<std::string>& header() const override { return ref_.columns(); }
  const reference_metadata& metadata() const override { return ref_.metadata(); }
  const std::string& where() const override { return where_; }
  bool next() override { return ++row_ <= ref_.size(); }
  std::size_t line() const override { return first_line_ + row_; }
  decimal number(std::size_t c) const override {
    if (ref_.kinds()[c].kind == held_reference::cell_kind::time) return binary_number(ref_.times()[row_ - 1]);
    const std::string text = ref_.text(row_ - 1, c);
    return decimal{text, std::strtod(text.c_str(), nullptr)};
  }
  T value(std::size_t c) const override { return ref_.template value<T>(row_ - 1, c); }

 private:
  const held_reference& ref_;
  std::string where_;
  std::size_t first_line_ = 0;
  std::size_t row_ = 0;
};

// The physical scaling of the reference's scene (from its "# scene_text:" lines).
template <scalar T>
physical_scaling<T> scaling_of_reference(const reference_table<T>& ref) {
  const std::string& where = ref.where();
  if (ref.metadata().scene_text.empty())
    throw input_error(fmt::format("{}: no `# scene_text:` lines, so omega cannot be mapped to Omega", where));
  const scene s = parse_scene(ref.metadata().scene_text, where + " (scene_text)");
  if (!s.is_physical()) throw input_error(fmt::format("{}: the scene is not physical", where));
  return scaling_of<T>(s);
}

// The estimated error of `# estimated_max_error` (--verify) is of the integrator's variables, the
// normalized ones of Eq. 4 for a physical scene, not the compared ones: it carries its unit. A
// body's file also has it in rad/s (`# estimated_max_error_omega`), which the table adds beside
// errors in rad/s where the first figure is not already that one (the direct form's).
void describe_reference_file(const check_job& job, const reference_metadata& meta, check_result& r) {
  const auto& error = meta.estimated_max_error;
  const auto& omega = meta.estimated_max_error_omega;
  const std::string& unit = r.scene.estimated_error_unit;
  const bool omega_apart = omega && r.terms.state_unit == "rad/s" && unit != "rad/s";
  r.reference_text = fmt::format("{} (scene {}, {}, {})", job.held ? job.reference_path : "file " + job.reference_path,
                                 meta.scene_name.empty() ? "?" : meta.scene_name, meta.precision.name(),
                                 error ? fmt::format("estimated max error {:.3e} {}{}", error->value,
                                                     r.scene.estimated_error_label,
                                                     omega_apart ? fmt::format(", {:.3e} rad/s", omega->value) : "")
                                       : std::string("no estimated max error: made without --verify"));
  r.reference_json = {
      {"source", job.held ? "memory" : "file"},
      {"path", job.held ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(job.reference_path)},
      {"scene", meta.scene_name.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(meta.scene_name)},
      {"precision", meta.precision.name()},
      {"estimated_max_error", number_or_null(error ? std::optional<double>(error->value) : std::nullopt)},
      {"estimated_max_error_unit", error ? nlohmann::ordered_json(unit) : nlohmann::ordered_json(nullptr)},
      {"estimated_max_error_omega", number_or_null(omega ? std::optional<double>(omega->value) : std::nullopt)},
      {"estimated_max_error_omega_unit", omega ? nlohmann::ordered_json("rad/s") : nlohmann::ordered_json(nullptr)}};
}

// The reference's form, from its columns, for a file that does not give its scene.
template <scalar T>
integrated_form form_of_columns(const reference_table<T>& ref) {
  if (ref.column("y1")) return integrated_form::coefficient;
  if (!ref.column("tau")) return integrated_form::direct;
  return integrated_form::normalized;
}

// The names a trajectory is compared by against this file: its own time and state.
template <scalar T>
expected_names expected_of(const reference_table<T>& ref) {
  if (ref.column("omega1")) return {"t", "omega"};
  if (ref.column("y1")) return {"t", "y"};
  return {};
}

// The reference file's columns that a trajectory with columns `cols` is compared with, and the
// variables of the comparison; the tally's flags (attitude, certified) set in `r`.
template <scalar T>
struct compared_columns {
  std::size_t time = 0;
  std::array<std::size_t, 3> state{};  // the integrator's state: Omega, omega (direct form) or y
  compared_variables<T> vars;
  std::optional<std::array<std::size_t, 3>> omega;  // physical columns: the file's omega
  std::optional<std::array<std::size_t, 4>> q;      // the attitude compared
  std::optional<std::size_t> radius;                 // a certified reference's radius of the compared state
};

template <scalar T>
compared_columns<T> compared_columns_of(const check_job& job, const reference_table<T>& ref, const table_rows& rows,
                                          const trajectory_columns& cols, check_result& r) {
  compared_columns<T> c;
  // The reference's columns are always the canonical names of `eulervop reference`.
  c.time = cols.physical ? ref.required("t", " (the trajectory has physical times; the reference is normalized)")
                         : ref.required("tau");
  if (cols.physical && cols.state == "omega" && !ref.column("omega1").has_value())
    throw input_error(fmt::format("{}: the trajectory has omega1..3, the reference has not", rows.where()));
  // Physical columns against a physical reference with tau and Omega: compared in rad/s against
  // the file's omega columns, with its Omega for the normalized measure.
  const char* state = ref.column("Omega1") ? "Omega" : ref.column("omega1") ? "omega" : ref.column("y1") ? "y" : "Omega";
  for (int k = 0; k < 3; ++k) c.state[k] = ref.required(fmt::format("{}{}", state, k + 1));
  if (cols.physical && ref.column("tau")) {
    c.vars = compared_variables<T>(scaling_of_reference<T>(ref));
    c.omega = {ref.required("omega1"), ref.required("omega2"), ref.required("omega3")};
  }
  r.time_name = cols.time_name;
  r.terms = terms_of(cols, cols.state == "omega", c.vars.physical());
  // The attitude: the reference's q0..q3 (a file of a scene with [initial] q), compared when the
  // trajectory has them too.
  r.t.reference_attitude = ref.column("q0").has_value();
  require_attitude_match(job, cols, rows, r.t.reference_attitude, ref.where(), "no columns q0..q3");
  r.t.attitude = cols.q.has_value();
  if (r.t.attitude) c.q = {ref.required("q0"), ref.required("q1"), ref.required("q2"), ref.required("q3")};
  // A certified reference: each row's radius, of the state compared (radius_omega of omega, which
  // a body in the direct form has as its only radius of the rates).
  c.radius = ref.column(c.vars.physical() || cols.state == "omega" ? "radius_omega" : "radius");
  r.t.certified = c.radius.has_value();
  return c;
}

// The rows of the trajectory against the reference's, with the equations `motion` (of the scene
// text's problem, or null) for the direction of motion.
template <scalar T>
check_result check_rows(const check_job& job, reference_table<T>& ref, const scene* scn, const motion_function* motion) {
  const std::unique_ptr<table_rows> trajectory = job.open_trajectory();
  table_rows& rows = *trajectory;
  const trajectory_columns cols = find_columns(job, rows, expected_of(ref));
  check_result r;
  const compared_columns<T> c = compared_columns_of<T>(job, ref, rows, cols, r);
  r.scene = scn ? scene_terms_of(*scn, cols) : unknown_scene_terms(form_of_columns(ref));
  if (cols.q)
    for (int k = 0; k < 4; ++k) r.q_columns[k] = rows.header()[(*cols.q)[k]];
  const compared_variables<T>& vars = c.vars;
  errors_writer out(job.errors_out);
  out.header(cols.time_name, r.t.certified, r.t.attitude);
  row_reader reader{rows, cols};
  reference_cursor<T> cursor(ref, c.time);
  while (rows.next()) {
    const decimal time = reader.time();
    const std::array<decimal, 3> d = reader.values();
    std::optional<std::array<decimal, 4>> a;
    if (cols.q) a = reader.attitude();
    cursor.seek(time, rows, cols.time_name);
    const vec3<T> traj = vec3_of<T>(d);
    const T tau = vars.tau_of(time.template to_scalar<T>());
    const vec3<T> reference_state = ref.values(c.state);
    const row_states<T> states =
        c.omega ? vars.states(reference_state, ref.values(*c.omega), traj) : vars.states(reference_state, traj);
    std::optional<decimal> radius;
    if (c.radius) radius = ref.number(*c.radius);
    std::optional<attitude_pair<T>> q;
    if (c.q) {
      const std::array<std::size_t, 4>& k = *c.q;
      q = attitude_pair<T>{quaternion<T>{ref.value(k[0]), ref.value(k[1]), ref.value(k[2]), ref.value(k[3])},
                           quaternion_of<T>(*a)};
    }
    record<T>(job, r.t, out, rows.line(), time, states, vars, motion, tau, radius, q ? &*q : nullptr);
  }
  if (!r.t.rows) throw input_error(fmt::format("{}: no data rows", rows.where()));
  out.commit();
  describe_reference_file(job, ref.metadata(), r);
  return r;
}

// The equations, for the direction of motion: from the reference's scene text, if it has one
// and its rates are a problem of their own (not with a torque of the attitude, which needs q).
template <scalar T>
check_result check_in(const check_job& job, reference_table<T>& ref) {
  if (ref.metadata().scene_text.empty()) return check_rows<T>(job, ref, nullptr, nullptr);
  const scene s = parse_scene(ref.metadata().scene_text, ref.where() + " (scene_text)");
  const std::optional<motion_function> motion = motion_of(s);
  return check_rows<T>(job, ref, &s, motion ? &*motion : nullptr);
}

}  // namespace

check_result check_against_file(const check_job& job) {
  if (job.held) {  // in memory, in its own precision
    return with_scalar(job.held->precision(), [&](auto zero) {
      held_table<decltype(zero)> ref(*job.held, job.reference_path);
      return check_in<decltype(zero)>(job, ref);
    });
  }
  std::ifstream in = open_input_file("reference", job.reference_path);
  reference_csv_reader file(in, "reference " + job.reference_path);
  return with_scalar(file.metadata().reading_precision(), [&](auto zero) -> check_result {
    using T = decltype(zero);
    if constexpr (std::is_same_v<T, double>) {
      throw std::logic_error("a reference file is read in quad or MPFR");
    } else {
      file_table<T> ref(file);
      return check_in<T>(job, ref);
    }
  });
}

}  // namespace eulervop::app
