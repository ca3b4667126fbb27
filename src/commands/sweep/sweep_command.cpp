#include "commands/sweep/sweep_command.hpp"

#include "cli/command_flags.hpp"
#include "cli/exit_codes.hpp"
#include "commands/sweep/sweep_job.hpp"
#include "commands/sweep/sweep_output.hpp"
#include "compute/cheapest_configurations.hpp"
#include "io/figure.hpp"
#include "io/output_dir.hpp"

#include <chrono>
#include <vector>

namespace eulervop::app {

void add_sweep_flags(CLI::App& sub, sweep_options& o) {
  add_text_flag(sub, {"scene", "SCENE", "Scene file (TOML); default: the embedded paper scene"}, o.scene_path);
  add_grid_flags(sub, o.grid, sweep_grid_defaults);
  scene_override_set which;
  which.times = false;
  add_scene_override_flags(sub, o.overrides, which,
                           "About this many error samples per run, at its step points (default: 200)");
  add_output_flags(sub, o.out_dir, o.no_plot, "sweep", "work_precision");
}

int run_sweep(const sweep_options& options, std::ostream& standard_output) {
  const sweep_job job = sweep_job_of(options);
  const auto start = std::chrono::steady_clock::now();
  output_dir dir(job.out_dir, "sweep.csv");
  const std::vector<wp_outcome> outcomes = run_grids({job.grid}, job.precision, job.settings, job.run);
  const wp_outcome& o = outcomes.front();
  const std::vector<double> levels(sweep_error_levels.begin(), sweep_error_levels.end());
  const std::vector<level_choice> cheapest = cheapest_per_level(job.grid, o, levels);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  write_atomically(dir.path() / "sweep.csv", sweep_csv(job.grid, o));
  write_atomically(dir.path() / "cheapest.csv", cheapest_csv(job.grid, o, cheapest));
  write_atomically(dir.path() / "summary.json", sweep_summary_json(job, o, cheapest, wall).dump(2) + "\n");
  dir.keep();

  standard_output << sweep_table(job, o, cheapest, wall) << std::flush;
  if (job.plot) draw_figure(dir.path(), "plot_work_precision.py");
  return exit_success;
}

}  // namespace eulervop::app
