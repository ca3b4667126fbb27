#include "io/progress_line.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cstdio>

#include <unistd.h>

namespace eulervop::app {

namespace {
constexpr auto quiet_period = std::chrono::seconds(1);
constexpr auto redraw_period = std::chrono::milliseconds(100);
std::atomic<bool> all_disabled{false};
}  // namespace

void progress_line::disable_all() { all_disabled = true; }

progress_line::progress_line(std::string label, double total, std::string unit)
    : label_(std::move(label)), total_(total), unit_(std::move(unit)), enabled_(!all_disabled && ::isatty(STDERR_FILENO) == 1),
      start_(clock::now()), last_draw_(start_) {}

progress_line::~progress_line() { clear(); }

void progress_line::update(double reached) {
  if (!enabled_) return;
  const auto now = clock::now();
  if (now - start_ < quiet_period || (drawn_ && now - last_draw_ < redraw_period)) return;
  last_draw_ = now;
  drawn_ = true;
  const double percent = total_ > 0 ? 100.0 * reached / total_ : 0.0;
  fmt::print(stderr, "\r {}: {} {:.4g} / {:.4g} ({:.0f}%)\x1b[K", label_, unit_, reached, total_, percent);
  std::fflush(stderr);
}

void progress_line::clear() {
  if (!drawn_) return;
  fmt::print(stderr, "\r\x1b[K");
  std::fflush(stderr);
  drawn_ = false;
}

}  // namespace eulervop::app
