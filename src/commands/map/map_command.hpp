// `eulervop map [SCENE] [options]`: where VOP pays. The scene's torque is scaled by each of
// --torque-scales; at each scale every formulation runs on a ladder of fixed steps and one of
// tolerances with every method (work_precision_grid.hpp); for each scale and error level the
// cheapest configuration of each formulation is found, and the speed-up of the best VOP
// formulation over the direct Euler equations. map.csv, runs.csv, summary.json and
// regime_map.png/.svg.
#pragma once

#include "cli/grid_flags.hpp"
#include "cli/scene_overrides.hpp"

#include "cli/cli11_fwd.hpp"

#include <optional>
#include <ostream>
#include <string>

namespace eulervop::app {

// The command's flags exactly as given (validated by run_map).
struct map_options {
  std::optional<std::string> scene_path;     // none: the embedded default scene
  scene_override_flags overrides;            // --tau-end/--t-end, --samples, --precision, --degree, --tolerance
  std::optional<std::string> torque_scales;  // "1e-6,1e-4,1e-2,1"
  std::optional<std::string> levels;         // "1e-6,1e-8,1e-10,1e-12"
  grid_flags grid;                           // --steps, --tols, --max-step, --methods, --formulations, --repeat, --jobs
  std::optional<std::string> out_dir;        // default ./eulervop-map/
  bool no_plot = false;
};

// Registers the command's flags on `sub`, bound to `options`.
void add_map_flags(CLI::App& sub, map_options& options);

// Runs the command: input_error for bad scene or flags (before any computation and before
// anything is written); eulervop::numerical_failure when a reference gives up. Prints the map to
// `standard_output`; returns exit_success.
int run_map(const map_options& options, std::ostream& standard_output);

}  // namespace eulervop::app
