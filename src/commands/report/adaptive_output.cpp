#include "commands/report/adaptive_output.hpp"

#include "io/text_buffer.hpp"
#include "io/text_table.hpp"

#include <fmt/format.h>

namespace eulervop::app {

std::string adaptive_errors_csv(const report_job& job, const std::vector<run_errors>& runs) {
  text_buffer out;
  // With the attitude, a sixth column: the attitude error there (radians; empty if none).
  out.put("formulation,method,tol,tau,error{}\n", job.attitude ? ",attitude_error" : "");
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const run_spec& spec = job.runs[i];
    const run_result& r = runs[i].run;
    for (std::size_t k = 0; k < r.Omega.size(); ++k) {
      if (!runs[i].error[k]) continue;
      out.put("{},{},{},{},{}", formulation_name(spec.form), rk::method_name(spec.method), job.tols[*spec.tol].value,
              r.sample_tau[k], *runs[i].error[k]);
      if (job.attitude) {
        out.put(",");
        if (runs[i].attitude_error[k]) out.put("{}", *runs[i].attitude_error[k]);
      }
      out.put("\n");
    }
  }
  return out.text();
}

nlohmann::ordered_json adaptive_summary_json(const report_job& job, const computed_reference_info& ref,
                                             const std::vector<run_errors>& runs) {
  nlohmann::ordered_json j;
  j["scene"] = job.scn.name;
  j["reference"] = {{"precision", job.precision.name()},
                    {"estimated_max_error", nullptr},
                    {"source", "computed"},
                    {"seconds", ref.seconds},
                    {"segments", ref.segments}};
  if (!job.note.empty()) j["note"] = job.note;
  j["max_step"] = {{"h", job.max_step.h}, {"rule", job.max_step.rule}};
  j["runs"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < runs.size(); ++i)
    j["runs"].push_back(run_json(job.runs[i], runs[i], nullptr, job.tols[*job.runs[i].tol].value, job.attitude));
  return j;
}

std::string adaptive_table(const report_job& job, const computed_reference_info& ref,
                           const std::vector<run_errors>& runs) {
  text_buffer out;
  out.put("scene {}{}: to tau = {:.6g} under error control (atol = rtol = tol)\n", job.scn.name,
          job.overrides.empty() ? "" : " (" + job.overrides + ")", tau_end_of<double>(job.scn));
  out.put("maximum step: {}\n", job.max_step.rule);
  if (!job.note.empty()) out.put("note: {}\n", job.note);
  out.put("reference: {} (computed, {:.1f} s)\n", job.precision.name(), ref.seconds);
  out.put("error samples: about {} per run, at its accepted steps\n", job.samples);
  if (job.attitude)
    out.put("attitude: {}; attitude error = rotation angle from the reference's q (rad)\n", attitude_mode(job.scn));
  out.put("\n");
  // The last column is the divergence note, when there is one.
  std::vector<std::vector<std::string>> rows = {{"formulation", "method", "tol", "steps", "rejected", "rhs evals",
                                                 "seconds", "max error", "final tau", "final error", ""}};
  if (job.attitude) rows[0].insert(rows[0].end() - 1, {"max att err", "final att err"});
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const run_result& r = runs[i].run;
    const run_spec& spec = job.runs[i];
    rows.push_back({std::string(formulation_name(spec.form)), std::string(rk::method_name(spec.method)),
                    job.tols[*spec.tol].text, fmt::format("{}", r.steps), fmt::format("{}", r.rejected),
                    fmt::format("{}", r.rhs_evals), fmt::format("{:.3f}", r.seconds),
                    optional_text(runs[i].max_error, "{:.3e}"), optional_text(runs[i].final_tau, "{:.6g}"),
                    optional_text(runs[i].final_error, "{:.3e}"), divergence_note(r)});
    if (job.attitude)
      rows.back().insert(rows.back().end() - 1, {optional_text(runs[i].max_attitude_error, "{:.3e}"),
                                                 optional_text(runs[i].final_attitude_error, "{:.3e}")});
  }
  return out.text() + aligned_table(rows, 2) + bands_notes(job, runs);
}

}  // namespace eulervop::app
