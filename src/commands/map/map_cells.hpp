// The cells of the map: at each torque scale and error level, the cheapest configuration of each
// formulation, the cheapest VOP formulation and its speed-up over Euler.
#pragma once

#include "commands/map/map_job.hpp"
#include "compute/cheapest_configurations.hpp"
#include "compute/work_precision_runs.hpp"

#include <cstddef>
#include <optional>
#include <vector>

namespace eulervop::app {

// One cell: a scale and a level.
struct map_cell {
  level_choice choice;
  std::optional<std::size_t> euler;     // index into grid.forms
  std::optional<std::size_t> best_vop;  // index into grid.forms
  std::optional<double> speedup;        // euler time / best VOP time
};

// Per scale (the job's grids), per level (the job's levels).
std::vector<std::vector<map_cell>> cells_of(const map_job& job, const std::vector<wp_outcome>& outcomes);

}  // namespace eulervop::app
