// The cheapest configuration of each formulation at error levels, from a grid's runs: what
// `sweep` and `map` tabulate.
#pragma once

#include "compute/work_precision_grid.hpp"
#include "compute/work_precision_runs.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace eulervop::app {

// The cheapest case per formulation whose max error is at most the level (diverged runs never),
// and the formulation with the cheapest of those.
struct level_choice {
  double level = 0;
  std::vector<std::optional<std::size_t>> best;  // per formulation (grid.forms order): case index
  std::optional<std::size_t> winner;             // index into grid.forms
};

std::vector<level_choice> cheapest_per_level(const wp_grid& grid, const wp_outcome& outcome,
                                             const std::vector<double>& levels);

// An error level as tables print it: "1e-08".
std::string level_text(double level);

}  // namespace eulervop::app
