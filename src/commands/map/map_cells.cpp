#include "commands/map/map_cells.hpp"

namespace eulervop::app {

std::vector<std::vector<map_cell>> cells_of(const map_job& job, const std::vector<wp_outcome>& outcomes) {
  std::vector<std::vector<map_cell>> out;
  for (std::size_t s = 0; s < job.grids.size(); ++s) {
    const wp_grid& g = job.grids[s];
    std::vector<map_cell> row;
    for (const level_choice& lc : cheapest_per_level(g, outcomes[s], job.levels)) {
      map_cell c;
      c.choice = lc;
      for (std::size_t f = 0; f < g.forms.size(); ++f) {
        if (!lc.best[f]) continue;
        const double t = outcomes[s].results[*lc.best[f]].seconds;
        if (g.forms[f] == formulation::euler) c.euler = f;
        else if (!c.best_vop || t < outcomes[s].results[*lc.best[*c.best_vop]].seconds) c.best_vop = f;
      }
      if (c.euler && c.best_vop)
        c.speedup =
            outcomes[s].results[*lc.best[*c.euler]].seconds / outcomes[s].results[*lc.best[*c.best_vop]].seconds;
      row.push_back(c);
    }
    out.push_back(std::move(row));
  }
  return out;
}

}  // namespace eulervop::app
