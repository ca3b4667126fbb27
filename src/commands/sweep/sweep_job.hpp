// What a `sweep` computes, from its flags: the grid of one scene, how its runs are timed, the
// reference's settings and where the outputs go.
#pragma once

#include "cli/grid_flags.hpp"
#include "commands/sweep/sweep_command.hpp"
#include "compute/work_precision_grid.hpp"
#include "compute/work_precision_runs.hpp"

#include <eulervop/core/precision.hpp>
#include <eulervop/reference/settings.hpp>

#include <array>
#include <filesystem>
#include <string>

namespace eulervop::app {

// The default ladder of fixed steps and three timed runs per case.
extern const grid_flag_defaults sweep_grid_defaults;

// The error levels of the cheapest-configuration table.
inline constexpr std::array<double, 5> sweep_error_levels = {1e-4, 1e-6, 1e-8, 1e-10, 1e-12};

struct sweep_job : wp_job {
  wp_grid grid;
  std::string note;  // why only euler runs (the coefficient and direct forms), or empty
};

sweep_job sweep_job_of(const sweep_options& options);

}  // namespace eulervop::app
