// The outputs of `map`: map.csv (the cheapest configurations per scale and level), runs.csv
// (every run), summary.json and the tables on standard output.
#pragma once

#include "commands/map/map_cells.hpp"
#include "commands/map/map_job.hpp"
#include "compute/work_precision_runs.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace eulervop::app {

using map_cells = std::vector<std::vector<map_cell>>;

std::string map_csv(const map_job& job, const std::vector<wp_outcome>& outcomes, const map_cells& cells);
std::string map_runs_csv(const map_job& job, const std::vector<wp_outcome>& outcomes);
nlohmann::ordered_json map_summary_json(const map_job& job, const std::vector<wp_outcome>& outcomes,
                                        const map_cells& cells, double wall);
std::string map_table(const map_job& job, const std::vector<wp_outcome>& outcomes, const map_cells& cells,
                      double wall);

}  // namespace eulervop::app
