// What a `map` computes, from its flags: one grid per torque scale of the scene, the error
// levels, how the runs are timed and where the outputs go.
#pragma once

#include "cli/grid_flags.hpp"
#include "commands/map/map_command.hpp"
#include "compute/scene_library.hpp"
#include "compute/work_precision_grid.hpp"
#include "compute/work_precision_runs.hpp"

#include <eulervop/core/precision.hpp>
#include <eulervop/reference/settings.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace eulervop::app {

// The defaults of --torque-scales and --levels, and of the grid: fixed steps from K (four steps a
// period of the initial motion: on a small torque the VOP elements barely move, and their
// cheapest step is as long as the forcing allows) to K/6400, about doubling; one timed run per case.
extern const std::string default_torque_scales;
extern const std::string default_map_levels;
extern const grid_flag_defaults map_grid_defaults;

struct map_job : wp_job {
  std::vector<decimal> scales;
  std::vector<double> levels;  // increasing order of difficulty: as given
  std::vector<wp_grid> grids;  // one per scale
  std::string scene_name;
};

map_job map_job_of(const map_options& options);

}  // namespace eulervop::app
