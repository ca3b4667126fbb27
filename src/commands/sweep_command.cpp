#include "commands/sweep_command.hpp"

#include "io/figure.hpp"
#include "compute/grid_flags.hpp"
#include "io/output_cells.hpp"
#include "io/output_dir.hpp"
#include "compute/run_names.hpp"
#include "compute/scene_library.hpp"
#include "io/text_table.hpp"
#include "compute/work_precision.hpp"

#include <eulervop/runs/comparison_run.hpp>
#include <eulervop/core/outcome_text.hpp>
#include <eulervop/rk/explicit_rk.hpp>

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
const grid_flag_defaults defaults{default_step_ladder, 3};

// ---- flags -> a job ----------------------------------------------------------------------------

struct sweep_job {
  wp_grid grid;
  std::string overrides;
  wp_run_options run;
  eulervop::precision precision;
  picard_settings settings;
  fs::path out_dir;
  bool plot = true;
};

sweep_job make_job(const sweep_options& o) {
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
  job.run = run_options_of(o.grid, defaults, "sweep");
  job.grid = grid_of(s, static_cast<std::size_t>(*s.samples), o.grid, defaults);

  job.out_dir = out_dir_of(o.out_dir, "sweep");
  job.plot = !o.no_plot;
  return job;
}

// ---- output ---------------------------------------------------------------------------------------

// "vop, 2.60x faster than euler, 1.10x faster than vop-theta" (and which reach nothing).
std::string verdict(const wp_grid& g, const wp_outcome& o, const level_choice& lc) {
  if (!lc.winner) return "no formulation reaches it";
  const double best = o.results[*lc.best[*lc.winner]].seconds;
  std::string s(formulation_name(g.forms[*lc.winner]));
  std::vector<std::string> missing;
  for (std::size_t f = 0; f < g.forms.size(); ++f) {
    if (f == *lc.winner) continue;
    const std::string name(formulation_name(g.forms[f]));
    if (lc.best[f])
      s += fmt::format(", {:.2f}x faster than {}", o.results[*lc.best[f]].seconds / best, name);
    else
      missing.push_back(name);
  }
  if (!missing.empty()) s += fmt::format("; not reached by {}", joined(missing));
  return s;
}

std::string sweep_csv(const wp_grid& g, const wp_outcome& o) {
  fmt::memory_buffer out;
  auto put = [&]<class... Args>(fmt::format_string<Args...> f, Args&&... args) {
    fmt::format_to(std::back_inserter(out), f, std::forward<Args>(args)...);
  };
  put("formulation,method,step,h,tol,steps,accepted,rejected,rhs_evals,seconds,max_error,final_error,diverged,"
      "diverged_at\n");
  for (std::size_t i = 0; i < g.cases.size(); ++i) {
    const wp_case& c = g.cases[i];
    const wp_result& r = o.results[i];
    put("{},{},", formulation_name(c.form), rk::method_name(c.method));
    if (c.adaptive)
      put(",,{},{},{},{},", g.tols[c.rung].value, r.run.steps, r.run.steps, r.run.rejected);
    else
      put("{},{},,{},,,", g.steps[c.rung].text, g.steps[c.rung].choice.h, r.run.steps);
    put("{},{:.6g},{},{},{},{}\n", r.run.rhs_evals, r.seconds, csv_number(r.max_error),
        csv_number(r.final_error), r.run.diverged() ? "true" : "false",
        r.run.diverged() ? csv_number(r.run.diverged_at()) : std::string());
  }
  return fmt::to_string(out);
}

std::string cheapest_csv(const wp_grid& g, const wp_outcome& o, const std::vector<level_choice>& levels) {
  fmt::memory_buffer out;
  auto put = [&]<class... Args>(fmt::format_string<Args...> f, Args&&... args) {
    fmt::format_to(std::back_inserter(out), f, std::forward<Args>(args)...);
  };
  // One row per level and formulation; empty cells where the formulation does not reach the
  // level. `factor` is its time over the level's cheapest time (1 for the cheapest).
  put("level,formulation,method,step,h,tol,seconds,max_error,rhs_evals,factor\n");
  for (const level_choice& lc : levels) {
    for (std::size_t f = 0; f < g.forms.size(); ++f) {
      put("{},{}", level_text(lc.level), formulation_name(g.forms[f]));
      if (!lc.best[f]) {
        put(",,,,,,,,\n");
        continue;
      }
      const std::size_t i = *lc.best[f];
      const wp_case& c = g.cases[i];
      put(",{},", rk::method_name(c.method));
      if (c.adaptive) put(",,{}", g.tols[c.rung].value);
      else put("{},{},", g.steps[c.rung].text, g.steps[c.rung].choice.h);
      put(",{:.6g},{},{},{:.4g}\n", o.results[i].seconds, *o.results[i].max_error, o.results[i].run.rhs_evals,
          o.results[i].seconds / o.results[*lc.best[*lc.winner]].seconds);
    }
  }
  return fmt::to_string(out);
}

