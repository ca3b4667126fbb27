#include "compute/progress.hpp"

#include <fmt/format.h>

#include <utility>

namespace eulervop::app {

namespace {
progress_display_factory& installed() {
  static progress_display_factory factory;
  return factory;
}
// Per thread: two commands may run at once in one process (the Python module).
scene_clock& clock_in_use() {
  thread_local scene_clock clock;
  return clock;
}
}  // namespace

void set_progress_display(progress_display_factory factory) { installed() = std::move(factory); }

std::unique_ptr<progress_display> open_progress(const std::string& label, double total, const progress_unit& unit) {
  return installed() ? installed()(label, total, unit) : nullptr;
}

std::string scene_clock::at(double tau, int digits) const {
  const std::string tau_text = fmt::format("tau={:.{}g}", tau, digits);
  if (unit.name == "tau") return tau_text;
  return fmt::format("{}={:.{}g}{} ({})", unit.name, tau * per_tau, digits, unit.unit.empty() ? "" : " " + unit.unit,
                     tau_text);
}

const scene_clock& scene_time() { return clock_in_use(); }

scene_clock_scope::scene_clock_scope(scene_clock clock) : previous_(std::exchange(clock_in_use(), std::move(clock))) {}

scene_clock_scope::~scene_clock_scope() { clock_in_use() = std::move(previous_); }

}  // namespace eulervop::app
