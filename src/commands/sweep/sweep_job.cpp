#include "commands/sweep/sweep_job.hpp"

#include "cli/scene_overrides.hpp"
#include "compute/ladders.hpp"
#include "compute/scene_library.hpp"
#include "io/output_dir.hpp"

#include <cstdint>

namespace eulervop::app {

namespace {
constexpr std::int64_t default_samples = 200;
}  // namespace

const grid_flag_defaults sweep_grid_defaults{default_step_ladder, 3};

sweep_job sweep_job_of(const sweep_options& o) {
  sweep_job job;
  scene s = o.scene_path ? load_scene_file(*o.scene_path) : load_default_scene();

  // Error samples are step points of each run, about --samples of them; the scene's own sample
  // times and count are for `reference` and do not apply.
  s.times.clear();
  s.samples = default_samples;
  const applied_overrides applied = apply_scene_overrides(s, o.overrides);
  job.overrides = applied.text();
  job.precision = applied.precision;
  job.settings = applied.settings;
  job.run = run_options_of(o.grid, sweep_grid_defaults, "sweep");
  job.grid = grid_of(s, static_cast<std::size_t>(*s.samples), o.grid, sweep_grid_defaults);

  job.out_dir = out_dir_of(o.out_dir, "sweep");
  job.plot = !o.no_plot;
  return job;
}

}  // namespace eulervop::app
