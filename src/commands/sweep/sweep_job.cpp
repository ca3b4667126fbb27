#include "commands/sweep/sweep_job.hpp"

#include "cli/scene_overrides.hpp"
#include "compute/formulation_probe.hpp"
#include "compute/ladders.hpp"
#include "compute/scene_library.hpp"
#include "io/output_dir.hpp"

#include <cstdint>

namespace eulervop::app {

const grid_flag_defaults sweep_grid_defaults{default_step_ladder, 3};

sweep_job sweep_job_of(const sweep_options& o) {
  sweep_job job;
  const scene s = work_precision_scene(o.scene_path, o.overrides, job);
  job.run = run_options_of(o.grid, sweep_grid_defaults, "sweep");
  job.grid = grid_of(s, static_cast<std::size_t>(*s.samples), o.grid, sweep_grid_defaults);
  if (const std::string why = euler_only_reason(s); !why.empty()) job.note = why + ", so only euler runs";

  job.out_dir = out_dir_of(o.out_dir, "sweep");
  job.plot = !o.no_plot;
  return job;
}

}  // namespace eulervop::app
