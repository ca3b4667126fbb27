#include "compute/run_names.hpp"

#include "compute/scene_library.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <string_view>
#include <stdexcept>

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

namespace {

// Names -> values by `from_name`; `kind` ("formulation", "method") and `available` for messages.
template <class V, class FromName>
std::vector<V> values_of(const std::vector<std::string>& names, const std::string& where, const std::string& hint,
                         std::string_view kind, FromName from_name, const std::vector<std::string>& available) {
  std::vector<V> out;
  for (const std::string& name : names) {
    const std::optional<V> v = from_name(name);
    if (!v)
      throw input_error(fmt::format("{}: {} `{}` is unknown (available: {}){}", where, kind, name, joined(available), hint));
    if (std::find(out.begin(), out.end(), *v) != out.end())
      throw input_error(fmt::format("{}: {} `{}` is listed twice", where, kind, name));
    out.push_back(*v);
  }
  return out;
}

}  // namespace

// `where` names the source in messages: "--formulations euler,foo" or "[run] formulations".
std::vector<formulation> formulations_of(const std::vector<std::string>& names, const std::string& where,
                                         const std::string& hint) {
  return values_of<formulation>(names, where, hint, "formulation", formulation_from_name, available_formulations());
}

std::vector<rk::method> methods_of(const std::vector<std::string>& names, const std::string& where,
                                   const std::string& hint) {
  return values_of<rk::method>(names, where, hint, "method", rk::method_from_name, available_methods());
}

void probe_formulations(const std::vector<formulation>& forms, const euler_problem<double>& problem, double h) {
  for (formulation f : forms) {
    try {
      (void)run_fixed(f, rk::method::rk4, problem, fixed_run_settings{h, 1, 1});
    } catch (const std::domain_error& e) {
      throw input_error(fmt::format("formulation {} cannot start from this scene: {} (leave it out with --formulations)",
                                    formulation_name(f), e.what()));
    }
  }
}

}  // namespace eulervop::app
