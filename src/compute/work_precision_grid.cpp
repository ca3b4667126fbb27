#include "compute/work_precision_grid.hpp"

#include <fmt/format.h>

namespace eulervop::app {

void wp_grid::make_cases() {
  cases.clear();
  for (formulation f : forms)
    for (rk::method m : methods) {
      if (rk::is_fixed_step(m))
        for (std::size_t i = 0; i < steps.size(); ++i) cases.push_back({f, m, false, i});
      if (rk::is_adaptive(m))
        for (std::size_t i = 0; i < tols.size(); ++i) cases.push_back({f, m, true, i});
    }
}

std::string wp_grid::rung_text(const wp_case& c) const {
  return c.adaptive ? fmt::format("tol {}", tols[c.rung].text) : steps[c.rung].text;
}

std::string wp_grid::configuration(const wp_case& c) const {
  return fmt::format("{} {}", rk::method_name(c.method), rung_text(c));
}

}  // namespace eulervop::app
