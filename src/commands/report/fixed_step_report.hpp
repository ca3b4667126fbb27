// A report at one fixed step: the reference at every sample step (computed here, or the rows of
// a --reference file), each run's Eq. 20 error there, and the outputs (fixed_step_output.hpp).
#pragma once

#include "commands/report/report_job.hpp"

#include <ostream>

namespace eulervop::app {

// In the precision of the reference (the file's, or --precision). input_error for a bad
// reference file before anything is written; numerical_failure when the reference gives up.
void run_fixed_step_report(const report_job& job, std::ostream& standard_output);

}  // namespace eulervop::app
