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
      fixed_run_settings one{h, 1, 1};
      if (s.couples_attitude())  // its runs carry q
        one.attitude = attitude_settings{body_rates_of<double>(s), attitude_of<double>(s)};
      with_run_problem(s, [&](const auto& problem) { (void)run_fixed(f, rk::method::rk4, problem, one); });
    } catch (const std::domain_error& e) {
      throw input_error(
          fmt::format("formulation {} cannot start from this scene: {} (leave it out with --formulations)",
                      formulation_name(f), e.what()));
    }
  }
}

}  // namespace eulervop::app
