// How far a long computation has come, as compute/ reports it. compute/ knows no terminal: the
// program installs a display at start (set_progress_display; io/progress_line.hpp draws a line on
// a terminal's stderr), and where none is installed (a library use, a test) nothing is shown.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>

namespace eulervop::app {

// A display of one computation's progress: `update` as it goes, `clear` when it ends.
class progress_display {
 public:
  virtual ~progress_display() = default;
  // `segments`: the reference's segments accepted so far (0: not an integration).
  virtual void update(double reached, std::size_t segments) = 0;
  virtual void clear() = 0;
};

// What a display shows a computation's extent in: its name and unit ("t" and "s").
struct progress_unit {
  std::string name = "tau";
  std::string unit;  // after the total ("s"), or none
};

// Makes the display of a computation named `label` that goes to `total`, counted in `unit`.
using progress_display_factory = std::function<std::unique_ptr<progress_display>(
    const std::string& label, double total, const progress_unit& unit)>;

// Installs the program's display (before any computation starts; not thread-safe).
void set_progress_display(progress_display_factory factory);

// A display for one computation, or nullptr where none is installed.
std::unique_ptr<progress_display> open_progress(const std::string& label, double total,
                                                const progress_unit& unit = {});

// The time an integration in tau is shown in: the scene's own. A command that integrates a scene
// whose time is not tau (t = tau / (dtau/dt) of Eq. 4, in seconds for a physical scene) sets it
// for the duration of the command; progress_time() is what is set (tau, else).
struct progress_clock {
  progress_unit unit;
  double per_tau = 1;  // the shown time per unit of tau
};
const progress_clock& progress_time();

class progress_clock_scope {
 public:
  explicit progress_clock_scope(progress_clock clock);
  ~progress_clock_scope();
  progress_clock_scope(const progress_clock_scope&) = delete;
  progress_clock_scope& operator=(const progress_clock_scope&) = delete;

 private:
  progress_clock previous_;
};

}  // namespace eulervop::app
