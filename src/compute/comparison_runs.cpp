#include "compute/comparison_runs.hpp"

namespace eulervop {

EULERVOP_COMPARISON_RUNS(, constant_torque<double>)
EULERVOP_COMPARISON_RUNS(, time_torque<double>)
EULERVOP_COMPARISON_RUNS(, state_torque<double>)

}  // namespace eulervop
