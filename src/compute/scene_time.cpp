#include "compute/scene_time.hpp"

namespace eulervop::app {

scene_clock clock_of(const scene& s) {
  if (s.is_coefficient_form()) return {{"t", ""}, 1.0};
  if (!s.is_physical()) return {};
  return {{"t", "s"}, 1.0 / scaling_of<double>(s).tau_rate()};
}

}  // namespace eulervop::app
