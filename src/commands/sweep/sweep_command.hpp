// `eulervop sweep [SCENE] [options]`: work against precision. Every formulation x method x fixed
// step of a geometric ladder, and x tolerance of a ladder for the methods with an embedded pair
// (work_precision_grid.hpp), each run timed (the minimum of --repeat runs) and measured (Eq. 20,
// max over samples and final) against one reference; sweep.csv, the cheapest configuration per
// formulation at error levels 1e-4 ... 1e-12 (cheapest.csv and a table), summary.json and the
// work-precision figure.
#pragma once

#include "cli/grid_flags.hpp"
#include "cli/scene_overrides.hpp"

#include "cli/cli11_fwd.hpp"

#include <optional>
#include <ostream>
#include <string>

namespace eulervop::app {

// The command's flags exactly as given (validated by run_sweep).
struct sweep_options {
  std::optional<std::string> scene_path;    // none: the embedded default scene
  scene_override_flags overrides;           // --tau-end/--t-end, --samples, --precision, --degree, --tolerance
  grid_flags grid;                          // --steps, --tols, --max-step, --methods, --formulations, --repeat, --jobs
  std::optional<std::string> out_dir;       // default ./eulervop-sweep/
  bool no_plot = false;
};

// Registers the command's flags on `sub`, bound to `options`.
void add_sweep_flags(CLI::App& sub, sweep_options& options);

// Runs the command: input_error for bad scene or flags (before any computation and before
// anything is written); eulervop::numerical_failure when the reference integrator gives up.
// Prints the grid and the cheapest table to `standard_output`; returns exit_success.
int run_sweep(const sweep_options& options, std::ostream& standard_output);

}  // namespace eulervop::app
