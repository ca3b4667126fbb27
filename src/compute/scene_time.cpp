#include "compute/scene_time.hpp"

#include <fmt/format.h>

namespace eulervop::app {

scene_clock clock_of(const scene& s) {
  if (s.is_coefficient_form()) return {{"t", ""}, 1.0};
  if (!s.is_physical()) return {};
  return {{"t", "s"}, 1.0 / scaling_of<double>(s).tau_rate()};
}

std::string scene_time_text(const scene& s, double tau, std::string_view equals) {
  const scene_clock clock = clock_of(s);
  const std::string in_tau = fmt::format("tau{}{:.6g}", equals, tau);
  if (clock.unit.name == "tau") return in_tau;
  std::string out = fmt::format("{}{}{:.6g}{}", clock.unit.name, equals, tau * clock.per_tau,
                                clock.unit.unit.empty() ? "" : " " + clock.unit.unit);
  if (s.is_physical() && !uses_direct_form(s)) out += fmt::format(" ({})", in_tau);
  return out;
}

}  // namespace eulervop::app
