#include "cli/grid_flags.hpp"

#include "cli/flags.hpp"
#include "compute/formulation_probe.hpp"
#include "compute/ladders.hpp"
#include "compute/scene_library.hpp"
#include "compute/scene_time.hpp"

#include <eulervop/rk/tableaux.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>

namespace eulervop::app {

namespace {
constexpr std::int64_t max_repeat = 1000;
constexpr std::int64_t max_jobs = 256;
}  // namespace

wp_grid grid_of(const scene& s, std::size_t samples, const grid_flags& f, const grid_flag_defaults& d) {
  wp_grid g;
  g.scn = s;
  g.samples = samples;
  const bool steps = f.steps || !f.tols;
  const bool tols = f.tols || !f.steps;
  // The formulations first: one the scene does not take is refused before its ladders are read.
  const std::vector<formulation> every(all_formulations.begin(), all_formulations.end());
  g.forms = chosen_formulations(f.formulations, {}, formulations_for(s, every));
  if (f.formulations) require_formulations_apply(g.forms, s, "--formulations " + *f.formulations);
  if (steps) g.steps = step_ladder(s, flag_list("--steps", f.steps.value_or(d.steps)), "--steps", !f.steps, samples);
  if (tols) g.tols = tol_ladder("--tols", f.tols.value_or(default_tol_ladder));
  g.max_step = max_step_of(s, f.max_step);
  g.methods = chosen_methods(f.methods, {}, {rk::all_methods.begin(), rk::all_methods.end()}, steps, tols);
  g.make_cases();
  probe_formulations(g.forms, s,
                     steps ? g.steps.front().choice.h : std::min(g.max_step.h, tau_end_of<double>(s)));
  return g;
}

wp_run_options run_options_of(const grid_flags& f, const grid_flag_defaults& d, std::string progress_label) {
  wp_run_options o;
  o.repeat = f.repeat ? static_cast<int>(flag_integer("--repeat", *f.repeat, 1, max_repeat)) : d.repeat;
  o.jobs = f.jobs ? static_cast<int>(flag_integer("--jobs", *f.jobs, 1, max_jobs)) : 1;
  o.progress_label = std::move(progress_label);
  return o;
}

std::string timing_text(const wp_run_options& o) {
  if (o.jobs == 1) return fmt::format("each time is the minimum of {} run(s), one case at a time", o.repeat);
  return fmt::format("each time is the minimum of {} run(s); --jobs {}: the timings were taken in parallel and are "
                     "less pure than with --jobs 1",
                     o.repeat, o.jobs);
}

nlohmann::ordered_json scene_time_json(const scene& s, double tau_end) {
  const scene_clock clock = clock_of(s);
  return {{"name", clock.unit.name},
          {"unit", clock.unit.unit.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(clock.unit.unit)},
          {"end", tau_end * clock.per_tau}};
}

scene work_precision_scene(const std::optional<std::string>& path, const scene_override_flags& flags, wp_job& job) {
  scene s = load_scene(path);
  // Error samples are step points of each run, about --samples of them; the scene's own sample
  // times and count are for `reference` and do not apply.
  s.times.clear();
  s.samples = 200;
  const applied_overrides applied = apply_scene_overrides(s, flags);
  job.overrides = applied.text();
  job.precision = applied.precision;
  job.settings = applied.settings;
  return s;
}

}  // namespace eulervop::app
