#include "compute/progress.hpp"

#include <utility>

namespace eulervop::app {

namespace {
progress_display_factory& installed() {
  static progress_display_factory factory;
  return factory;
}
}  // namespace

void set_progress_display(progress_display_factory factory) { installed() = std::move(factory); }

std::unique_ptr<progress_display> open_progress(const std::string& label, double total, const std::string& unit) {
  return installed() ? installed()(label, total, unit) : nullptr;
}

}  // namespace eulervop::app
