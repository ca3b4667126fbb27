// The outputs of a fixed-step report: errors.csv (one column per run at the reference's
// samples), summary.json and the table.
#pragma once

#include "commands/report/report_job.hpp"
#include "commands/report/report_output.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace eulervop::app {

// The reference of a fixed-step report as its outputs describe it.
struct fixed_reference_info {
  std::vector<double> tau;       // each error sample's tau
  std::size_t sample_every = 1;  // the runs sample every this many steps (and the last)
  std::string precision;
  std::string source;            // "computed", or the --reference file's path
  std::optional<double> estimated_max_error;
  std::optional<double> estimated_max_attitude_error;  // --verify of an attitude reference (rad)
  std::optional<double> seconds;  // a computed reference's wall time and segments
  std::optional<std::size_t> segments;
};

std::string fixed_errors_csv(const report_job& job, const fixed_reference_info& ref,
                             const std::vector<run_errors>& runs);
nlohmann::ordered_json fixed_summary_json(const report_job& job, const fixed_reference_info& ref,
                                          const std::vector<run_errors>& runs);
std::string fixed_table(const report_job& job, const fixed_reference_info& ref, const std::vector<run_errors>& runs);

}  // namespace eulervop::app
