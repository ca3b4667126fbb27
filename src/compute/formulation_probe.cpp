#include "compute/formulation_probe.hpp"

#include <eulervop/runs/comparison_run.hpp>
#include "compute/scene_library.hpp"

#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/rk/tableaux.hpp>

#include <fmt/format.h>

#include <stdexcept>

namespace eulervop::app {

std::string euler_only_reason(const scene& s) {
  if (s.is_coefficient_form())
    return "the paper's VOP does not apply to the coefficient form (its elements live in the normalized Eq. 5)";
  if (uses_direct_form(s))
    return fmt::format("the paper's VOP does not apply to this body (two moments are equal or within {} of each "
                       "other)",
                       direct_form_gap);
  return "";
}

std::vector<formulation> formulations_for(const scene& s, std::vector<formulation> preferred) {
  if (euler_only_reason(s).empty()) return preferred;
  return {formulation::euler};
}

void require_formulations_apply(const std::vector<formulation>& forms, const scene& s, const std::string& where) {
  const std::string why = euler_only_reason(s);
  if (why.empty()) return;
  for (formulation f : forms)
    if (f != formulation::euler)
      throw input_error(fmt::format("{}: formulation {} cannot run on scene `{}`: {}; only euler runs on it", where,
                                    formulation_name(f), s.name, why));
}

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