nlohmann::ordered_json summary_json(const sweep_job& job, const wp_outcome& o, const std::vector<level_choice>& levels,
                                    double wall_seconds) {
  const wp_grid& g = job.grid;
  nlohmann::ordered_json j;
  j["scene"] = g.scn.name;
  j["overrides"] = job.overrides;
  j["reference"] = {{"precision", job.precision.name()},
                    {"tau_end", o.reference_tau_end},
                    {"seconds", o.reference_seconds},
                    {"segments", o.reference_segments}};
  j["samples"] = g.samples;
  j["repeat"] = job.run.repeat;
  j["jobs"] = job.run.jobs;
  j["timing"] = timing_text(job.run);
  j["wall_seconds"] = wall_seconds;
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  for (const ladder_step& st : g.steps)
    steps.push_back({{"step", st.text},
                     {"h", st.choice.h},
                     {"steps", st.choice.n_steps},
                     {"sample_every", st.sample_every},
                     {"rule", st.choice.rule}});
  j["steps"] = steps;
  nlohmann::ordered_json tols = nlohmann::ordered_json::array();
  for (const ladder_tol& t : g.tols) tols.push_back(t.value);
  j["tols"] = tols;
  j["max_step"] = {{"h", g.h_max}, {"rule", g.h_max_rule}};
  j["runs"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < g.cases.size(); ++i) {
    const wp_case& c = g.cases[i];
    const wp_result& r = o.results[i];
    const auto null = nlohmann::ordered_json(nullptr);
    j["runs"].push_back({{"formulation", std::string(formulation_name(c.form))},
                         {"method", std::string(rk::method_name(c.method))},
                         {"step", c.adaptive ? null : nlohmann::ordered_json(g.steps[c.rung].text)},
                         {"h", c.adaptive ? null : nlohmann::ordered_json(g.steps[c.rung].choice.h)},
                         {"tol", c.adaptive ? nlohmann::ordered_json(g.tols[c.rung].value) : null},
                         {"steps", r.run.steps},
                         {"accepted", c.adaptive ? nlohmann::ordered_json(r.run.steps) : null},
                         {"rejected", c.adaptive ? nlohmann::ordered_json(r.run.rejected) : null},
                         {"rhs_evals", r.run.rhs_evals},
                         {"seconds", r.seconds},
                         {"max_error", number_or_null(r.max_error)},
                         {"final_error", number_or_null(r.final_error)},
                         {"diverged", r.run.diverged()},
                         {"diverged_at", r.run.diverged() ? number_or_null(r.run.diverged_at()) : null},
                         {"why", r.run.diverged() ? nlohmann::ordered_json(describe(r.run.status)) : null}});
  }
  j["cheapest"] = nlohmann::ordered_json::array();
  for (const level_choice& lc : levels) {
    nlohmann::ordered_json by = nlohmann::ordered_json::object();
    for (std::size_t f = 0; f < g.forms.size(); ++f) {
      const std::string name(formulation_name(g.forms[f]));
      if (!lc.best[f]) {
        by[name] = nullptr;
        continue;
      }
      const std::size_t i = *lc.best[f];
      const wp_case& c = g.cases[i];
      by[name] = {{"method", std::string(rk::method_name(c.method))},
                  {"step", c.adaptive ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(g.steps[c.rung].text)},
                  {"tol", c.adaptive ? nlohmann::ordered_json(g.tols[c.rung].value) : nlohmann::ordered_json(nullptr)},
                  {"seconds", o.results[i].seconds},
                  {"max_error", *o.results[i].max_error},
                  {"factor", o.results[i].seconds / o.results[*lc.best[*lc.winner]].seconds}};
    }
    j["cheapest"].push_back(
        {{"level", lc.level},
         {"cheapest", lc.winner ? nlohmann::ordered_json(std::string(formulation_name(g.forms[*lc.winner])))
                                : nlohmann::ordered_json(nullptr)},
         {"verdict", verdict(g, o, lc)},
         {"by_formulation", by}});
  }
  return j;
}

