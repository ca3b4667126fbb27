// A single updating progress line on standard error.
//
// Progress goes to stderr, only when it is a terminal, and only once a run has taken more than
// a second (short runs and pipelines stay silent). The line is cleared when the run ends, so the
// terminal is left as it was (docs/design.md section 5.3). It is the display that the program
// installs for compute/'s progress (compute/progress.hpp).
#pragma once

#include "compute/progress.hpp"

#include <chrono>
#include <string>

namespace eulervop::app {

class progress_line final : public progress_display {
 public:
  // `label` names the stage ("reference", "verify"); `total` is how far the run goes, in
  // `unit` ("tau" by default; "case" for a sweep).
  progress_line(std::string label, double total, std::string unit = "tau");
  ~progress_line() override;
  progress_line(const progress_line&) = delete;
  progress_line& operator=(const progress_line&) = delete;

  // "\r reference: tau 12.3 / 136 (9%)", at most ten times a second.
  void update(double reached) override;
  // Erases the line if one was drawn.
  void clear() override;

  // Turns every progress line off for the rest of the process (`batch`, where several runs
  // share one terminal from several threads).
  static void disable_all();

 private:
  using clock = std::chrono::steady_clock;
  std::string label_;
  double total_;
  std::string unit_;
  bool enabled_;
  bool drawn_ = false;
  clock::time_point start_, last_draw_;
};

}  // namespace eulervop::app
