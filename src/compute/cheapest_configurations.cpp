#include "compute/cheapest_configurations.hpp"

#include <fmt/format.h>

namespace eulervop::app {

std::string level_text(double level) { return fmt::format("{:.0e}", level); }

std::vector<level_choice> cheapest_per_level(const wp_grid& g, const wp_outcome& o, const std::vector<double>& levels) {
  std::vector<level_choice> out;
  for (double level : levels) {
    level_choice lc;
    lc.level = level;
    lc.best.resize(g.forms.size());
    for (std::size_t f = 0; f < g.forms.size(); ++f) {
      for (std::size_t i = 0; i < g.cases.size(); ++i) {
        if (g.cases[i].form != g.forms[f]) continue;
        const wp_result& r = o.results[i];
        if (r.skipped || r.run.diverged() || !r.max_error || !(*r.max_error <= level)) continue;
        if (!lc.best[f] || r.seconds < o.results[*lc.best[f]].seconds) lc.best[f] = i;
      }
      if (lc.best[f] && (!lc.winner || o.results[*lc.best[f]].seconds < o.results[*lc.best[*lc.winner]].seconds))
        lc.winner = f;
    }
    out.push_back(std::move(lc));
  }
  return out;
}

}  // namespace eulervop::app
