#include "io/progress_line.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <cstdio>

#include <unistd.h>

namespace eulervop::app {

namespace {
constexpr auto quiet_period = std::chrono::seconds(1);
constexpr auto redraw_period = std::chrono::milliseconds(100);
constexpr auto log_period = std::chrono::seconds(1);  // forced on a pipe or a file: a line a second
std::atomic<bool> all_disabled{false};

// "about 6 s left", "about 3 min left": from the mean rate so far, once there is one.
std::string time_left(double elapsed, double reached, double total) {
  if (!(reached > 0) || !(total > reached) || !std::isfinite(elapsed)) return "";
  const double left = elapsed * (total - reached) / reached;
  if (left < 90) return fmt::format(", about {:.0f} s left", std::ceil(left));
  if (left < 5400) return fmt::format(", about {:.0f} min left", std::ceil(left / 60));
  return fmt::format(", about {:.1f} h left", left / 3600);
}
}  // namespace

void progress_line::disable_all() { all_disabled = true; }

progress_line::progress_line(std::string label, double total, progress_unit unit, progress_mode mode)
    : label_(std::move(label)),
      total_(total),
      unit_(std::move(unit)),
      terminal_(::isatty(STDERR_FILENO) == 1),
      forced_(mode == progress_mode::on),
      start_(clock::now()),
      last_draw_(start_) {
  enabled_ = !all_disabled && mode != progress_mode::off && (forced_ || terminal_);
}

progress_line::~progress_line() { clear(); }

void progress_line::update(double reached, std::size_t segments) {
  if (!enabled_) return;
  const auto now = clock::now();
  if (!forced_ && now - start_ < quiet_period) return;
  if (drawn_ && now - last_draw_ < (terminal_ ? redraw_period : log_period)) return;
  last_draw_ = now;
  drawn_ = true;
  const double percent = total_ > 0 ? 100.0 * reached / total_ : 0.0;
  const std::string unit = unit_.unit.empty() ? "" : " " + unit_.unit;
  const std::string segs = segments ? fmt::format(", {} segments", segments) : "";
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const std::string text = fmt::format("{}: {} {:.6g} / {:.6g}{} ({:.0f}%){}{}", label_, unit_.name, reached, total_,
                                       unit, percent, segs, time_left(elapsed, reached, total_));
  if (terminal_)
    fmt::print(stderr, "\r {}\x1b[K", text);
  else
    fmt::print(stderr, "{}\n", text);
  std::fflush(stderr);
}

void progress_line::clear() {
  if (!drawn_ || !terminal_) return;
  fmt::print(stderr, "\r\x1b[K");
  std::fflush(stderr);
  drawn_ = false;
}

}  // namespace eulervop::app
