#include "commands/map_command.hpp"

#include "io/figure.hpp"
#include "compute/grid_flags.hpp"
#include "io/output_cells.hpp"
#include "io/output_dir.hpp"
#include "compute/run_names.hpp"
#include "compute/scene_library.hpp"
#include "io/text_table.hpp"
#include "compute/work_precision.hpp"

#include <eulervop/runs/comparison_run.hpp>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <vector>

namespace eulervop::app {

namespace fs = std::filesystem;

namespace {

constexpr std::int64_t default_samples = 200;
const std::string default_scales = "1e-6,1e-4,1e-2,1";
const std::string default_levels = "1e-6,1e-8,1e-10,1e-12";
// From K (four steps a period of the initial motion: on a small torque the VOP elements barely
// move, and their cheapest step is as long as the forcing allows) to K/6400, about doubling.
const std::string default_map_steps =
    "K/1,K/2,K/3,K/6,K/12,K/25,K/50,K/100,K/200,K/400,K/800,K/1600,K/3200,K/6400";
const grid_flag_defaults defaults{default_map_steps, 1};

struct map_job {
  std::vector<decimal> scales;
  std::vector<double> levels;  // increasing order of difficulty: as given
  std::vector<wp_grid> grids;  // one per scale
  std::string scene_name;
  std::string overrides;
  wp_run_options run;
  eulervop::precision precision;
  picard_settings settings;
  fs::path out_dir;
  bool plot = true;
};

bool is_vop(formulation f) { return f != formulation::euler; }

map_job make_job(const map_options& o) {
  map_job job;
  scene base = o.scene_path ? load_scene_file(*o.scene_path) : load_default_scene();
  base.times.clear();
  base.samples = default_samples;
  const applied_overrides applied = apply_scene_overrides(base, o.overrides);
  job.overrides = applied.text();
  job.precision = applied.precision;
  job.settings = applied.settings;
  job.scene_name = base.name;

  job.scales = flag_ladder("--torque-scales", o.torque_scales.value_or(default_scales));
  for (const decimal& d : flag_ladder("--levels", o.levels.value_or(default_levels))) {
    if (!(d.value < 1))
      throw input_error(fmt::format("--levels {}: {} is not below 1 (a level is a max Eq. 20 error)", *o.levels, d.text));
    job.levels.push_back(d.value);
  }
  if (!base.torque || std::all_of(base.torque->begin(), base.torque->end(), [](const decimal& g) { return g.value == 0; }))
    throw input_error(fmt::format("scene `{}` has no torque to scale (give a scene with [torque] G or M)", base.name));
  job.run = run_options_of(o.grid, defaults, "map");
  job.run.stop_below = *std::min_element(job.levels.begin(), job.levels.end());

  for (const decimal& scale : job.scales) {
    scene scaled = base;
    for (decimal& gi : *scaled.torque) {
      const auto product = decimal_product(gi, scale);
      if (!product)
        throw input_error(fmt::format("--torque-scales {}: {} times the torque {} is out of the range of a double",
                                      o.torque_scales.value_or(default_scales), scale.text, gi.text));
      gi = *product;
    }
    job.grids.push_back(grid_of(scaled, static_cast<std::size_t>(*base.samples), o.grid, defaults));
  }
  const std::vector<formulation>& forms = job.grids.front().forms;  // the same at every scale
  if (std::none_of(forms.begin(), forms.end(), is_vop) ||
      std::find(forms.begin(), forms.end(), formulation::euler) == forms.end())
    throw input_error(fmt::format("--formulations {}: the map compares euler with vop or vop-theta; give both kinds",
                                  o.grid.formulations.value_or("")));

  job.out_dir = out_dir_of(o.out_dir, "map");
  job.plot = !o.no_plot;
  return job;
}

// ---- the map ------------------------------------------------------------------------------------

// One cell: a scale and a level.
struct map_cell {
  level_choice choice;
  std::optional<std::size_t> euler;     // index into grid.forms
  std::optional<std::size_t> best_vop;  // index into grid.forms
  std::optional<double> speedup;        // euler time / best VOP time
};

std::vector<std::vector<map_cell>> cells_of(const map_job& job, const std::vector<wp_outcome>& outcomes) {
  std::vector<std::vector<map_cell>> out;
  for (std::size_t s = 0; s < job.grids.size(); ++s) {
    const wp_grid& g = job.grids[s];
    std::vector<map_cell> row;
    for (const level_choice& lc : cheapest_per_level(g, outcomes[s], job.levels)) {
      map_cell c;
      c.choice = lc;
      for (std::size_t f = 0; f < g.forms.size(); ++f) {
        if (!lc.best[f]) continue;
        const double t = outcomes[s].results[*lc.best[f]].seconds;
        if (g.forms[f] == formulation::euler) c.euler = f;
        else if (!c.best_vop || t < outcomes[s].results[*lc.best[*c.best_vop]].seconds) c.best_vop = f;
      }
      if (c.euler && c.best_vop)
        c.speedup = outcomes[s].results[*lc.best[*c.euler]].seconds / outcomes[s].results[*lc.best[*c.best_vop]].seconds;
      row.push_back(c);
    }
    out.push_back(std::move(row));
  }
  return out;
}

std::string torque_text(const wp_grid& g) {
  const auto& G = *g.scn.torque;
  return fmt::format("({}, {}, {})", G[0].text, G[1].text, G[2].text);
}

std::string verdict(const wp_grid& g, const map_cell& c) {
  if (!c.euler && !c.best_vop) return "not reached";
  if (!c.best_vop) return "only euler reaches it";
  if (!c.euler) return fmt::format("only {} reaches it", formulation_name(g.forms[*c.best_vop]));
  const std::string vop(formulation_name(g.forms[*c.best_vop]));
  return *c.speedup >= 1 ? fmt::format("{} {:.2f}x faster", vop, *c.speedup)
                         : fmt::format("euler {:.2f}x faster", 1 / *c.speedup);
}

std::string map_csv(const map_job& job, const std::vector<wp_outcome>& outcomes,
                    const std::vector<std::vector<map_cell>>& cells) {
  fmt::memory_buffer out;
  auto put = [&]<class... Args>(fmt::format_string<Args...> f, Args&&... args) {
    fmt::format_to(std::back_inserter(out), f, std::forward<Args>(args)...);
  };
  const wp_grid& first = job.grids.front();
  put("scale,level");
  for (formulation f : first.forms) {
    const std::string n(formulation_name(f));
    put(",{0}_method,{0}_config,{0}_seconds,{0}_max_error,{0}_rhs_evals", n);
  }
  put(",best_vop,speedup\n");
  for (std::size_t s = 0; s < job.grids.size(); ++s) {
    const wp_grid& g = job.grids[s];
    for (const map_cell& c : cells[s]) {
      put("{},{}", job.scales[s].text, c.choice.level);
      for (std::size_t f = 0; f < g.forms.size(); ++f) {
        if (!c.choice.best[f]) {
          put(",,,,,");
          continue;
        }
        const std::size_t i = *c.choice.best[f];
        const wp_result& r = outcomes[s].results[i];
        put(",{},{},{:.6g},{},{}", rk::method_name(g.cases[i].method), g.rung_text(g.cases[i]), r.seconds, *r.max_error,
            r.run.rhs_evals);
      }
      put(",{},{}\n", c.best_vop ? std::string(formulation_name(g.forms[*c.best_vop])) : std::string(),
          c.speedup ? fmt::format("{:.4g}", *c.speedup) : std::string());
    }
  }
  return fmt::to_string(out);
}

std::string runs_csv(const map_job& job, const std::vector<wp_outcome>& outcomes) {
  fmt::memory_buffer out;
  auto put = [&]<class... Args>(fmt::format_string<Args...> f, Args&&... args) {
    fmt::format_to(std::back_inserter(out), f, std::forward<Args>(args)...);
  };
  put("scale,formulation,method,step,h,tol,steps,rejected,rhs_evals,seconds,max_error,final_error,diverged,skipped\n");
  for (std::size_t s = 0; s < job.grids.size(); ++s) {
    const wp_grid& g = job.grids[s];
    for (std::size_t i = 0; i < g.cases.size(); ++i) {
      const wp_case& c = g.cases[i];
      const wp_result& r = outcomes[s].results[i];
      put("{},{},{},", job.scales[s].text, formulation_name(c.form), rk::method_name(c.method));
      if (c.adaptive) put(",,{},", g.tols[c.rung].value);
      else put("{},{},,", g.steps[c.rung].text, g.steps[c.rung].choice.h);
      if (r.skipped) {
        put(",,,,,,,true\n");
        continue;
      }
      put("{},{},{},{:.6g},{},{},{},false\n", r.run.steps, c.adaptive ? fmt::format("{}", r.run.rejected) : "",
          r.run.rhs_evals, r.seconds, csv_number(r.max_error), csv_number(r.final_error),
          r.run.diverged() ? "true" : "false");
    }
  }
  return fmt::to_string(out);
}

nlohmann::ordered_json summary_json(const map_job& job, const std::vector<wp_outcome>& outcomes,
                                    const std::vector<std::vector<map_cell>>& cells, double wall) {
  const wp_grid& first = job.grids.front();
  nlohmann::ordered_json j;
  j["scene"] = job.scene_name;
  j["overrides"] = job.overrides;
  j["tau_end"] = tau_end_of<double>(first.scn);
  j["precision"] = job.precision.name();
  j["levels"] = job.levels;
  nlohmann::ordered_json steps = nlohmann::ordered_json::array(), tols = nlohmann::ordered_json::array();
  for (const ladder_step& st : first.steps) steps.push_back(st.text);
  for (const ladder_tol& t : first.tols) tols.push_back(t.value);
  j["steps"] = steps;
  j["tols"] = tols;
  j["max_step_rule"] = first.h_max_rule;
  j["samples"] = first.samples;
  j["repeat"] = job.run.repeat;
  j["jobs"] = job.run.jobs;
  j["timing"] = timing_text(job.run);
  j["pruning"] = "each ladder (formulation, method, fixed or adaptive) stops at the first rung that reaches the "
                 "smallest level: tighter rungs cost more";
  j["wall_seconds"] = wall;
  j["scales"] = nlohmann::ordered_json::array();
  for (std::size_t s = 0; s < job.grids.size(); ++s) {
    const wp_grid& g = job.grids[s];
    nlohmann::ordered_json scale;
    scale["scale"] = job.scales[s].value;
    scale["scale_text"] = job.scales[s].text;
    scale["torque"] = torque_text(g);
    scale["reference"] = {{"seconds", outcomes[s].reference_seconds},
                          {"segments", outcomes[s].reference_segments},
                          {"tau_end", outcomes[s].reference_tau_end}};
    std::size_t run = 0, skipped = 0;
    for (const wp_result& r : outcomes[s].results) (r.skipped ? skipped : run) += 1;
    scale["runs"] = run;
    scale["skipped"] = skipped;
    scale["cells"] = nlohmann::ordered_json::array();
    for (const map_cell& c : cells[s]) {
      nlohmann::ordered_json by = nlohmann::ordered_json::object();
      for (std::size_t f = 0; f < g.forms.size(); ++f) {
        const std::string name(formulation_name(g.forms[f]));
        if (!c.choice.best[f]) {
          by[name] = nullptr;
          continue;
        }
        const std::size_t i = *c.choice.best[f];
        const wp_result& r = outcomes[s].results[i];
        by[name] = {{"method", std::string(rk::method_name(g.cases[i].method))},
                    {"adaptive", g.cases[i].adaptive},
                    {"configuration", g.configuration(g.cases[i])},
                    {"seconds", r.seconds},
                    {"max_error", *r.max_error},
                    {"rhs_evals", r.run.rhs_evals}};
      }
      scale["cells"].push_back(
          {{"level", c.choice.level},
           {"by_formulation", by},
           {"best_vop", c.best_vop ? nlohmann::ordered_json(std::string(formulation_name(g.forms[*c.best_vop])))
                                   : nlohmann::ordered_json(nullptr)},
           {"speedup", number_or_null(c.speedup)},
           {"verdict", verdict(g, c)}});
    }
    j["scales"].push_back(std::move(scale));
  }
  return j;
}

std::string table_text(const map_job& job, const std::vector<wp_outcome>& outcomes,
                       const std::vector<std::vector<map_cell>>& cells, double wall) {
  const wp_grid& first = job.grids.front();
  std::string out;
  out += fmt::format("scene {}{}: torque scaled by {}, to tau = {:.6g}\n", job.scene_name,
                     job.overrides.empty() ? "" : " (" + job.overrides + ")", joined([&] {
                       std::vector<std::string> t;
                       for (const decimal& d : job.scales) t.push_back(d.text);
                       return t;
                     }()),
                     tau_end_of<double>(first.scn));
  out += fmt::format("runs per scale: {} formulation(s) x {} method(s) on {} step(s) and {} tolerance(s), each "
                     "ladder stopped once it reaches {}; maximum step {}\n",
                     first.forms.size(), first.methods.size(), first.steps.size(), first.tols.size(),
                     level_text(*std::min_element(job.levels.begin(), job.levels.end())), first.h_max_rule);
  out += fmt::format("references ({}):", job.precision.name());
  for (std::size_t s = 0; s < job.grids.size(); ++s)
    out += fmt::format(" {} {:.1f} s{}", job.scales[s].text, outcomes[s].reference_seconds,
                       s + 1 < job.grids.size() ? "," : "\n");
  out += fmt::format("timing: {}; wall time {:.1f} s\n\n", timing_text(job.run), wall);

  out += "speed-up of the cheapest VOP configuration over the cheapest Euler one (max error over the span <= level):\n";
  std::vector<std::vector<std::string>> table;
  std::vector<std::string> header = {"level \\ scale"};
  for (const decimal& d : job.scales) header.push_back(d.text);
  table.push_back(header);
  for (std::size_t l = 0; l < job.levels.size(); ++l) {
    std::vector<std::string> row = {level_text(job.levels[l])};
    for (std::size_t s = 0; s < job.grids.size(); ++s) {
      const map_cell& c = cells[s][l];
      if (c.speedup) row.push_back(fmt::format("{:.2f}x", *c.speedup));
      else row.push_back(c.best_vop ? "vop only" : c.euler ? "euler only" : "-");
    }
    table.push_back(std::move(row));
  }
  out += aligned_table(table, 1);

  out += "\ncheapest configurations:\n";
  std::vector<std::vector<std::string>> detail = {{"scale", "level", "euler", "best vop", "verdict"}};
  for (std::size_t s = 0; s < job.grids.size(); ++s) {
    const wp_grid& g = job.grids[s];
    for (const map_cell& c : cells[s]) {
      auto config = [&](const std::optional<std::size_t>& f) {
        if (!f) return std::string("not reached");
        const std::size_t i = *c.choice.best[*f];
        return fmt::format("{} {} {:.3e} s", formulation_name(g.forms[*f]), g.configuration(g.cases[i]),
                           outcomes[s].results[i].seconds);
      };
      detail.push_back({job.scales[s].text, level_text(c.choice.level), config(c.euler), config(c.best_vop),
                        verdict(g, c)});
    }
  }
  out += aligned_table(detail, 5);
  return out;
}

}  // namespace

CLI::App* add_map_command(CLI::App& app, map_options& o) {
  CLI::App* sub = app.add_subcommand(
      "map", "Where VOP pays: the scene's torque scaled, every formulation x method x step and tolerance, the cheapest "
             "per error level and VOP's speed-up over Euler");
  auto bind = [&](const std::string& name, std::optional<std::string>& target, const std::string& help) {
    return add_text_option(*sub, name, target, help);
  };
  bind("scene", o.scene_path, "Scene file (TOML) with a torque; default: the embedded paper scene")->type_name("SCENE");
  bind("--torque-scales", o.torque_scales, "Comma-separated factors of the scene's torque (default: " + default_scales + ")")
      ->type_name("LIST");
  bind("--levels", o.levels, "Comma-separated max-error levels (default: " + default_levels + ")")->type_name("LIST");
  add_grid_flags(*sub, o.grid, defaults);
  scene_override_set which;
  which.times = false;
  add_scene_override_options(*sub, o.overrides, which, "About this many error samples per run (default: 200)");
  add_output_flags(*sub, o.out_dir, o.no_plot, "map", "regime_map");
  return sub;
}

void run_map(const map_options& options, std::ostream& standard_output) {
  const map_job job = make_job(options);
  const auto start = std::chrono::steady_clock::now();
  output_dir dir(job.out_dir, "map.csv");
  const std::vector<wp_outcome> outcomes = run_grids(job.grids, job.precision, job.settings, job.run);
  const auto cells = cells_of(job, outcomes);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  write_atomically(dir.path() / "map.csv", map_csv(job, outcomes, cells));
  write_atomically(dir.path() / "runs.csv", runs_csv(job, outcomes));
  write_atomically(dir.path() / "summary.json", summary_json(job, outcomes, cells, wall).dump(2) + "\n");
  dir.keep();
  standard_output << table_text(job, outcomes, cells, wall) << std::flush;
  if (job.plot) draw_figure(dir.path(), "plot_regime_map.py");
}

}  // namespace eulervop::app
