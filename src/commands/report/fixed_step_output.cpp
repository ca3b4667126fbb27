#include "commands/report/fixed_step_output.hpp"

#include "io/output_cells.hpp"
#include "io/text_buffer.hpp"
#include "io/text_table.hpp"

#include <fmt/format.h>

namespace eulervop::app {

std::string fixed_errors_csv(const report_job& job, const fixed_reference_info& ref,
                             const std::vector<run_errors>& runs) {
  const report_units units = report_units::of(job.scn);
  const auto cell = [&](const std::optional<double>& x) {
    return x ? fmt::format(",{}", *x) : std::string(",");  // shortest round trip
  };
  text_buffer out;
  // A physical scene leads with t (s) and each run's rates' error (rad/s), as `check` speaks;
  // the normalized tau and Eq. 20 errors follow, named as such.
  out.put("{}", units.physical ? "t" : "tau");
  for (const run_spec& r : job.runs) out.put(",{}", r.column());
  // With the attitude, a second block: each run's attitude error (radians), "euler_rk4_attitude".
  if (job.attitude)
    for (const run_spec& r : job.runs) out.put(",{}_attitude", r.column());
  if (units.physical) {
    out.put(",tau");
    for (const run_spec& r : job.runs) out.put(",{}_normalized", r.column());
  }
  out.put("\n");
  for (std::size_t i = 0; i < ref.tau.size(); ++i) {
    out.put("{}", units.t_of(ref.tau[i]));
    for (const run_errors& r : runs) out.put("{}", cell(units.physical ? r.rate_error[i] : r.error[i]));
    if (job.attitude)
      for (const run_errors& r : runs) out.put("{}", cell(r.attitude_error[i]));
    if (units.physical) {
      out.put(",{}", ref.tau[i]);
      for (const run_errors& r : runs) out.put("{}", cell(r.error[i]));
    }
    out.put("\n");
  }
  return out.text();
}

nlohmann::ordered_json fixed_summary_json(const report_job& job, const fixed_reference_info& ref,
                                          const std::vector<run_errors>& runs) {
  const report_units units = report_units::of(job.scn);
  nlohmann::ordered_json j;
  j["scene"] = job.scn.name;
  if (units.physical) j["units"] = units_json(units);
  // The reference's estimate (--verify) is of its normalized state, Eq. 20.
  j["reference"] = {{"precision", ref.precision},
                    {units.physical ? "estimated_max_error_normalized" : "estimated_max_error",
                     number_or_null(ref.estimated_max_error)},
                    {"source", ref.source}};
  if (job.attitude) j["reference"]["estimated_max_attitude_error"] = number_or_null(ref.estimated_max_attitude_error);
  if (ref.seconds) j["reference"]["seconds"] = *ref.seconds;
  if (ref.segments) j["reference"]["segments"] = *ref.segments;
  j["step_rule"] = job.step.rule;
  if (!job.note.empty()) j["note"] = job.note;
  j["runs"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < runs.size(); ++i)
    j["runs"].push_back(run_json(job.runs[i], runs[i], job.step.h, nullptr, job.attitude, units));
  return j;
}

std::string fixed_table(const report_job& job, const fixed_reference_info& ref, const std::vector<run_errors>& runs) {
  const report_units units = report_units::of(job.scn);
  const double span = static_cast<double>(job.step.n_steps) * job.step.h;
  text_buffer out;
  out.put("scene {}{}: {} steps to {}\n", job.scn.name, job.overrides.empty() ? "" : " (" + job.overrides + ")",
          job.step.n_steps,
          units.physical ? fmt::format("t = {:.6g} s (tau = {:.6g})", units.t_of(span), span)
                         : fmt::format("tau = {:.6g}", span));
  out.put("step: {}{}\n", job.step.rule,
          units.physical && !units.direct ? fmt::format(" (in tau; {:.6g} s)", units.t_of(job.step.h)) : "");
  if (!job.note.empty()) out.put("note: {}\n", job.note);
  out.put("reference: {} ({}{}), estimated max error {}{}\n", ref.precision, ref.source,
          ref.seconds ? fmt::format(", {:.1f} s", *ref.seconds) : "", optional_text(ref.estimated_max_error, "{:.2e}"),
          units.physical && ref.estimated_max_error ? " (normalized, Eq. 20)" : "");
  if (units.physical)
    out.put("errors: the rates' in rad/s on the body's axes, at t in s; \"normalized\" is {}\n",
            units.direct ? "the same figure (the direct form integrates t and omega)" : "Eq. 20 in tau and Omega");
  if (job.attitude)
    out.put("attitude: {}; attitude error = rotation angle from the reference's q (rad){}\n", attitude_mode(job.scn),
            ref.estimated_max_attitude_error
                ? fmt::format(", reference's estimated max {:.2e}", *ref.estimated_max_attitude_error)
                : "");
  out.put("error samples: {} (every {} steps)\n\n", ref.tau.size(), ref.sample_every);
  std::vector<std::vector<std::string>> rows = {
      {"formulation", "method", units.physical ? "h (s)" : "h", "steps", "rhs evals", "seconds"}};
  const std::vector<std::string> headers = error_headers(units, job.attitude);
  rows[0].insert(rows[0].end(), headers.begin(), headers.end());
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const run_result& r = runs[i].run;
    rows.push_back({std::string(formulation_name(job.runs[i].form)), std::string(rk::method_name(job.runs[i].method)),
                    fmt::format("{:.6g}", units.t_of(job.step.h)), fmt::format("{}", r.steps),
                    fmt::format("{}", r.rhs_evals), fmt::format("{:.3f}", r.seconds)});
    const std::vector<std::string> cells = error_cells(runs[i], units, job.attitude);
    rows.back().insert(rows.back().end(), cells.begin(), cells.end());
  }
  return out.text() + aligned_table(rows, 2) + bands_notes(job, runs, units);
}

}  // namespace eulervop::app
