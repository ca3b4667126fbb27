#include "compute/formulation_probe.hpp"

#include <eulervop/runs/comparison_run.hpp>
#include "compute/scene_library.hpp"

#include <eulervop/rk/tableaux.hpp>

#include <fmt/format.h>

#include <stdexcept>

namespace eulervop::app {

void probe_formulations(const std::vector<formulation>& forms, const scene& s, double h) {
  for (formulation f : forms) {
    try {
      with_problem<double>(s, [&](const auto& problem) { (void)run_fixed(f, rk::method::rk4, problem, fixed_run_settings{h, 1, 1}); });
    } catch (const std::domain_error& e) {
      throw input_error(
          fmt::format("formulation {} cannot start from this scene: {} (leave it out with --formulations)",
                      formulation_name(f), e.what()));
    }
  }
}

}  // namespace eulervop::app
