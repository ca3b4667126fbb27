#include "commands/report/adaptive_output.hpp"

#include "io/text_buffer.hpp"
#include "io/text_table.hpp"

#include <fmt/format.h>

namespace eulervop::app {

std::string adaptive_errors_csv(const report_job& job, const std::vector<run_errors>& runs) {
  const report_units units = report_units::of(job.scn);
  text_buffer out;
  // With the attitude, a sixth column: the attitude error there (radians; empty if none). A
  // physical scene speaks t (s) and the rates' error (rad/s), then the normalized tau and Eq. 20.
  out.put("formulation,method,tol,{},error{}{}\n", units.physical ? "t" : "tau", job.attitude ? ",attitude_error" : "",
          units.physical ? ",tau,error_normalized" : "");
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const run_spec& spec = job.runs[i];
    const run_result& r = runs[i].run;
    for (std::size_t k = 0; k < r.Omega.size(); ++k) {
      if (!runs[i].error[k]) continue;
      out.put("{},{},{},{},", formulation_name(spec.form), rk::method_name(spec.method), job.tols[*spec.tol].value,
              units.t_of(r.sample_tau[k]));
      if (!units.physical) {
        out.put("{}", *runs[i].error[k]);
      } else if (runs[i].rate_error[k]) {
        out.put("{}", *runs[i].rate_error[k]);
      }
      if (job.attitude) {
        out.put(",");
        if (runs[i].attitude_error[k]) out.put("{}", *runs[i].attitude_error[k]);
      }
      if (units.physical) out.put(",{},{}", r.sample_tau[k], *runs[i].error[k]);
      out.put("\n");
    }
  }
  return out.text();
}

nlohmann::ordered_json adaptive_summary_json(const report_job& job, const computed_reference_info& ref,
                                             const std::vector<run_errors>& runs) {
  const report_units units = report_units::of(job.scn);
  nlohmann::ordered_json j;
  j["scene"] = job.scn.name;
  if (units.physical) j["units"] = units_json(units);
  j["reference"] = {{"precision", job.precision.name()},
                    {units.physical ? "estimated_max_error_normalized" : "estimated_max_error", nullptr},
                    {"source", "computed"},
                    {"seconds", ref.seconds},
                    {"segments", ref.segments}};
  if (!job.note.empty()) j["note"] = job.note;
  j["max_step"] = {{"h", job.max_step.h}, {"rule", job.max_step.rule}};
  j["runs"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < runs.size(); ++i)
    j["runs"].push_back(
        run_json(job.runs[i], runs[i], nullptr, job.tols[*job.runs[i].tol].value, job.attitude, units));
  return j;
}

std::string adaptive_table(const report_job& job, const computed_reference_info& ref,
                           const std::vector<run_errors>& runs) {
  const report_units units = report_units::of(job.scn);
  const double span = tau_end_of<double>(job.scn);
  text_buffer out;
  out.put("scene {}{}: to {} under error control (atol = rtol = tol)\n", job.scn.name,
          job.overrides.empty() ? "" : " (" + job.overrides + ")",
          units.physical ? fmt::format("t = {:.6g} s (tau = {:.6g})", units.t_of(span), span)
                         : fmt::format("tau = {:.6g}", span));
  out.put("maximum step: {}\n", job.max_step.rule);
  if (!job.note.empty()) out.put("note: {}\n", job.note);
  out.put("reference: {} (computed, {:.1f} s)\n", job.precision.name(), ref.seconds);
  out.put("error samples: about {} per run, at its accepted steps\n", job.samples);
  if (units.physical)
    out.put("errors: the rates' in rad/s on the body's axes, at t in s; \"normalized\" is {}\n",
            units.direct ? "the same figure (the direct form integrates t and omega)" : "Eq. 20 in tau and Omega");
  if (job.attitude)
    out.put("attitude: {}; attitude error = rotation angle from the reference's q (rad)\n", attitude_mode(job.scn));
  out.put("\n");
  std::vector<std::vector<std::string>> rows = {
      {"formulation", "method", "tol", "steps", "rejected", "rhs evals", "seconds"}};
  const std::vector<std::string> headers = error_headers(units, job.attitude);
  rows[0].insert(rows[0].end(), headers.begin(), headers.end());
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const run_result& r = runs[i].run;
    const run_spec& spec = job.runs[i];
    rows.push_back({std::string(formulation_name(spec.form)), std::string(rk::method_name(spec.method)),
                    job.tols[*spec.tol].text, fmt::format("{}", r.steps), fmt::format("{}", r.rejected),
                    fmt::format("{}", r.rhs_evals), fmt::format("{:.3f}", r.seconds)});
    const std::vector<std::string> cells = error_cells(runs[i], units, job.attitude);
    rows.back().insert(rows.back().end(), cells.begin(), cells.end());
  }
  return out.text() + aligned_table(rows, 2) + bands_notes(job, runs, units);
}

}  // namespace eulervop::app
