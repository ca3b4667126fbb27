// Command-line flags that override parts of a scene, shared by the commands: the span end
// (--tau-end / --t-end), the samples (--samples / --times) and the reference integrator's
// settings (--precision, --degree, --tolerance).
//
// The flags are kept as the user's text until they are applied to the scene they modify, so
// every message can name the flag, the value and the scene.
#pragma once

#include "compute/scene_library.hpp"

#include <eulervop/core/precision.hpp>
#include <eulervop/reference/settings.hpp>

#include <optional>
#include <string>
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

}  // namespace eulervop::app
