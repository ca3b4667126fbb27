#include "commands/check/against_file.hpp"

#include "commands/check/scene_terms.hpp"
#include "commands/check/trajectory_columns.hpp"
#include "compute/with_scalar.hpp"
#include "io/csv_rows.hpp"
#include "io/output_cells.hpp"
#include "io/reference_csv.hpp"

#include <eulervop/model/physical_scaling.hpp>

#include <fmt/format.h>

#include <algorithm>
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
      if (pending_)
        nearest += fmt::format("{}{} (line {})", nearest.empty() ? "" : " and ", current_->text, current_line_);
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

// The estimated error of `# estimated_max_error` (--verify) is of the integrator's variables, the
// normalized ones of Eq. 4 for a physical scene, not the compared ones: it carries its unit. A
// body's file also has it in rad/s (`# estimated_max_error_omega`), which the table adds beside
// errors in rad/s where the first figure is not already that one (the direct form's).
void describe_reference_file(const check_job& job, const reference_metadata& meta, check_result& r) {
  const auto& error = meta.estimated_max_error;
  const auto& omega = meta.estimated_max_error_omega;
  const std::string& unit = r.scene.estimated_error_unit;
  const bool omega_apart = omega && r.terms.state_unit == "rad/s" && unit != "rad/s";
  r.reference_text = fmt::format("file {} (scene {}, {}, {})", job.reference_path,
                                 meta.scene_name.empty() ? "?" : meta.scene_name, meta.precision.name(),
                                 error ? fmt::format("estimated max error {:.3e} {}{}", error->value,
                                                     r.scene.estimated_error_label,
                                                     omega_apart ? fmt::format(", {:.3e} rad/s", omega->value) : "")
                                       : std::string("no estimated max error: made without --verify"));
  r.reference_json = {
      {"source", "file"},
      {"path", job.reference_path},
      {"scene", meta.scene_name.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(meta.scene_name)},
      {"precision", meta.precision.name()},
      {"estimated_max_error", number_or_null(error ? std::optional<double>(error->value) : std::nullopt)},
      {"estimated_max_error_unit", error ? nlohmann::ordered_json(unit) : nlohmann::ordered_json(nullptr)},
      {"estimated_max_error_omega", number_or_null(omega ? std::optional<double>(omega->value) : std::nullopt)},
      {"estimated_max_error_omega_unit", omega ? nlohmann::ordered_json("rad/s") : nlohmann::ordered_json(nullptr)}};
}

// The reference's form, from its columns, for a file that does not give its scene.
integrated_form form_of_columns(const csv_rows& ref) {
  if (ref.column("y1")) return integrated_form::coefficient;
  if (!ref.column("tau")) return integrated_form::direct;
  return integrated_form::normalized;
}

// The names a trajectory is compared by against this file: its own time and state.
expected_names expected_of(const csv_rows& ref) {
  if (ref.column("omega1")) return {"t", "omega"};
  if (ref.column("y1")) return {"t", "y"};
  return {};
}

// The reference file's columns that a trajectory with columns `cols` is compared with, and the
// variables of the comparison; the tally's flags (attitude, certified) set in `r`.
template <scalar T>
struct reference_columns {
  std::size_t time = 0;
  compared_variables<T> vars;
  std::optional<std::array<std::size_t, 3>> omega;  // physical columns: the file's omega
  std::optional<std::array<std::size_t, 4>> q;      // the attitude compared
  std::optional<std::size_t> radius;                 // a certified reference's radius of the compared state
};

template <scalar T>
reference_columns<T> reference_columns_of(const check_job& job, reference_csv_reader& ref, const csv_rows& rows,
                                          const trajectory_columns& cols, check_result& r) {
  reference_columns<T> c;
  // The reference's columns are always the canonical names of `eulervop reference`.
  c.time = cols.physical ? ref.column("t", " (the trajectory has physical times; the reference is normalized)")
                         : ref.column("tau");
  if (cols.physical && cols.state == "omega" && !ref.rows().column("omega1").has_value())
    throw input_error(fmt::format("{}: the trajectory has omega1..3, the reference has not", rows.where()));
  // Physical columns against a physical reference with tau and Omega: compared in rad/s against
  // the file's omega columns, with its Omega for the normalized measure.
  if (cols.physical && ref.rows().column("tau")) {
    c.vars = compared_variables<T>(scaling_of_reference<T>(ref));
    c.omega = {ref.column("omega1"), ref.column("omega2"), ref.column("omega3")};
  }
  r.time_name = cols.time_name;
  r.terms = terms_of(cols, cols.state == "omega", c.vars.physical());
  // The attitude: the reference's q0..q3 (a file of a scene with [initial] q), compared when the
  // trajectory has them too.
  r.t.reference_attitude = ref.rows().column("q0").has_value();
  require_attitude_match(job, cols, rows, r.t.reference_attitude, "reference " + job.reference_path,
                         "no columns q0..q3");
  r.t.attitude = cols.q.has_value();
  if (r.t.attitude) c.q = {ref.column("q0"), ref.column("q1"), ref.column("q2"), ref.column("q3")};
  // A certified reference: each row's radius, of the state compared (radius_omega of omega, which
  // a body in the direct form has as its only radius of the rates).
  c.radius = ref.rows().column(c.vars.physical() || cols.state == "omega" ? "radius_omega" : "radius");
  r.t.certified = c.radius.has_value();
  return c;
}

