#include "commands/map/map_output.hpp"

#include "compute/cheapest_configurations.hpp"
#include "compute/run_names.hpp"
#include "compute/scene_time.hpp"
#include "io/output_cells.hpp"
#include "io/text_buffer.hpp"
#include "io/text_table.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace eulervop::app {

namespace {

using json = nlohmann::ordered_json;

std::string torque_text(const wp_grid& g) {
  if (g.scn.has_torque_law()) return law_text(*g.scn.torque_law);
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

// One cell of summary.json: the cheapest configuration of each formulation, the best VOP one.
json cell_json(const wp_grid& g, const wp_outcome& outcome, const map_cell& c) {
  json by = json::object();
  for (std::size_t f = 0; f < g.forms.size(); ++f) {
    const std::string name(formulation_name(g.forms[f]));
    if (!c.choice.best[f]) {
      by[name] = nullptr;
      continue;
    }
    const std::size_t i = *c.choice.best[f];
    const wp_result& r = outcome.results[i];
    by[name] = {{"method", std::string(rk::method_name(g.cases[i].method))},
                {"adaptive", g.cases[i].adaptive},
                {"configuration", g.configuration(g.cases[i])},
                {"seconds", r.seconds},
                {"max_error", *r.max_error},
                {"rhs_evals", r.run.rhs_evals}};
    if (g.scn.has_attitude()) by[name]["max_attitude_error"] = number_or_null(r.max_attitude_error);
  }
  return {{"level", c.choice.level},
          {"by_formulation", by},
          {"best_vop", c.best_vop ? json(std::string(formulation_name(g.forms[*c.best_vop]))) : json(nullptr)},
          {"speedup", number_or_null(c.speedup)},
          {"verdict", verdict(g, c)}};
}

// One torque scale of summary.json: its torque, reference, runs and cells.
json scale_json(const map_job& job, std::size_t s, const wp_outcome& outcome, const std::vector<map_cell>& cells) {
  const wp_grid& g = job.grids[s];
  json scale;
  scale["scale"] = job.scales[s].value;
  scale["scale_text"] = job.scales[s].text;
  scale["torque"] = torque_text(g);
  scale["reference"] = {{"seconds", outcome.reference_seconds},
                        {"segments", outcome.reference_segments},
                        {"tau_end", outcome.reference_tau_end}};
  std::size_t run = 0, skipped = 0;
  for (const wp_result& r : outcome.results) (r.skipped ? skipped : run) += 1;
  scale["runs"] = run;
  scale["skipped"] = skipped;
  scale["cells"] = json::array();
  for (const map_cell& c : cells) scale["cells"].push_back(cell_json(g, outcome, c));
  return scale;
}

// The speed-up of the cheapest VOP configuration over the cheapest Euler one: levels x scales.
std::string speedup_table(const map_job& job, const map_cells& cells) {
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
  return aligned_table(table, 1);
}

// Each cell's cheapest Euler and VOP configurations and the verdict.
std::string configurations_table(const map_job& job, const std::vector<wp_outcome>& outcomes, const map_cells& cells) {
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
  return aligned_table(detail, 5);
}

}  // namespace

std::string map_csv(const map_job& job, const std::vector<wp_outcome>& outcomes, const map_cells& cells) {
  text_buffer out;
  out.put("scale,level");
  for (formulation f : job.grids.front().forms)
    out.put(",{0}_method,{0}_config,{0}_seconds,{0}_max_error,{0}_rhs_evals", formulation_name(f));
  out.put(",best_vop,speedup\n");
  for (std::size_t s = 0; s < job.grids.size(); ++s) {
    const wp_grid& g = job.grids[s];
    for (const map_cell& c : cells[s]) {
      out.put("{},{}", job.scales[s].text, c.choice.level);
      for (std::size_t f = 0; f < g.forms.size(); ++f) {
        if (!c.choice.best[f]) {
          out.put(",,,,,");
          continue;
        }
        const std::size_t i = *c.choice.best[f];
        const wp_result& r = outcomes[s].results[i];
        out.put(",{},{},{:.6g},{},{}", rk::method_name(g.cases[i].method), g.rung_text(g.cases[i]), r.seconds,
                *r.max_error, r.run.rhs_evals);
      }
      out.put(",{},{}\n", c.best_vop ? std::string(formulation_name(g.forms[*c.best_vop])) : std::string(),
              c.speedup ? fmt::format("{:.4g}", *c.speedup) : std::string());
    }
  }
  return out.text();
}

std::string map_runs_csv(const map_job& job, const std::vector<wp_outcome>& outcomes) {
  const bool attitude = job.grids.front().scn.has_attitude();
  text_buffer out;
  out.put("scale,formulation,method,step,h,tol,steps,rejected,rhs_evals,seconds,max_error,final_error,{}diverged,"
          "skipped\n",
          attitude ? "max_attitude_error,final_attitude_error," : "");
  for (std::size_t s = 0; s < job.grids.size(); ++s) {
    const wp_grid& g = job.grids[s];
    for (std::size_t i = 0; i < g.cases.size(); ++i) {
      const wp_case& c = g.cases[i];
      const wp_result& r = outcomes[s].results[i];
      out.put("{},{},{},", job.scales[s].text, formulation_name(c.form), rk::method_name(c.method));
      if (c.adaptive)
        out.put(",,{},", g.tols[c.rung].value);
      else
        out.put("{},{},,", g.steps[c.rung].text, g.steps[c.rung].choice.h * clock_of(g.scn).per_tau);
      if (r.skipped) {
        out.put(",,,,,,,{}true\n", attitude ? ",," : "");
        continue;
      }
      out.put("{},{},{},{:.6g},{},{},", r.run.steps, c.adaptive ? fmt::format("{}", r.run.rejected) : "",
              r.run.rhs_evals, r.seconds, csv_number(r.max_error), csv_number(r.final_error));
      if (attitude) out.put("{},{},", csv_number(r.max_attitude_error), csv_number(r.final_attitude_error));
      out.put("{},false\n", r.run.diverged() ? "true" : "false");
    }
  }
  return out.text();
}

nlohmann::ordered_json map_summary_json(const map_job& job, const std::vector<wp_outcome>& outcomes,
                                        const map_cells& cells, double wall) {
  const wp_grid& first = job.grids.front();
  json j;
  j["scene"] = job.scene_name;
  j["overrides"] = job.overrides;
  j["tau_end"] = tau_end_of<double>(first.scn);
  j["time"] = scene_time_json(first.scn, tau_end_of<double>(first.scn));
  j["precision"] = job.precision.name();
  j["levels"] = job.levels;
  json steps = json::array(), tols = json::array();
  for (const ladder_step& st : first.steps) steps.push_back(st.text);
  for (const ladder_tol& t : first.tols) tols.push_back(t.value);
  j["steps"] = steps;
  j["tols"] = tols;
  j["max_step_rule"] = first.max_step.rule;
  j["samples"] = first.samples;
  j["repeat"] = job.run.repeat;
  j["jobs"] = job.run.jobs;
  j["timing"] = timing_text(job.run);
  j["pruning"] = "each ladder (formulation, method, fixed or adaptive) stops at the first rung that reaches the "
                 "smallest level: tighter rungs cost more";
  j["wall_seconds"] = wall;
  j["scales"] = json::array();
  for (std::size_t s = 0; s < job.grids.size(); ++s) j["scales"].push_back(scale_json(job, s, outcomes[s], cells[s]));
  return j;
}

std::string map_table(const map_job& job, const std::vector<wp_outcome>& outcomes, const map_cells& cells,
                      double wall) {
  const wp_grid& first = job.grids.front();
  std::vector<std::string> scales;
  for (const decimal& d : job.scales) scales.push_back(d.text);
  text_buffer out;
  out.put("scene {}{}: torque scaled by {}, to {}\n", job.scene_name,
          job.overrides.empty() ? "" : " (" + job.overrides + ")", joined(scales),
          scene_time_text(first.scn, tau_end_of<double>(first.scn)));
  out.put("runs per scale: {} formulation(s) x {} method(s) on {} step(s) and {} tolerance(s), each ladder stopped "
          "once it reaches {}; maximum step {}\n",
          first.forms.size(), first.methods.size(), first.steps.size(), first.tols.size(),
          level_text(*std::min_element(job.levels.begin(), job.levels.end())), first.max_step.rule);
  out.put("references ({}):", job.precision.name());
  for (std::size_t s = 0; s < job.grids.size(); ++s)
    out.put(" {} {:.1f} s{}", job.scales[s].text, outcomes[s].reference_seconds, s + 1 < job.grids.size() ? "," : "\n");
  out.put("timing: {}; wall time {:.1f} s\n\n", timing_text(job.run), wall);
  out.put(
      "speed-up of the cheapest VOP configuration over the cheapest Euler one (max error over the span <= level):\n");
  out.put("{}", speedup_table(job, cells));
  out.put("\ncheapest configurations:\n");
  out.put("{}", configurations_table(job, outcomes, cells));
  return out.text();
}

}  // namespace eulervop::app
