#include "compute/run_names.hpp"

#include <eulervop/rk/tableaux.hpp>
#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

namespace eulervop::app {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + std::string(n);
  return s;
}

std::vector<std::string> available_formulations() {
  std::vector<std::string> names;
  for (formulation f : all_formulations) names.emplace_back(formulation_name(f));
  return names;
}

std::vector<std::string> available_methods() {
  std::vector<std::string> names;
  for (rk::method m : rk::fixed_step_methods) names.emplace_back(rk::method_name(m));
  return names;
}

}  // namespace eulervop::app
