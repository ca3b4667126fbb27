// The outputs of `sweep`: sweep.csv (every run), cheapest.csv (the cheapest configuration per
// formulation and level), summary.json and the table on standard output.
#pragma once

#include "commands/sweep/sweep_job.hpp"
#include "compute/cheapest_configurations.hpp"
#include "compute/work_precision_grid.hpp"
#include "compute/work_precision_runs.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace eulervop::app {

std::string sweep_csv(const wp_grid& g, const wp_outcome& o);
std::string cheapest_csv(const wp_grid& g, const wp_outcome& o, const std::vector<level_choice>& levels);
nlohmann::ordered_json sweep_summary_json(const sweep_job& job, const wp_outcome& o,
                                          const std::vector<level_choice>& levels, double wall_seconds);
std::string sweep_table(const sweep_job& job, const wp_outcome& o, const std::vector<level_choice>& levels,
                        double wall_seconds);

}  // namespace eulervop::app
