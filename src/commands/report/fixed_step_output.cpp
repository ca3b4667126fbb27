#include "commands/report/fixed_step_output.hpp"

#include "io/output_cells.hpp"
#include "io/text_buffer.hpp"
#include "io/text_table.hpp"

#include <fmt/format.h>

namespace eulervop::app {

std::string fixed_errors_csv(const report_job& job, const fixed_reference_info& ref,
                             const std::vector<run_errors>& runs) {
  text_buffer out;
  out.put("tau");
  for (const run_spec& r : job.runs) out.put(",{}", r.column());
  // With the attitude, a second block: each run's attitude error (radians), "euler_rk4_attitude".
  if (job.attitude)
    for (const run_spec& r : job.runs) out.put(",{}_attitude", r.column());
  out.put("\n");
  for (std::size_t i = 0; i < ref.tau.size(); ++i) {
    out.put("{}", ref.tau[i]);  // shortest round trip
    for (const run_errors& r : runs) {
      out.put(",");
      if (r.error[i]) out.put("{}", *r.error[i]);
    }
    if (job.attitude)
      for (const run_errors& r : runs) {
        out.put(",");
        if (r.attitude_error[i]) out.put("{}", *r.attitude_error[i]);
      }
    out.put("\n");
  }
  return out.text();
}

nlohmann::ordered_json fixed_summary_json(const report_job& job, const fixed_reference_info& ref,
                                          const std::vector<run_errors>& runs) {
  nlohmann::ordered_json j;
  j["scene"] = job.scn.name;
  j["reference"] = {{"precision", ref.precision},
                    {"estimated_max_error", number_or_null(ref.estimated_max_error)},
                    {"source", ref.source}};
  if (job.attitude) j["reference"]["estimated_max_attitude_error"] = number_or_null(ref.estimated_max_attitude_error);
  if (ref.seconds) j["reference"]["seconds"] = *ref.seconds;
  if (ref.segments) j["reference"]["segments"] = *ref.segments;
  j["step_rule"] = job.step.rule;
  if (!job.note.empty()) j["note"] = job.note;
  j["runs"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < runs.size(); ++i)
    j["runs"].push_back(run_json(job.runs[i], runs[i], job.step.h, nullptr, job.attitude));
  return j;
}

std::string fixed_table(const report_job& job, const fixed_reference_info& ref, const std::vector<run_errors>& runs) {
  text_buffer out;
  out.put("scene {}{}: {} steps to tau = {:.6g}\n", job.scn.name,
          job.overrides.empty() ? "" : " (" + job.overrides + ")", job.step.n_steps,
          static_cast<double>(job.step.n_steps) * job.step.h);
  out.put("step: {}\n", job.step.rule);
  if (!job.note.empty()) out.put("note: {}\n", job.note);
  out.put("reference: {} ({}{}), estimated max error {}\n", ref.precision, ref.source,
          ref.seconds ? fmt::format(", {:.1f} s", *ref.seconds) : "", optional_text(ref.estimated_max_error, "{:.2e}"));
  if (job.attitude)
    out.put("attitude: {}; attitude error = rotation angle from the reference's q (rad){}\n", attitude_mode(job.scn),
            ref.estimated_max_attitude_error
                ? fmt::format(", reference's estimated max {:.2e}", *ref.estimated_max_attitude_error)
                : "");
  out.put("error samples: {} (every {} steps)\n\n", ref.tau.size(), ref.sample_every);
  // The last column is the divergence note, when there is one.
  std::vector<std::vector<std::string>> rows = {
      {"formulation", "method", "h", "steps", "rhs evals", "seconds", "max error", "final tau", "final error", ""}};
  if (job.attitude) rows[0].insert(rows[0].end() - 1, {"max att err", "final att err"});
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const run_result& r = runs[i].run;
    rows.push_back({std::string(formulation_name(job.runs[i].form)), std::string(rk::method_name(job.runs[i].method)),
                    fmt::format("{:.6g}", job.step.h), fmt::format("{}", r.steps), fmt::format("{}", r.rhs_evals),
                    fmt::format("{:.3f}", r.seconds), optional_text(runs[i].max_error, "{:.3e}"),
                    optional_text(runs[i].final_tau, "{:.6g}"), optional_text(runs[i].final_error, "{:.3e}"),
                    divergence_note(r)});
    if (job.attitude)
      rows.back().insert(rows.back().end() - 1, {optional_text(runs[i].max_attitude_error, "{:.3e}"),
                                                 optional_text(runs[i].final_attitude_error, "{:.3e}")});
  }
  return out.text() + aligned_table(rows, 2) + bands_notes(job, runs);
}

}  // namespace eulervop::app
