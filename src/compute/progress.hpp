// How far a long computation has come, as compute/ reports it. compute/ knows no terminal: the
// program installs a display at start (set_progress_display; io/progress_line.hpp draws a line on
// a terminal's stderr), and where none is installed (a library use, a test) nothing is shown.
#pragma once

#include <functional>
#include <memory>
#include <string>

namespace eulervop::app {

// A display of one computation's progress: `update` as it goes, `clear` when it ends.
class progress_display {
 public:
  virtual ~progress_display() = default;
  virtual void update(double reached) = 0;
  virtual void clear() = 0;
};

// Makes the display of a computation named `label` that goes to `total`, counted in `unit`.
using progress_display_factory =
    std::function<std::unique_ptr<progress_display>(const std::string& label, double total, const std::string& unit)>;

// Installs the program's display (before any computation starts; not thread-safe).
void set_progress_display(progress_display_factory factory);

// A display for one computation, or nullptr where none is installed.
std::unique_ptr<progress_display> open_progress(const std::string& label, double total,
                                                const std::string& unit = "tau");

}  // namespace eulervop::app
