#include "commands/map/map_command.hpp"

#include "cli/command_flags.hpp"
#include "cli/exit_codes.hpp"
#include "commands/map/map_cells.hpp"
#include "commands/map/map_job.hpp"
#include "commands/map/map_output.hpp"
#include "io/figure.hpp"
#include "io/output_dir.hpp"

#include <chrono>
#include <vector>

namespace eulervop::app {

void add_map_flags(CLI::App& sub, map_options& o) {
  add_text_flag(sub, {"scene", "SCENE", "Scene file (TOML) with a torque; default: the embedded paper scene"},
                o.scene_path);
  add_text_flag(sub,
                {"--torque-scales", "LIST",
                 "Comma-separated factors of the scene's torque (default: " + default_torque_scales + ")"},
                o.torque_scales);
  add_text_flag(sub, {"--levels", "LIST", "Comma-separated max-error levels (default: " + default_map_levels + ")"},
                o.levels);
  add_grid_flags(sub, o.grid, map_grid_defaults);
  scene_override_set which;
  which.times = false;
  add_scene_override_flags(sub, o.overrides, which, "About this many error samples per run (default: 200)");
  add_output_flags(sub, o.out_dir, o.no_plot, "map", "regime_map");
}

int run_map(const map_options& options, std::ostream& standard_output) {
  const map_job job = map_job_of(options);
  const auto start = std::chrono::steady_clock::now();
  output_dir dir(job.out_dir, "map.csv");
  const std::vector<wp_outcome> outcomes = run_grids(job.grids, job.precision, job.settings, job.run);
  const map_cells cells = cells_of(job, outcomes);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  write_atomically(dir.path() / "map.csv", map_csv(job, outcomes, cells));
  write_atomically(dir.path() / "runs.csv", map_runs_csv(job, outcomes));
  write_atomically(dir.path() / "summary.json", map_summary_json(job, outcomes, cells, wall).dump(2) + "\n");
  dir.keep();
  standard_output << map_table(job, outcomes, cells, wall) << std::flush;
  if (job.plot) draw_figure(dir.path(), "plot_regime_map.py");
  return exit_success;
}

}  // namespace eulervop::app
