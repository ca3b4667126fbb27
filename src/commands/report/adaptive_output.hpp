// The outputs of a report under error control (--tols): errors.csv (one row per sample of each
// run, since the runs' step points differ), summary.json and the table.
#pragma once

#include "commands/report/report_job.hpp"
#include "commands/report/report_output.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace eulervop::app {

// What the outputs say of the reference computed here.
struct computed_reference_info {
  double seconds = 0;
  std::size_t segments = 0;
};

std::string adaptive_errors_csv(const report_job& job, const std::vector<run_errors>& runs);
nlohmann::ordered_json adaptive_summary_json(const report_job& job, const computed_reference_info& ref,
                                             const std::vector<run_errors>& runs);
std::string adaptive_table(const report_job& job, const computed_reference_info& ref,
                           const std::vector<run_errors>& runs);

}  // namespace eulervop::app
