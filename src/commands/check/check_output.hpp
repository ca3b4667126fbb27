// What `check` prints: the errors, the oracle metrics and the verdict, as a table or as JSON
// (--format json).
#pragma once

#include "commands/check/check_job.hpp"
#include "commands/check/check_tally.hpp"

#include <ostream>

namespace eulervop::app {

// Prints the result and returns the exit code: exit_success within the bar (or without one),
// exit_check_outside when some row exceeds it.
int print_check(const check_job& job, const check_result& r, std::ostream& standard_output);

}  // namespace eulervop::app
