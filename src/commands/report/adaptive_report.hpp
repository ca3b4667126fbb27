// A report under error control (--tols): every formulation x method x tolerance run to the span
// end, then one reference evaluated at all the runs' step points, and the outputs
// (adaptive_output.hpp).
#pragma once

#include "commands/report/report_job.hpp"

#include <ostream>

namespace eulervop::app {

// numerical_failure when the reference gives up.
void run_adaptive_report(const report_job& job, std::ostream& standard_output);

}  // namespace eulervop::app
