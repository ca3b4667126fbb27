#include "commands/map/map_job.hpp"

#include "cli/flags.hpp"
#include "cli/scene_overrides.hpp"
#include "compute/formulation_probe.hpp"
#include "io/output_dir.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>

namespace eulervop::app {

const std::string default_torque_scales = "1e-6,1e-4,1e-2,1";
const std::string default_map_levels = "1e-6,1e-8,1e-10,1e-12";
const grid_flag_defaults map_grid_defaults{
    "K/1,K/2,K/3,K/6,K/12,K/25,K/50,K/100,K/200,K/400,K/800,K/1600,K/3200,K/6400", 1};

namespace {

bool is_vop(formulation f) { return f != formulation::euler; }

// The grid of the scene with its torque scaled by each scale (the decimals multiplied exactly).
std::vector<wp_grid> scaled_grids(const scene& base, const map_job& job, const map_options& o) {
  std::vector<wp_grid> grids;
  for (const decimal& scale : job.scales) {
    scene scaled = base;
    if (base.has_torque_law()) {  // formulas: each is multiplied by the scale's decimal text
      scaled.torque_law = std::make_shared<const torque_law>(scaled_law(*base.torque_law, scale.text));
      grids.push_back(grid_of(scaled, static_cast<std::size_t>(*base.samples), o.grid, map_grid_defaults));
      continue;
    }
    for (decimal& gi : *scaled.torque) {
      const auto product = decimal_product(gi, scale);
      if (!product)
        throw input_error(fmt::format("--torque-scales {}: {} times the torque {} is out of the range of a double",
                                      o.torque_scales.value_or(default_torque_scales), scale.text, gi.text));
      gi = *product;
    }
    grids.push_back(grid_of(scaled, static_cast<std::size_t>(*base.samples), o.grid, map_grid_defaults));
  }
  return grids;
}

}  // namespace

map_job map_job_of(const map_options& o) {
  map_job job;
  const scene base = work_precision_scene(o.scene_path, o.overrides, job);
  job.scene_name = base.name;

  job.scales = flag_ladder("--torque-scales", o.torque_scales.value_or(default_torque_scales));
  job.levels = level_ladder(o.levels.value_or(default_map_levels));
  if (!base.has_torque_law() && (!base.torque ||
      std::all_of(base.torque->begin(), base.torque->end(), [](const decimal& g) { return g.value == 0; })))
    throw input_error(fmt::format("scene `{}` has no torque to scale (give a scene with [torque] G or M)", base.name));
  if (const std::string why = euler_only_reason(base); !why.empty())
    throw input_error(fmt::format("scene `{}`: {}, so only euler runs on it, and the map compares euler with vop or "
                                  "vop-theta",
                                  base.name, why));
  job.run = run_options_of(o.grid, map_grid_defaults, "map");
  job.run.stop_below = *std::min_element(job.levels.begin(), job.levels.end());

  job.grids = scaled_grids(base, job, o);
  const std::vector<formulation>& forms = job.grids.front().forms;  // the same at every scale
  if (std::none_of(forms.begin(), forms.end(), is_vop) ||
      std::find(forms.begin(), forms.end(), formulation::euler) == forms.end())
    throw input_error(fmt::format("--formulations {}: the map compares euler with vop or vop-theta; give both kinds",
                                  o.grid.formulations.value_or("")));

  job.out_dir = out_dir_of(o.out_dir, "map");
  job.plot = !o.no_plot;
  return job;
}

}  // namespace eulervop::app
