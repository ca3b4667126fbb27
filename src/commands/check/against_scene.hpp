// `check` against a scene: the reference integrated to the trajectory's last time, in the job's
// precision, and evaluated at every row's time as its segments are accepted.
#pragma once

#include "commands/check/check_job.hpp"
#include "commands/check/check_tally.hpp"

namespace eulervop::app {

// input_error for a bad trajectory; numerical_failure when the reference gives up.
check_result check_against_scene(const check_job& job);

}  // namespace eulervop::app