// The rows of the trajectory against the reference file's, with the equations `problem` (a
// pointer to the scene text's problem, or to nothing) for the direction of motion.
template <scalar T, class P>
check_result check_rows(const check_job& job, reference_csv_reader& ref, const scene* scn, const P* problem) {
  std::ifstream in = open_input_file("trajectory", job.trajectory_path);
  csv_rows rows(in, "trajectory " + job.trajectory_path);
  const trajectory_columns cols = find_columns(job, rows, expected_of(ref.rows()));
  check_result r;
  const reference_columns<T> c = reference_columns_of<T>(job, ref, rows, cols, r);
  r.scene = scn ? scene_terms_of(*scn, cols) : unknown_scene_terms(form_of_columns(ref.rows()));
  if (cols.q)
    for (int k = 0; k < 4; ++k) r.q_columns[k] = rows.header()[(*cols.q)[k]];
  const compared_variables<T>& vars = c.vars;
  errors_writer out(job.errors_out);
  out.header(cols.time_name, r.t.certified, r.t.attitude);
  row_reader reader{rows, cols};
  reference_cursor cursor(ref, c.time);
  while (rows.next()) {
    const decimal time = reader.time();
    const std::array<decimal, 3> d = reader.values();
    std::optional<std::array<decimal, 4>> a;
    if (cols.q) a = reader.attitude();
    cursor.seek(time, rows, cols.time_name);
    const vec3<T> traj = vec3_of<T>(d);
    const T tau = vars.tau_of(time.template to_scalar<T>());
    const row_states<T> states = c.omega ? vars.states(ref.template Omega<T>(), ref.template columns<T>(*c.omega), traj)
                                         : vars.states(ref.template Omega<T>(), traj);
    std::optional<decimal> radius;
    if (c.radius) radius = ref.rows().number(*c.radius);
    std::optional<attitude_pair<T>> q;
    if (c.q) {
      const csv_rows& f = ref.rows();
      const std::array<std::size_t, 4>& k = *c.q;
      q = attitude_pair<T>{quaternion_of<T>({f.number(k[0]), f.number(k[1]), f.number(k[2]), f.number(k[3])}),
                           quaternion_of<T>(*a)};
    }
    record<T>(job, r.t, out, rows.line(), time, states, vars, problem, tau, radius, q ? &*q : nullptr);
  }
  if (!r.t.rows) throw input_error(fmt::format("{}: no data rows", rows.where()));
  out.commit();
  describe_reference_file(job, ref.metadata(), r);
  return r;
}

// The equations, for the direction of motion: from the reference's scene text, if it has one
// and its rates are a problem of their own (not with a torque of the attitude, which needs q).
template <scalar T>
check_result check_in(const check_job& job, reference_csv_reader& ref) {
  const auto* none = static_cast<const euler_problem<T>*>(nullptr);
  if (ref.metadata().scene_text.empty()) return check_rows<T>(job, ref, nullptr, none);
  const scene s = parse_scene(ref.metadata().scene_text, ref.rows().where() + " (scene_text)");
  if (s.couples_attitude()) return check_rows<T>(job, ref, &s, none);
  return with_problem<T>(s, [&](const auto& problem) { return check_rows<T>(job, ref, &s, &problem); });
}

}  // namespace

check_result check_against_file(const check_job& job) {
  std::ifstream in = open_input_file("reference", job.reference_path);
  reference_csv_reader ref(in, "reference " + job.reference_path);
  return with_scalar(ref.metadata().reading_precision(), [&](auto zero) -> check_result {
    using T = decltype(zero);
    if constexpr (std::is_same_v<T, double>)
      throw std::logic_error("a reference file is read in quad or MPFR");
    else
      return check_in<T>(job, ref);
  });
}

}  // namespace eulervop::app