std::string table_text(const sweep_job& job, const wp_outcome& o, const std::vector<level_choice>& levels,
                       double wall_seconds) {
  const wp_grid& g = job.grid;
  std::string out;
  out += fmt::format("scene {}{}: {} formulation(s) x {} method(s) on {} step(s) and {} tolerance(s) = {} runs, to "
                     "tau = {:.6g}\n",
                     g.scn.name, job.overrides.empty() ? "" : " (" + job.overrides + ")", g.forms.size(),
                     g.methods.size(), g.steps.size(), g.tols.size(), g.cases.size(), o.reference_tau_end);
  out += fmt::format("reference: {} ({:.1f} s, {} segments); errors (Eq. 20) at about {} samples per run\n",
                     job.precision.name(), o.reference_seconds, o.reference_segments, g.samples);
  if (!g.tols.empty()) out += fmt::format("adaptive runs: atol = rtol = tol, maximum step {}\n", g.h_max_rule);
  out += fmt::format("timing: {}\n", timing_text(job.run));
  out += fmt::format("wall time of the sweep: {:.1f} s\n\n", wall_seconds);

  std::vector<std::vector<std::string>> rows = {{"formulation", "method", "step", "h", "steps", "rejected", "rhs evals",
                                                 "seconds", "max error", "final error", ""}};
  for (std::size_t i = 0; i < g.cases.size(); ++i) {
    const wp_case& c = g.cases[i];
    const wp_result& r = o.results[i];
    auto sci = [](const std::optional<double>& x) { return x ? fmt::format("{:.3e}", *x) : std::string("-"); };
    rows.push_back({std::string(formulation_name(c.form)), std::string(rk::method_name(c.method)), g.rung_text(c),
                    c.adaptive ? std::string("-") : fmt::format("{:.6g}", g.steps[c.rung].choice.h),
                    fmt::format("{}", r.run.steps), c.adaptive ? fmt::format("{}", r.run.rejected) : std::string("-"),
                    fmt::format("{}", r.run.rhs_evals), fmt::format("{:.3e}", r.seconds), sci(r.max_error),
                    sci(r.final_error),
                    r.run.diverged() ? fmt::format("DIVERGED at tau={} ({})",
                                                   r.run.diverged_at() ? fmt::format("{:.6g}", *r.run.diverged_at()) : "?",
                                                   describe(r.run.status))
                                     : ""});
  }
  out += aligned_table(rows, 3);

  out += "\ncheapest configuration per formulation (max error over the span <= level; diverged runs excluded):\n";
  std::vector<std::vector<std::string>> table;
  std::vector<std::string> header = {"level"};
  for (formulation f : g.forms) header.emplace_back(formulation_name(f));
  header.emplace_back("cheaper");
  table.push_back(header);
  for (const level_choice& lc : levels) {
    std::vector<std::string> row = {level_text(lc.level)};
    for (std::size_t f = 0; f < g.forms.size(); ++f) {
      if (!lc.best[f]) {
        row.emplace_back("not reached");
        continue;
      }
      const std::size_t i = *lc.best[f];
      row.push_back(fmt::format("{} {:.3e} s", g.configuration(g.cases[i]), o.results[i].seconds));
    }
    row.push_back(verdict(g, o, lc));
    table.push_back(std::move(row));
  }
  out += aligned_table(table, table.front().size());
  return out;
}

}  // namespace

CLI::App* add_sweep_command(CLI::App& app, sweep_options& o) {
  CLI::App* sub = app.add_subcommand(
      "sweep", "Work against precision: every formulation x method x fixed step and tolerance, timed and measured "
               "against one reference");
  auto bind = [&](const std::string& name, std::optional<std::string>& target, const std::string& help) {
    return add_text_option(*sub, name, target, help);
  };
  bind("scene", o.scene_path, "Scene file (TOML); default: the embedded paper scene")->type_name("SCENE");
  add_grid_flags(*sub, o.grid, defaults);
  scene_override_set which;
  which.times = false;
  add_scene_override_options(*sub, o.overrides, which,
                             "About this many error samples per run, at its step points (default: 200)");
  add_output_flags(*sub, o.out_dir, o.no_plot, "sweep", "work_precision");
  return sub;
}

void run_sweep(const sweep_options& options, std::ostream& standard_output) {
  const sweep_job job = make_job(options);
  const auto start = std::chrono::steady_clock::now();
  output_dir dir(job.out_dir, "sweep.csv");
  const std::vector<wp_outcome> outcomes = run_grids({job.grid}, job.precision, job.settings, job.run);
  const wp_outcome& o = outcomes.front();
  const std::vector<double> levels(sweep_error_levels.begin(), sweep_error_levels.end());
  const std::vector<level_choice> cheapest = cheapest_per_level(job.grid, o, levels);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  write_atomically(dir.path() / "sweep.csv", sweep_csv(job.grid, o));
  write_atomically(dir.path() / "cheapest.csv", cheapest_csv(job.grid, o, cheapest));
  write_atomically(dir.path() / "summary.json", summary_json(job, o, cheapest, wall).dump(2) + "\n");
  dir.keep();

  standard_output << table_text(job, o, cheapest, wall) << std::flush;
  if (job.plot) draw_figure(dir.path(), "plot_work_precision.py");
}

}  // namespace eulervop::app
