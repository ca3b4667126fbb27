#include "commands/check/check_output.hpp"

#include "cli/exit_codes.hpp"
#include "io/output_cells.hpp"
#include "io/text_buffer.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

namespace eulervop::app {

namespace {

using json = nlohmann::ordered_json;

double time_value(const std::string& text) { return std::strtod(text.c_str(), nullptr); }

// -log10 of a largest error: significant correct digits (infinite for an exact match).
double digits_of(double max_error) {
  return max_error > 0 ? -std::log10(max_error) : std::numeric_limits<double>::infinity();
}

double rms_of(const tally& t) {
  return static_cast<double>(std::sqrt(t.sum_squares / static_cast<long double>(t.rows)));
}

double attitude_rms_of(const tally& t) {
  return static_cast<double>(std::sqrt(t.attitude_sum_squares / static_cast<long double>(t.rows)));
}

bool has_bar(const check_job& job) { return job.tol || job.rel_tol; }

// A verdict needs a bar on every quantity judged (check_job_of and require_attitude_match refuse
// a bar on the rates alone when the trajectory has an attitude, unless --ignore-attitude).
bool judged(const check_job& job) { return has_bar(job) || job.attitude_tol; }

bool passed(const tally& t) { return t.exceeding == 0 && t.attitude_exceeding == 0; }

// " rad/s", or "" in the normalized variables.
std::string unit_suffix(const std::string& unit) { return unit.empty() ? "" : " " + unit; }

// "|omega_ref|": the norm a relative bar scales.
std::string reference_norm(const compared_terms& terms) {
  return fmt::format("|{}_ref|", terms.components[0].substr(0, terms.components[0].size() - 1));
}

// Against a certified reference: the rows whose verdict the radius leaves open.
void add_certified_json(const check_job& job, const tally& t, json& j) {
  const bool open = t.certified && has_bar(job);
  j["certified_reference"] = t.certified;
  j["max_reference_radius"] = t.certified ? json(t.max_radius) : json(nullptr);
  j["uncertain_rows"] = open ? json(t.uncertain) : json(nullptr);
  j["uncertain_lines"] = open ? json(t.uncertain_lines) : json(nullptr);
  j["all_rows_certain"] = open ? json(t.uncertain == 0) : json(nullptr);
}

// The oracle metrics: scd, mescd, the largest error per component, the drift of Eq. 7 and the
// error along and across the motion.
void add_metrics_json(const check_job& job, const tally& t, json& j) {
  const auto digits = [](double max_error) {
    const double d = digits_of(max_error);
    return std::isfinite(d) ? json(d) : json(nullptr);  // null: exact
  };
  j["scd"] = digits(t.max_relative);
  j["mescd"] = digits(t.max_mixed);
  j["scd_atol"] = job.scd_atol;
  j["scd_rtol"] = job.scd_rtol;
  j["max_component_errors"] = {t.max_component[0], t.max_component[1], t.max_component[2]};
  const auto drift = [&](double max, double last) {
    return t.has_invariants ? json{{"max", max}, {"last", last}} : json(nullptr);
  };
  j["c1_squared_drift"] = drift(t.c1_drift_max, t.c1_drift_last);
  j["c2_squared_drift"] = drift(t.c2_drift_max, t.c2_drift_last);
  j["max_error_along_motion"] = t.has_direction ? json(t.max_along) : json(nullptr);
  j["max_error_across_motion"] = t.has_direction ? json(t.max_across) : json(nullptr);
}

// The attitude (a trajectory with q0..q3): its errors in radians, as the rates' above; null
// without q0..q3.
void add_attitude_json(const check_job& job, const tally& t, json& j) {
  const auto checked = [&](json value) { return t.attitude ? value : json(nullptr); };
  const bool exceeded = t.attitude && t.first_attitude_exceeding_time.has_value();
  j["attitude_tol"] = number_or_null(job.attitude_tol);
  j["max_attitude_error"] = checked(t.max_attitude);
  j["max_attitude_error_time"] = checked(time_value(t.max_attitude_time));
  j["max_attitude_error_line"] = checked(t.max_attitude_line);
  j["rms_attitude_error"] = checked(attitude_rms_of(t));
  j["attitude_exceeding_rows"] = checked(t.attitude_exceeding);
  j["first_attitude_exceeding_time"] = exceeded ? json(time_value(*t.first_attitude_exceeding_time)) : json(nullptr);
  j["first_attitude_exceeding_line"] = exceeded ? json(t.first_attitude_exceeding_line) : json(nullptr);
}

// The compared variables' names and units (null: the normalized variables of Eq. 4, or the
// coefficient form's own), and the Eq. 20 error in the normalized variables when it is not the
// compared one.
void add_terms_json(const check_result& r, json& j) {
  const tally& t = r.t;
  const auto unit = [](const std::string& u) { return u.empty() ? json(nullptr) : json(u); };
  j["components"] = r.terms.components;
  j["time_unit"] = unit(r.terms.time_unit);
  j["error_unit"] = unit(r.terms.state_unit);
  const bool apart = r.terms.normalized_apart;
  j["normalized_max_error"] = apart ? json(t.max_normalized_error) : json(nullptr);
  j["normalized_max_error_time"] = apart ? json(time_value(t.max_normalized_time)) : json(nullptr);
  j["normalized_rms_error"] =
      apart ? json(static_cast<double>(std::sqrt(t.normalized_sum_squares / static_cast<long double>(t.rows))))
            : json(nullptr);
}

json check_json(const check_job& job, const check_result& r) {
  const tally& t = r.t;
  json j;
  j["trajectory"] = job.trajectory_path;
  j["reference"] = r.reference_json;
  j["time_column"] = r.time_name;
  add_terms_json(r, j);
  j["rows"] = t.rows;
  j["first_time"] = time_value(t.first_time);
  j["last_time"] = time_value(t.last_time);
  j["max_error"] = t.max_error;
  j["max_error_time"] = time_value(t.max_time);
  j["max_error_line"] = t.max_line;
  j["rms_error"] = rms_of(t);
  j["tol"] = number_or_null(job.tol);
  j["rel_tol"] = number_or_null(job.rel_tol);
  j["exceeding_rows"] = t.exceeding;
  j["first_exceeding_time"] = t.first_exceeding_time ? json(time_value(*t.first_exceeding_time)) : json(nullptr);
  j["first_exceeding_line"] = t.first_exceeding_time ? json(t.first_exceeding_line) : json(nullptr);
  j["pass"] = judged(job) ? json(passed(t)) : json(nullptr);  // null: no bar given, no verdict
  j["attitude_judged"] = t.attitude ? json(job.attitude_tol.has_value()) : json(nullptr);
  add_certified_json(job, t, j);
  add_metrics_json(job, t, j);
  add_attitude_json(job, t, j);
  return j;
}

// The table's lines on the bars: the tolerances, a certified reference's uncertain rows, the
// result.
void put_verdict(const check_job& job, const check_result& r, text_buffer& out) {
  const tally& t = r.t;
  const std::string unit = unit_suffix(r.terms.state_unit);
  if (!judged(job)) {
    out.put("tolerance: none given (--tol, --rel-tol{}): no verdict\n", t.attitude ? ", --attitude-tol" : "");
    return;
  }
  if (has_bar(job)) {
    std::string bar;
    if (job.tol) bar = fmt::format("{}{}", *job.tol, unit);
    if (job.rel_tol) bar += fmt::format("{}{} {}", bar.empty() ? "" : " + ", *job.rel_tol, reference_norm(r.terms));
    out.put("tolerance: error <= {}\n", bar);
    if (t.certified)
      out.put(
          "certified reference: each error is +- its row's radius (max {:.3g}); a row fails only if error - radius > "
          "bar; {} of {} rows uncertain\n",
          t.max_radius, t.uncertain, t.rows);
  }
  if (job.attitude_tol) out.put("attitude tolerance: attitude error <= {} rad\n", *job.attitude_tol);
  const std::string unjudged = t.attitude && !job.attitude_tol ? "; the attitude not judged (--ignore-attitude)" : "";
  if (passed(t)) {
    out.put("result: PASS (every row within tolerance{})\n", unjudged);
    return;
  }
  std::string why;
  if (t.exceeding)
    why = fmt::format("{} of {} rows exceed; first at {} = {}, line {}", t.exceeding, t.rows, r.time_name,
                      *t.first_exceeding_time, t.first_exceeding_line);
  if (t.attitude_exceeding)
    why += fmt::format("{}attitude: {} of {} rows exceed; first at {} = {}, line {}", why.empty() ? "" : "; ",
                       t.attitude_exceeding, t.rows, r.time_name, *t.first_attitude_exceeding_time,
                       t.first_attitude_exceeding_line);
  out.put("result: FAIL ({}{})\n", why, unjudged);
}

std::string check_table(const check_job& job, const check_result& r) {
  const tally& t = r.t;
  text_buffer out;
  out.put("trajectory: {} ({} rows, {} from {} to {})\n", job.trajectory_path, t.rows, r.time_name, t.first_time,
          t.last_time);
  out.put("reference: {}\n", r.reference_text);
  const compared_terms& terms = r.terms;
  const std::string unit = unit_suffix(terms.state_unit);
  out.put("max error: {}{} at {} = {} (line {})\n", t.max_error, unit, r.time_name, t.max_time, t.max_line);
  out.put("rms error: {:.6e}{}\n", rms_of(t), unit);
  out.put("per component: max |error| of {} {:.3e}, {} {:.3e}, {} {:.3e}{}\n", terms.components[0], t.max_component[0],
          terms.components[1], t.max_component[1], terms.components[2], t.max_component[2], unit);
  if (terms.normalized_apart)
    out.put("normalized (Eq. 20 in tau, Omega of Eq. 4): max error {} at {} = {}\n", t.max_normalized_error,
            r.time_name, t.max_normalized_time);
  out.put("scd: {:.2f}   mescd: {:.2f} (atol {}, rtol {})\n", digits_of(t.max_relative), digits_of(t.max_mixed),
          job.scd_atol, job.scd_rtol);
  if (t.has_invariants)
    out.put(
        "invariant drift (Eq. 7 in the normalized variables, against the reference): c1^2 max {:.3e} last {:.3e}; c2^2 "
        "max {:.3e} last {:.3e}\n",
        t.c1_drift_max, t.c1_drift_last, t.c2_drift_max, t.c2_drift_last);
  else
    out.put(
        "invariant drift: none (Eq. 7 holds only for the normalized Eq. 5, not for the direct form of Eq. 1 or the "
        "coefficient form)\n");
  if (t.has_direction)
    out.put("error along the motion (phase): max {:.3e}{}; across it: max {:.3e}{}\n", t.max_along, unit, t.max_across,
            unit);
  if (t.attitude) {
    out.put("max attitude error: {} rad at {} = {} (line {})\n", t.max_attitude, r.time_name, t.max_attitude_time,
            t.max_attitude_line);
    out.put("rms attitude error: {:.6e} rad\n", attitude_rms_of(t));
  } else if (t.reference_attitude) {
    out.put("attitude: not checked (the trajectory has no columns q0..q3)\n");
  }
  put_verdict(job, r, out);
  return out.text();
}

}  // namespace

int print_check(const check_job& job, const check_result& r, std::ostream& standard_output) {
  if (job.json)
    standard_output << check_json(job, r).dump(2) << "\n";
  else
    standard_output << check_table(job, r);
  standard_output << std::flush;
  return passed(r.t) ? exit_success : exit_check_outside;
}

}  // namespace eulervop::app
