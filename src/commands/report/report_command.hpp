// `eulervop report [SCENE] [options]`: the double-precision Euler and VOP runs at a fixed step
// (fixed_step_report.hpp) or under error control with --tols (adaptive_report.hpp), their Eq. 20
// errors against the reference, and the paper's Fig. 1.
#pragma once

#include "cli/scene_overrides.hpp"

#include "cli/cli11_fwd.hpp"

#include <optional>
#include <ostream>
#include <string>

namespace eulervop::app {

// The command's flags exactly as given (validated by run_report).
struct report_options {
  std::optional<std::string> scene_path;      // none: the embedded default scene
  scene_override_flags overrides;             // --tau-end/--t-end, --samples, --precision, --degree, --tolerance
  std::optional<std::string> reference_file;  // --reference FILE (a CSV of `eulervop reference`)
  std::optional<std::string> step;            // "K/N" or a number
  std::optional<std::string> tols;            // "1e-6,1e-8": adaptive runs instead of the fixed step
  std::optional<std::string> max_step;        // their largest step
  std::optional<std::string> methods;         // "rk4,rkf45"
  std::optional<std::string> formulations;    // "euler,vop"
  std::optional<std::string> out_dir;         // default ./eulervop-report/
  std::optional<std::string> format;          // table | json
  bool no_plot = false;
  bool verify = false;
};

// Registers the command's flags on `sub`, bound to `options`.
void add_report_flags(CLI::App& sub, report_options& options);

// Runs the command: input_error for bad scene, flags or reference file (before any computation
// and before anything is written); eulervop::numerical_failure when the reference integrator
// gives up. Prints the table (or summary.json) to `standard_output`; returns exit_success.
int run_report(const report_options& options, std::ostream& standard_output);

}  // namespace eulervop::app
