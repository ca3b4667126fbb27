// `eulervop reference [SCENE] [options]`: the high-precision reference solution as CSV
// (layout in the README, "Command line").
#pragma once

#include "cli/command_flags.hpp"
#include "cli/scene_overrides.hpp"

#include "cli/cli11_fwd.hpp"

#include <optional>
#include <ostream>
#include <string>

namespace eulervop::app {

// The command's flags exactly as given (validated by run_reference, so every message can
// quote the user's text).
struct reference_options {
  std::optional<std::string> scene_path;  // none: the embedded default scene
  scene_override_flags overrides;         // --tau-end, --samples, --precision, ...
  std::optional<std::string> out;         // none: standard output
  bool verify = false;
  bool certify = false;
  // Not flags: set by main() and by `batch`.
  std::string command;       // "# command: ..." (the argv that made the file, without --out); none if empty
  bool omit_timing = false;  // leave out the "# wall_seconds" lines (batch: byte-identical reruns)
  bool certify_one_thread = false;  // --certify on one thread (batch --jobs > 1: scenes share the cores)
};

// The switches of `reference`, which `batch` passes on to every scene's run.
namespace reference_flags {
extern const flag_def verify, certify;
}  // namespace reference_flags

// Registers the command's flags on `sub`, bound to `options`.
void add_reference_flags(CLI::App& sub, reference_options& options);

// Runs the command. Throws input_error (bad scene or flags, before any computation) and
// eulervop::numerical_failure (the integrator gave up). Writes the CSV to `--out` atomically,
// or to `standard_output`; returns exit_success.
int run_reference(const reference_options& options, std::ostream& standard_output);

}  // namespace eulervop::app
