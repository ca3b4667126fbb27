// Command-line flags that override parts of a scene, shared by the subcommands (`reference`,
// `report`): the span end (--tau-end / --t-end), the samples (--samples / --times) and the
// reference integrator's settings (--precision, --degree, --tolerance).
//
// The flags are kept as the user's text until they are applied, so every message can quote it.
#pragma once

#include "compute/scene_library.hpp"

#include <eulervop/reference/integrate.hpp>
#include <eulervop/core/scalar.hpp>

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eulervop::app {

struct scene_override_flags {
  std::optional<std::string> tau_end;    // normalized scenes
  std::optional<std::string> t_end;      // physical scenes
  std::optional<std::string> samples;
  std::optional<std::string> times;      // comma-separated, tau (normalized) or t (physical)
  std::optional<std::string> precision;  // double | quad | mpfr:BITS, overrides [reference]
  std::optional<std::string> degree;
  std::optional<std::string> tolerance;
};

// Which of the flags a subcommand offers (the others are not registered).
struct scene_override_set {
  bool span = true;       // --tau-end, --t-end
  bool samples = true;    // --samples
  bool times = true;      // --times
  bool reference = true;  // --precision, --degree, --tolerance
};

// Registers an option whose value is kept as the text the user typed: flags are parsed when the
// scene they modify is known, so that errors can name the flag, the value and the scene.
CLI::Option* add_text_option(CLI::App& sub, const std::string& name, std::optional<std::string>& target,
                             const std::string& help);

// --out-dir (default ./eulervop-<command>/) and --no-plot (of the figure <figure>.png/.svg).
void add_output_flags(CLI::App& sub, std::optional<std::string>& out_dir, bool& no_plot, std::string_view command,
                      std::string_view figure);

// Registers the flags of `which` on `sub`, binding them to `flags`. `samples_help` describes
// --samples in the subcommand's own terms.
void add_scene_override_options(CLI::App& sub, scene_override_flags& flags, scene_override_set which,
                                const std::string& samples_help);

// What applying the flags gives besides the changed scene.
struct applied_overrides {
  eulervop::precision precision;   // --precision, else the scene's [reference] precision
  picard_settings settings;        // --degree/--tolerance, else [reference], else automatic
  std::vector<std::string> flags;  // "--tau-end=5", ... : the flags that changed something
  std::string text() const;        // those flags joined by spaces, for metadata
};

// Applies the flags to `s` (span end, samples, times) and resolves the reference settings.
// Throws input_error naming the flag and its value.
applied_overrides apply_scene_overrides(scene& s, const scene_override_flags& flags);

// ---- flag value parsing (input_error names the flag and the text) ----------------------------

decimal flag_number(std::string_view flag, const std::string& text);
decimal positive_flag_number(std::string_view flag, const std::string& text);
std::int64_t flag_integer(std::string_view flag, const std::string& text, std::int64_t lo, std::int64_t hi);
// "a,b,c": the items, none empty (input_error naming the flag otherwise).
std::vector<std::string> flag_list(std::string_view flag, const std::string& text);
// "1e-4,1e-6,1e-8": positive finite numbers, strictly increasing or strictly decreasing (a
// ladder); input_error naming the flag and the offending item otherwise.
std::vector<decimal> flag_ladder(std::string_view flag, const std::string& text);

}  // namespace eulervop::app
