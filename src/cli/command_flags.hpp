// How a command's flags reach its subcommand: a flag's definition (its name, the name of its
// value and its help), registered with its value kept as the user's text (flags.hpp parses it
// once the command knows what it modifies), and the sets of flags several commands share: the
// output directory, the scene overrides and the work-precision grid.
#pragma once

#include "cli/grid_flags.hpp"
#include "cli/scene_overrides.hpp"

#include "cli/cli11_fwd.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eulervop::app {

struct flag_def {
  std::string name;        // "--samples", or a positional's name ("scene")
  std::string value_name;  // "N" in the help; empty for a switch
  std::string help;
  // The same flag described by another command (`batch` says it of every scene).
  flag_def described(std::string other_help) const { return {name, value_name, std::move(other_help)}; }
};

CLI::Option* add_text_flag(CLI::App& sub, const flag_def& flag, std::optional<std::string>& text);
CLI::Option* add_switch(CLI::App& sub, const flag_def& flag, bool& on);
// A flag the command needs.
void add_required_text_flag(CLI::App& sub, const flag_def& flag, std::optional<std::string>& text);
// A positional argument the command needs (its value_name names it in the help), and one that
// takes every remaining word.
void add_required_positional(CLI::App& sub, const flag_def& arg, std::string& value);
void add_positional_list(CLI::App& sub, const flag_def& arg, std::vector<std::string>& values);

// " --name value" (the value one word for sh), or "" for a flag not given: the flag as a command
// line that the program writes states it.
std::string command_line_text(const flag_def& flag, const std::optional<std::string>& text);
std::string command_line_text(const flag_def& flag, bool on);

// --out-dir (default ./eulervop-<command>/) and --no-plot (of the figure <figure>.png/.svg).
void add_output_flags(CLI::App& sub, std::optional<std::string>& out_dir, bool& no_plot, std::string_view command,
                      std::string_view figure);

// ---- the scene overrides (scene_overrides.hpp) --------------------------------------------------

namespace override_flags {
// --samples has no help of its own: each command describes it in its own terms.
extern const flag_def precision, tau_end, t_end, samples, times, degree, tolerance;
}  // namespace override_flags

// Which of the overrides a command offers (the others are not registered).
struct scene_override_set {
  bool span = true;       // --tau-end, --t-end
  bool samples = true;    // --samples
  bool times = true;      // --times
  bool reference = true;  // --precision, --degree, --tolerance
};

void add_scene_override_flags(CLI::App& sub, scene_override_flags& flags, scene_override_set which,
                              const std::string& samples_help);

// ---- the work-precision grid of `sweep` and `map` (grid_flags.hpp) ---------------------------------

void add_grid_flags(CLI::App& sub, grid_flags& flags, const grid_flag_defaults& defaults);

}  // namespace eulervop::app
