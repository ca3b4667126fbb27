// The flags that choose a work-precision grid (work_precision_grid.hpp) and how its runs are
// timed, shared by `sweep` and `map`: --steps, --tols, --max-step, --methods, --formulations,
// --repeat and --jobs.
#pragma once

#include "cli/scene_overrides.hpp"
#include "compute/scene_library.hpp"
#include "compute/work_precision_grid.hpp"
#include "compute/work_precision_runs.hpp"

#include <eulervop/core/precision.hpp>
#include <eulervop/reference/settings.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

namespace eulervop::app {

// The flags exactly as given.
struct grid_flags {
  std::optional<std::string> steps;         // "K/25,K/100,0.01": the fixed-step ladder
  std::optional<std::string> tols;          // "1e-6,1e-8": the tolerance ladder (atol = rtol)
  std::optional<std::string> max_step;      // the adaptive runs' largest step, "K/N" or h
  std::optional<std::string> methods;       // "rk4,dop853"
  std::optional<std::string> formulations;  // "euler,vop"
  std::optional<std::string> repeat;        // timed runs per case (the minimum is kept)
  std::optional<std::string> jobs;          // cases run in parallel
};

// What differs between the commands.
struct grid_flag_defaults {
  std::string steps;  // the fixed-step ladder, "K/25,K/50,..."
  int repeat = 1;
};

// The grid of `s` the flags ask for: both ladders unless only one is given, every formulation the
// scene takes (euler alone for the coefficient and direct forms, formulation_probe.hpp) and every
// method unless listed (the scene's [run] lists choose the runs of `report`, not a grid's), the
// cases made and the formulations probed at the first step. input_error naming the flag and its
// value otherwise, and for a listed formulation the scene does not take.
wp_grid grid_of(const scene& s, std::size_t samples, const grid_flags& flags, const grid_flag_defaults& defaults);

// --repeat and --jobs (input_error naming the flag and its value).
wp_run_options run_options_of(const grid_flags& flags, const grid_flag_defaults& defaults, std::string progress_label);

// What `sweep` and `map` share of their jobs: the flags that changed the scene, how the runs
// are timed, the reference's precision and settings, and where the outputs go.
struct wp_job {
  std::string overrides;
  wp_run_options run;
  eulervop::precision precision;
  picard_settings settings;
  std::filesystem::path out_dir;
  bool plot = true;
};

// The scene of a sweep or a map: the file (or the embedded default) with about 200 error samples
// in place of its own sample times (those are for `reference`), and the scene flags applied;
// job's overrides, precision and settings are theirs.
scene work_precision_scene(const std::optional<std::string>& path, const scene_override_flags& flags, wp_job& job);

// "each time is the minimum of 3 run(s), one case at a time", for the summary and the figure.
std::string timing_text(const wp_run_options& o);

// The time the outputs of a grid of scene `s` speak, for summary.json: {"name": "t", "unit": "s",
// "end": the span's end in it} (unit null for tau and the coefficient form's t), the unit of their
// `h` and `diverged_at` too (compute/scene_time.hpp).
nlohmann::ordered_json scene_time_json(const scene& s, double tau_end);

}  // namespace eulervop::app
