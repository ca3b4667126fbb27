#include "compute/progress.hpp"

#include <utility>

namespace eulervop::app {

namespace {
progress_display_factory& installed() {
  static progress_display_factory factory;
  return factory;
}
progress_clock& clock_in_use() {
  static progress_clock clock;
  return clock;
}
}  // namespace

void set_progress_display(progress_display_factory factory) { installed() = std::move(factory); }

std::unique_ptr<progress_display> open_progress(const std::string& label, double total, const progress_unit& unit) {
  return installed() ? installed()(label, total, unit) : nullptr;
}

const progress_clock& progress_time() { return clock_in_use(); }

progress_clock_scope::progress_clock_scope(progress_clock clock) : previous_(std::exchange(clock_in_use(), std::move(clock))) {}

progress_clock_scope::~progress_clock_scope() { clock_in_use() = std::move(previous_); }

}  // namespace eulervop::app
