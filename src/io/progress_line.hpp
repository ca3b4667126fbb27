// A single updating progress line on standard error.
//
// By default progress goes to stderr only when it is a terminal, and only once a run has taken
// more than a second (short runs and pipelines stay silent). --progress shows it from the start
// even on a pipe or a file (one line a second there, each ending in a newline); --quiet never. On
// a terminal the line is cleared when the run ends, so the terminal is left as it was
// (docs/design.md section 5.3). Standard output and the output files never change. It is the
// display that the program installs for compute/'s progress (compute/progress.hpp).
#pragma once

#include "compute/progress.hpp"

#include <chrono>
#include <string>

namespace eulervop::app {

enum class progress_mode { automatic, on, off };

class progress_line final : public progress_display {
 public:
  // `label` names the stage ("reference", "verify"); `total` is how far the run goes, in `unit`.
  progress_line(std::string label, double total, progress_unit unit, progress_mode mode = progress_mode::automatic);
  ~progress_line() override;
  progress_line(const progress_line&) = delete;
  progress_line& operator=(const progress_line&) = delete;

  // "reference: t 1230 / 3600 s (34%), 812 segments, about 6 s left"
  void update(double reached, std::size_t segments) override;
  // Erases the line if one was drawn on a terminal.
  void clear() override;

  // Turns every progress line off for the rest of the process (`batch`, where several runs
  // share one terminal from several threads).
  static void disable_all();

 private:
  using clock = std::chrono::steady_clock;
  std::string label_;
  double total_;
  progress_unit unit_;
  bool enabled_;
  bool terminal_;
  bool forced_;
  bool drawn_ = false;
  clock::time_point start_, last_draw_;
};

}  // namespace eulervop::app
