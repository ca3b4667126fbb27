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
// for the duration of the command, on its thread; scene_time() is what is set (tau, else).
struct scene_clock {
  progress_unit unit;
  double per_tau = 1;  // the shown time per unit of tau

  // "t=50 s (tau=14.4337567)", or "tau=14.4337567" when the scene's time is tau: where
  // something happened, in the scene's own time first, to `digits` significant digits.
  std::string at(double tau, int digits = 9) const;
};
const scene_clock& scene_time();

class scene_clock_scope {
 public:
  explicit scene_clock_scope(scene_clock clock);
  ~scene_clock_scope();
  scene_clock_scope(const scene_clock_scope&) = delete;
  scene_clock_scope& operator=(const scene_clock_scope&) = delete;

 private:
  scene_clock previous_;
};

}  // namespace eulervop::app
