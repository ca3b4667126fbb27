#include "commands/sweep/sweep_output.hpp"

#include "compute/run_names.hpp"
#include "compute/scene_time.hpp"
#include "io/output_cells.hpp"
#include "io/text_buffer.hpp"
#include "io/text_table.hpp"

#include <eulervop/core/outcome_text.hpp>

#include <fmt/format.h>

namespace eulervop::app {

namespace {

using json = nlohmann::ordered_json;

// A step or a time of the runs (in tau) in the scene's own time: seconds for a physical body in
// the normalized form (as its --steps are given), the same number otherwise.
double in_scene_time(const wp_grid& g, double tau) { return tau * clock_of(g.scn).per_tau; }
std::optional<double> in_scene_time(const wp_grid& g, const std::optional<double>& tau) {
  return tau ? std::optional<double>(in_scene_time(g, *tau)) : std::nullopt;
}

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

// A case's time over the cheapest time at its level (1 for the cheapest).
double factor(const wp_outcome& o, const level_choice& lc, std::size_t i) {
  return o.results[i].seconds / o.results[*lc.best[*lc.winner]].seconds;
}

json steps_json(const wp_grid& g) {
  json steps = json::array();
  for (const ladder_step& st : g.steps)
    steps.push_back({{"step", st.text},
                     {"h", in_scene_time(g, st.choice.h)},
                     {"steps", st.choice.n_steps},
                     {"sample_every", st.sample_every},
                     {"rule", st.choice.rule}});
  return steps;
}

json runs_json(const wp_grid& g, const wp_outcome& o) {
  json runs = json::array();
  const auto null = json(nullptr);
  for (std::size_t i = 0; i < g.cases.size(); ++i) {
    const wp_case& c = g.cases[i];
    const wp_result& r = o.results[i];
    runs.push_back({{"formulation", std::string(formulation_name(c.form))},
                    {"method", std::string(rk::method_name(c.method))},
                    {"step", c.adaptive ? null : json(g.steps[c.rung].text)},
                    {"h", c.adaptive ? null : json(in_scene_time(g, g.steps[c.rung].choice.h))},
                    {"tol", c.adaptive ? json(g.tols[c.rung].value) : null},
                    {"steps", r.run.steps},
                    {"accepted", c.adaptive ? json(r.run.steps) : null},
                    {"rejected", c.adaptive ? json(r.run.rejected) : null},
                    {"rhs_evals", r.run.rhs_evals},
                    {"seconds", r.seconds},
                    {"max_error", number_or_null(r.max_error)},
                    {"final_error", number_or_null(r.final_error)},
                    {"diverged", r.run.diverged()},
                    {"diverged_at", r.run.diverged() ? number_or_null(in_scene_time(g, r.run.diverged_at())) : null},
                    {"why", r.run.diverged() ? json(describe(r.run.status)) : null}});
    if (g.scn.has_attitude()) {  // after final_error, as report has it (radians)
      json entry;
      for (auto& [key, value] : runs.back().items()) {
        entry[key] = value;
        if (key == "final_error") {
          entry["max_attitude_error"] = number_or_null(r.max_attitude_error);
          entry["final_attitude_error"] = number_or_null(r.final_attitude_error);
        }
      }
      runs.back() = std::move(entry);
    }
  }
  return runs;
}

json cheapest_json(const wp_grid& g, const wp_outcome& o, const std::vector<level_choice>& levels) {
  json cheapest = json::array();
  for (const level_choice& lc : levels) {
    json by = json::object();
    for (std::size_t f = 0; f < g.forms.size(); ++f) {
      const std::string name(formulation_name(g.forms[f]));
      if (!lc.best[f]) {
        by[name] = nullptr;
        continue;
      }
      const std::size_t i = *lc.best[f];
      const wp_case& c = g.cases[i];
      by[name] = {{"method", std::string(rk::method_name(c.method))},
                  {"step", c.adaptive ? json(nullptr) : json(g.steps[c.rung].text)},
                  {"tol", c.adaptive ? json(g.tols[c.rung].value) : json(nullptr)},
                  {"seconds", o.results[i].seconds},
                  {"max_error", *o.results[i].max_error},
                  {"factor", factor(o, lc, i)}};
    }
    cheapest.push_back(
        {{"level", lc.level},
         {"cheapest", lc.winner ? json(std::string(formulation_name(g.forms[*lc.winner]))) : json(nullptr)},
         {"verdict", verdict(g, o, lc)},
         {"by_formulation", by}});
  }
  return cheapest;
}

// The grid's runs, one row each.
std::string runs_table(const wp_grid& g, const wp_outcome& o) {
  const std::string h = clock_of(g.scn).unit.unit.empty() ? "h" : "h (" + clock_of(g.scn).unit.unit + ")";
  std::vector<std::vector<std::string>> rows = {{"formulation", "method", "step", h, "steps", "rejected", "rhs evals",
                                                 "seconds", "max error", "final error", ""}};
  const bool attitude = g.scn.has_attitude();
  if (attitude) rows[0].insert(rows[0].end() - 1, {"max att err", "final att err"});
  auto sci = [](const std::optional<double>& x) { return x ? fmt::format("{:.3e}", *x) : std::string("-"); };
  for (std::size_t i = 0; i < g.cases.size(); ++i) {
    const wp_case& c = g.cases[i];
    const wp_result& r = o.results[i];
    rows.push_back(
        {std::string(formulation_name(c.form)), std::string(rk::method_name(c.method)), g.rung_text(c),
         c.adaptive ? std::string("-") : fmt::format("{:.6g}", in_scene_time(g, g.steps[c.rung].choice.h)),
         fmt::format("{}", r.run.steps), c.adaptive ? fmt::format("{}", r.run.rejected) : std::string("-"),
         fmt::format("{}", r.run.rhs_evals), fmt::format("{:.3e}", r.seconds), sci(r.max_error), sci(r.final_error),
         r.run.diverged() ? fmt::format("DIVERGED at {} ({})",
                                        r.run.diverged_at() ? scene_time_text(g.scn, *r.run.diverged_at(), "=")
                                                            : clock_of(g.scn).unit.name + "=?",
                                        describe(r.run.status))
                          : ""});
    if (attitude) rows.back().insert(rows.back().end() - 1, {sci(r.max_attitude_error), sci(r.final_attitude_error)});
  }
  return aligned_table(rows, 3);
}

// The cheapest configuration per formulation at each level, and the verdict.
std::string cheapest_table(const wp_grid& g, const wp_outcome& o, const std::vector<level_choice>& levels) {
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
  return aligned_table(table, table.front().size());
}

}  // namespace

std::string sweep_csv(const wp_grid& g, const wp_outcome& o) {
  const bool attitude = g.scn.has_attitude();
  text_buffer out;
  out.put("formulation,method,step,h,tol,steps,accepted,rejected,rhs_evals,seconds,max_error,final_error,{}diverged,"
          "diverged_at\n",
          attitude ? "max_attitude_error,final_attitude_error," : "");
  for (std::size_t i = 0; i < g.cases.size(); ++i) {
    const wp_case& c = g.cases[i];
    const wp_result& r = o.results[i];
    out.put("{},{},", formulation_name(c.form), rk::method_name(c.method));
    if (c.adaptive)
      out.put(",,{},{},{},{},", g.tols[c.rung].value, r.run.steps, r.run.steps, r.run.rejected);
    else
      out.put("{},{},,{},,,", g.steps[c.rung].text, in_scene_time(g, g.steps[c.rung].choice.h), r.run.steps);
    out.put("{},{:.6g},{},{},", r.run.rhs_evals, r.seconds, csv_number(r.max_error), csv_number(r.final_error));
    if (attitude) out.put("{},{},", csv_number(r.max_attitude_error), csv_number(r.final_attitude_error));
    out.put("{},{}\n", r.run.diverged() ? "true" : "false",
            r.run.diverged() ? csv_number(in_scene_time(g, r.run.diverged_at())) : std::string());
  }
  return out.text();
}

std::string cheapest_csv(const wp_grid& g, const wp_outcome& o, const std::vector<level_choice>& levels) {
  text_buffer out;
  // One row per level and formulation; empty cells where the formulation does not reach the
  // level. `factor` is its time over the level's cheapest time (1 for the cheapest).
  out.put("level,formulation,method,step,h,tol,seconds,max_error,rhs_evals,factor\n");
  for (const level_choice& lc : levels) {
    for (std::size_t f = 0; f < g.forms.size(); ++f) {
      out.put("{},{}", level_text(lc.level), formulation_name(g.forms[f]));
      if (!lc.best[f]) {
        out.put(",,,,,,,,\n");
        continue;
      }
      const std::size_t i = *lc.best[f];
      const wp_case& c = g.cases[i];
      out.put(",{},", rk::method_name(c.method));
      if (c.adaptive)
        out.put(",,{}", g.tols[c.rung].value);
      else
        out.put("{},{},", g.steps[c.rung].text, in_scene_time(g, g.steps[c.rung].choice.h));
      out.put(",{:.6g},{},{},{:.4g}\n", o.results[i].seconds, *o.results[i].max_error, o.results[i].run.rhs_evals,
              factor(o, lc, i));
    }
  }
  return out.text();
}

nlohmann::ordered_json sweep_summary_json(const sweep_job& job, const wp_outcome& o,
                                          const std::vector<level_choice>& levels, double wall_seconds) {
  const wp_grid& g = job.grid;
  json j;
  j["scene"] = g.scn.name;
  j["overrides"] = job.overrides;
  j["time"] = scene_time_json(g.scn, o.reference_tau_end);
  j["note"] = job.note.empty() ? json(nullptr) : json(job.note);
  j["reference"] = {{"precision", job.precision.name()},
                    {"tau_end", o.reference_tau_end},
                    {"seconds", o.reference_seconds},
                    {"segments", o.reference_segments}};
  j["samples"] = g.samples;
  j["repeat"] = job.run.repeat;
  j["jobs"] = job.run.jobs;
  j["timing"] = timing_text(job.run);
  j["wall_seconds"] = wall_seconds;
  j["steps"] = steps_json(g);
  json tols = json::array();
  for (const ladder_tol& t : g.tols) tols.push_back(t.value);
  j["tols"] = tols;
  j["max_step"] = {{"h", in_scene_time(g, g.max_step.h)}, {"rule", g.max_step.rule}};
  j["runs"] = runs_json(g, o);
  j["cheapest"] = cheapest_json(g, o, levels);
  return j;
}

std::string sweep_table(const sweep_job& job, const wp_outcome& o, const std::vector<level_choice>& levels,
                        double wall_seconds) {
  const wp_grid& g = job.grid;
  text_buffer out;
  out.put("scene {}{}: {} formulation(s) x {} method(s) on {} step(s) and {} tolerance(s) = {} runs, to {}\n",
          g.scn.name, job.overrides.empty() ? "" : " (" + job.overrides + ")", g.forms.size(), g.methods.size(),
          g.steps.size(), g.tols.size(), g.cases.size(), scene_time_text(g.scn, o.reference_tau_end));
  if (!job.note.empty()) out.put("note: {}\n", job.note);
  out.put("reference: {} ({:.1f} s, {} segments); errors (Eq. 20) at about {} samples per run\n", job.precision.name(),
          o.reference_seconds, o.reference_segments, g.samples);
  if (!g.tols.empty()) out.put("adaptive runs: atol = rtol = tol, maximum step {}\n", g.max_step.rule);
  out.put("timing: {}\n", timing_text(job.run));
  out.put("wall time of the sweep: {:.1f} s\n\n", wall_seconds);
  out.put("{}", runs_table(g, o));
  out.put("\ncheapest configuration per formulation (max error over the span <= level; diverged runs excluded):\n");
  out.put("{}", cheapest_table(g, o, levels));
  return out.text();
}

}  // namespace eulervop::app
