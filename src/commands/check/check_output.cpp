#include "commands/check/check_output.hpp"

#include "cli/exit_codes.hpp"
#include "io/output_cells.hpp"
#include "io/reference_csv.hpp"
#include "io/text_buffer.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

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

// The table's one format for errors, differences and radii: four significant digits.
std::string figure(double x) { return fmt::format("{:.3e}", x); }

// A number the user gave (a bar, atol, rtol): the same format, with more digits only when four
// would not give it back (a bar of 9.99999e-07 is not printed as 1.000e-06, where an error just
// above it would fail beside an equal-looking bar).
std::string given_figure(double x) {
  for (int digits = 3; digits < 17; ++digits) {
    const std::string text = fmt::format("{:.{}e}", x, digits);
    if (std::strtod(text.c_str(), nullptr) == x) return text;
  }
  return fmt::format("{:.16e}", x);
}

// A time of the trajectory in the table: six significant digits in the scene's units (the line
// number beside it names the row exactly).
std::string time_figure(const std::string& text, const compared_terms& terms) {
  return fmt::format("{:.6g}{}", time_value(text), unit_suffix(terms.time_unit));
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
// error along and across the motion. Where scd's worst component is, with the reference's value
// there, so that a low scd of rates near zero is not read as a bad trajectory.
void add_metrics_json(const check_job& job, const check_result& r, json& j) {
  const tally& t = r.t;
  const auto digits = [](double max_error) {
    const double d = digits_of(max_error);
    return std::isfinite(d) ? json(d) : json(nullptr);  // null: exact
  };
  j["scd"] = digits(t.max_relative);
  j["scd_worst"] = t.scd_component >= 0 ? json{{"component", r.terms.components[t.scd_component]},
                                               {"time", time_value(t.scd_time)},
                                               {"line", t.scd_line},
                                               {"reference_value", t.scd_reference}}
                                        : json(nullptr);
  j["mescd"] = digits(t.max_mixed);
  j["scd_atol"] = job.scd_atol;
  j["scd_rtol"] = job.scd_rtol;
  j["max_component_errors"] = {t.max_component[0], t.max_component[1], t.max_component[2]};
  const bool invariants = r.scene.invariants;
  const auto drift = [&](double max, double last) {
    return invariants ? json{{"max", max}, {"last", last}} : json(nullptr);
  };
  j["c1_squared_drift"] = drift(t.c1_drift_max, t.c1_drift_last);
  j["c2_squared_drift"] = drift(t.c2_drift_max, t.c2_drift_last);
  j["invariant_drift_note"] = r.scene.invariants_note.empty() ? json(nullptr) : json(r.scene.invariants_note);
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
// compared one, labelled as such.
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
  j["normalized_error_unit"] =
      apart ? json(error_unit(reference_layout::physical, "estimated_max_error")) : json(nullptr);
}

// The hint of a first row whose q matches the reference's once reordered or inverted: the
// convention it looks written in, eulervop's, and the --columns that reads it so. Empty when
// there is none.
std::string q_convention_hint(const first_row_check& f, const std::array<std::string, 4>& names) {
  if (!f.q_order) return "";
  const std::array<int, 4>& order = *f.q_order;
  const std::array<int, 4> identity = {0, 1, 2, 3}, scalar_last = {3, 0, 1, 2};
  std::string looks;
  if (order == scalar_last)
    looks = f.q_inverse ? "looks scalar-last (x, y, z, w) and inverse (inertial to body, as in the JPL convention)"
                        : "looks scalar-last (x, y, z, w)";
  else if (order == identity)
    looks = "looks like the inverse rotation (inertial to body)";
  else
    looks = fmt::format("matches with its columns in the order {}, {}, {}, {}{}", names[order[0]], names[order[1]],
                        names[order[2]], names[order[3]], f.q_inverse ? " and inverted" : "");
  std::vector<std::string> fixes;
  if (order != identity)
    fixes.push_back(fmt::format("give --columns q0={},q1={},q2={},q3={}", names[order[0]], names[order[1]],
                                names[order[2]], names[order[3]]));
  if (f.q_inverse) fixes.push_back("write the inverse (q1..q3 negated)");
  return fmt::format(
      "the trajectory's q {}; eulervop's q0..q3 are scalar-first (w, x, y, z), Hamilton, body to inertial: {}", looks,
      fmt::join(fixes, " and "));
}

// The first row at time 0 against the reference's initial state (null when the first row is later).
void add_first_row_json(const check_result& r, json& j) {
  const first_row_check& f = r.t.first;
  j["first_row_matches_initial_state"] = f.done ? json(f.matches()) : json(nullptr);
  if (!f.done) {
    j["first_row_initial_state"] = nullptr;
    return;
  }
  const auto attitude = [&](json value) { return f.attitude ? value : json(nullptr); };
  const std::string hint = q_convention_hint(f, r.q_columns);
  j["first_row_initial_state"] = {{"line", f.line},
                                  {"time", time_value(f.time)},
                                  {"rate_difference", f.rate_difference},
                                  {"rate_limit", f.rate_limit},
                                  {"rates_match", f.rates_match},
                                  {"attitude_difference", attitude(f.attitude_difference)},
                                  {"attitude_limit", attitude(f.attitude_limit)},
                                  {"attitude_match", attitude(f.attitude_match)},
                                  {"q_convention_hint", hint.empty() ? json(nullptr) : json(hint)}};
}

json check_json(const check_job& job, const check_result& r) {
  const tally& t = r.t;
  json j;
  j["trajectory"] = job.trajectory_name;
  j["reference"] = r.reference_json;
  j["time_column"] = r.time_name;
  add_terms_json(r, j);
  j["rows"] = t.rows;
  j["first_time"] = time_value(t.first_time);
  j["last_time"] = time_value(t.last_time);
  add_first_row_json(r, j);
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
  add_metrics_json(job, r, j);
  add_attitude_json(job, t, j);
  return j;
}

// The table's lines on the first row when it disagrees with the reference's initial state: one
// for the rates, one for the attitude (with the convention its q looks written in).
void put_first_row(const check_job& job, const check_result& r, text_buffer& out) {
  const first_row_check& f = r.t.first;
  if (!f.done || f.matches()) return;
  const std::string unit = unit_suffix(r.terms.state_unit);
  const std::string row = fmt::format("the first row ({} = {}, line {})", r.time_name, time_figure(f.time, r.terms),
                                      f.line);
  if (!f.rates_match)
    out.put("initial state: {} disagrees with {}: off by {}{}, above {}{} ({})\n", row, r.scene.initial_rates,
            figure(f.rate_difference), unit, f.rate_limit_is_bar ? given_figure(f.rate_limit) : figure(f.rate_limit), unit,
            f.rate_limit_is_bar ? "the bar" : "1e-6 of the rates' norm; no bar given");
  if (!f.attitude_match) {
    const std::string hint = q_convention_hint(f, r.q_columns);
    out.put("initial state: {} disagrees with {}: q is off by {} rad, above {} rad ({}){}\n", row, r.scene.initial_q,
            figure(f.attitude_difference), given_figure(f.attitude_limit),
            f.attitude_limit_is_bar   ? "--attitude-tol"
            : job.ignore_attitude     ? "1e-6 rad; --ignore-attitude"
                                      : "1e-6 rad; no --attitude-tol",
            hint.empty() ? "" : "; " + hint);
  }
}

// scd and mescd, each with what it measures: a digit count alone reads as a grade, and a low scd
// of rates that decay towards zero is a small error relative to a small number.
void put_digits(const check_job& job, const check_result& r, text_buffer& out) {
  const tally& t = r.t;
  const std::string unit = unit_suffix(r.terms.state_unit);
  if (t.scd_component < 0)
    out.put("scd: exact (no component with a reference value other than 0 differs)\n");
  else
    out.put(
        "scd: {:.2f} (significant correct digits: -log10 of the largest |error|/|ref| of a component; it is at {} at "
        "{} = {} (line {}), where |{}_ref| = {}{})\n",
        digits_of(t.max_relative), r.terms.components[t.scd_component], r.time_name, time_figure(t.scd_time, r.terms),
        t.scd_line, r.terms.components[t.scd_component], figure(t.scd_reference), unit);
  const std::string floor = given_figure(job.scd_atol / job.scd_rtol);
  if (!(t.max_mixed > 0))
    out.put("mescd: exact (no component differs)\n");
  else
    out.put(
        "mescd: {:.2f} (-log10 of the largest |error|/(atol/rtol + |ref|), atol {}, rtol {}: relative where |ref| is "
        "well above atol/rtol = {}{}, absolute in units of it well below)\n",
        digits_of(t.max_mixed), given_figure(job.scd_atol), given_figure(job.scd_rtol), floor, unit);
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
    if (job.tol) bar = given_figure(*job.tol) + unit;
    if (job.rel_tol)
      bar += fmt::format("{}{} {}", bar.empty() ? "" : " + ", given_figure(*job.rel_tol), reference_norm(r.terms));
    out.put("tolerance: error <= {}\n", bar);
    if (t.certified)
      out.put(
          "certified reference: each error is +- its row's radius (max {}{}); a row fails only if error - radius > "
          "bar; {} of {} rows uncertain\n",
          figure(t.max_radius), unit, t.uncertain, t.rows);
  }
  if (job.attitude_tol) out.put("attitude tolerance: attitude error <= {} rad\n", given_figure(*job.attitude_tol));
  const std::string unjudged = t.attitude && !job.attitude_tol ? "; the attitude not judged (--ignore-attitude)" : "";
  if (passed(t)) {
    out.put("result: PASS (every row within tolerance{})\n", unjudged);
    return;
  }
  std::string why;
  if (t.exceeding)
    why = fmt::format("{} of {} rows exceed; first at {} = {}, line {}", t.exceeding, t.rows, r.time_name,
                      time_figure(*t.first_exceeding_time, r.terms), t.first_exceeding_line);
  if (t.attitude_exceeding)
    why += fmt::format("{}attitude: {} of {} rows exceed; first at {} = {}, line {}", why.empty() ? "" : "; ",
                       t.attitude_exceeding, t.rows, r.time_name,
                       time_figure(*t.first_attitude_exceeding_time, r.terms), t.first_attitude_exceeding_line);
  out.put("result: FAIL ({}{})\n", why, unjudged);
}

