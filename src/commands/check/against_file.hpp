// `check` against a reference file of `eulervop reference`: each trajectory row's time must be
// one of the file's sample times (to 1e-12 relative); both files are read side by side, in the
// file's precision. Against a certified file each row's error carries the row's radius.
#pragma once

#include "commands/check/check_job.hpp"
#include "commands/check/check_tally.hpp"

namespace eulervop::app {

// input_error for a bad reference file or trajectory.
check_result check_against_file(const check_job& job);

}  // namespace eulervop::app
