#include "compute/grid_flags.hpp"

#include "compute/run_names.hpp"
#include "compute/scene_library.hpp"
#include "compute/scene_overrides.hpp"

#include <eulervop/rk/explicit_rk.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>

namespace eulervop::app {

namespace {
constexpr std::int64_t max_repeat = 1000;
constexpr std::int64_t max_jobs = 256;
}  // namespace

void add_grid_flags(CLI::App& sub, grid_flags& f, const grid_flag_defaults& d) {
  add_text_option(sub, "--steps", f.steps,
                  fmt::format("Comma-separated fixed steps: K/N (K of the initial modulus) or h (default: {})", d.steps))
      ->type_name("LIST");
  add_text_option(sub, "--tols", f.tols,
                  fmt::format("Comma-separated tolerances of the adaptive runs, atol = rtol (default: {}; with --steps "
                              "alone: none)",
                              default_tol_ladder))
      ->type_name("LIST");
  add_text_option(sub, "--max-step", f.max_step,
                  fmt::format("Largest step of the adaptive runs: K/N or h (default: {})", default_max_step))
      ->type_name("S");
  add_text_option(sub, "--methods", f.methods,
                  "Comma-separated: rk4,rkf45,dp45,rk8 at the fixed steps, rkf45,dp45,dop853 at the tolerances "
                  "(default: all)")
      ->type_name("LIST");
  add_text_option(sub, "--formulations", f.formulations,
                  "Comma-separated: " + joined(available_formulations()) + " (default: all)")
      ->type_name("LIST");
  add_text_option(sub, "--repeat", f.repeat,
                  fmt::format("Timed runs per case; the minimum time is kept (default: {})", d.repeat))
      ->type_name("N");
  add_text_option(sub, "--jobs", f.jobs, "Cases run in parallel (default: 1; above 1 the timings are less pure)")
      ->type_name("N");
}

wp_grid grid_of(const scene& s, std::size_t samples, const grid_flags& f, const grid_flag_defaults& d) {
  wp_grid g;
  g.scn = s;
  g.samples = samples;
  const bool steps = f.steps || !f.tols;
  const bool tols = f.tols || !f.steps;
  if (steps) g.steps = step_ladder(s, flag_list("--steps", f.steps.value_or(d.steps)), "--steps", !f.steps, samples);
  if (tols) g.tols = tol_ladder("--tols", f.tols.value_or(default_tol_ladder));
  resolve_max_step(g, f.max_step);
  if (f.formulations)
    g.forms = formulations_of(flag_list("--formulations", *f.formulations), "--formulations " + *f.formulations, "");
  else
    g.forms.assign(all_formulations.begin(), all_formulations.end());
  if (f.methods) {
    g.methods = methods_of(flag_list("--methods", *f.methods), "--methods " + *f.methods, "");
    check_methods_for_ladders(g.methods, steps, tols, "--methods " + *f.methods);
  } else {
    g.methods.assign(rk::all_methods.begin(), rk::all_methods.end());
  }
  g.make_cases();
  probe_formulations(g.forms, to_problem<double>(s),
                     steps ? g.steps.front().choice.h : std::min(g.h_max, tau_end_of<double>(s)));
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

}  // namespace eulervop::app