// Every error, difference and bar in one format (figure, given_figure), every time in the
// scene's units with six significant digits, every figure with its unit.
std::string check_table(const check_job& job, const check_result& r) {
  const tally& t = r.t;
  const compared_terms& terms = r.terms;
  text_buffer out;
  out.put("trajectory: {} ({} rows, {} from {} to {})\n", job.trajectory_name, t.rows, r.time_name,
          time_figure(t.first_time, terms), time_figure(t.last_time, terms));
  out.put("reference: {}\n", r.reference_text);
  put_first_row(job, r, out);
  const std::string unit = unit_suffix(terms.state_unit);
  out.put("max error: {}{} at {} = {} (line {})\n", figure(t.max_error), unit, r.time_name,
          time_figure(t.max_time, terms), t.max_line);
  out.put("rms error: {}{}\n", figure(rms_of(t)), unit);
  out.put("per component: max |error| of {} {}, {} {}, {} {}{}\n", terms.components[0], figure(t.max_component[0]),
          terms.components[1], figure(t.max_component[1]), terms.components[2], figure(t.max_component[2]), unit);
  // The paper's measure, for a torque-free body only: under a torque the normalized variables are
  // a scaling of no use to a reader in rad/s (the JSON keeps it, labelled).
  if (terms.normalized_apart && r.scene.torque_free.value_or(false))
    out.put("normalized (Eq. 20 in tau, Omega of Eq. 4; dimensionless, not {}): max error {} at {} = {}\n",
            terms.state_unit, figure(t.max_normalized_error), r.time_name, time_figure(t.max_normalized_time, terms));
  put_digits(job, r, out);
  if (r.scene.invariants)
    out.put(
        "invariant drift (Eq. 7 in the normalized variables, against the reference): c1^2 max {} last {}; c2^2 max {} "
        "last {}{}\n",
        figure(t.c1_drift_max), figure(t.c1_drift_last), figure(t.c2_drift_max), figure(t.c2_drift_last),
        r.scene.invariants_note.empty() ? "" : " (" + r.scene.invariants_note + ")");
  else if (r.scene.invariants_in_table)
    out.put("invariant drift: none ({})\n", r.scene.invariants_note);
  if (t.has_direction)
    out.put("error along the motion (phase): max {}{}; across it: max {}{}\n", figure(t.max_along), unit,
            figure(t.max_across), unit);
  if (t.attitude) {
    out.put("max attitude error: {} rad at {} = {} (line {})\n", figure(t.max_attitude), r.time_name,
            time_figure(t.max_attitude_time, terms), t.max_attitude_line);
    out.put("rms attitude error: {} rad\n", figure(attitude_rms_of(t)));
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
