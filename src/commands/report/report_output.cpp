#include "commands/report/report_output.hpp"

#include "compute/progress.hpp"
#include "io/figure.hpp"
#include "io/output_cells.hpp"

#include <eulervop/scene/scene_problem.hpp>

#include <eulervop/core/outcome_text.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace eulervop::app {

namespace {

// The VOP fallback stretches (docs/vop-strategies.md): [[tau_in, tau_out], ...].
nlohmann::ordered_json bands_json(const std::vector<std::pair<double, double>>& bands) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const auto& [in, out_tau] : bands) out.push_back({in, out_tau});
  return out;
}

// "separatrix band tau 14.19..15.19, small-k bands tau 0..0.52, 3.1..3.4 (120 direct Euler steps,
// 1 regime change)": one line under the table for a run that left its elements; empty otherwise.
// A physical scene's stretches are in t (s).
std::string bands_note(const run_result& r, const report_units& units) {
  std::vector<std::string> parts;
  auto list = [&](const char* what, const std::vector<std::pair<double, double>>& bands) {
    if (bands.empty()) return;
    constexpr std::size_t shown = 4;
    std::string text = fmt::format("{} band{} {} ", what, bands.size() > 1 ? "s" : "", units.physical ? "t" : "tau");
    for (std::size_t i = 0; i < std::min(bands.size(), shown); ++i)
      text += fmt::format("{}{:.4g}..{:.4g}", i ? ", " : "", units.t_of(bands[i].first), units.t_of(bands[i].second));
    if (units.physical) text += " s";
    if (bands.size() > shown) text += fmt::format(" and {} more", bands.size() - shown);
    parts.push_back(std::move(text));
  };
  list("separatrix", r.separatrix_bands);
  list("small-k", r.small_k_bands);
  if (parts.empty()) return "";
  std::string line = parts[0];
  for (std::size_t i = 1; i < parts.size(); ++i) line += "; " + parts[i];
  line += fmt::format(" ({} direct Euler steps", r.direct_steps);
  if (r.regime_changes) line += fmt::format(", {} regime change{}", r.regime_changes, r.regime_changes > 1 ? "s" : "");
  return line + ")";
}

}  // namespace

std::string optional_text(const std::optional<double>& x, const char* spec) {
  return x ? fmt::format(fmt::runtime(spec), *x) : std::string("-");
}

std::string divergence_note(const run_result& r) {
  if (!r.diverged()) return "";
  // In the scene's own time first (t in seconds for a physical scene), as every failure is told.
  const std::string at = r.diverged_at() ? scene_time().at(*r.diverged_at(), 6) : "tau=-";
  return fmt::format("diverged at {} ({})", at, describe(r.status));
}

report_units report_units::of(const scene& s) {
  report_units u;
  if (!s.is_physical()) return u;
  u.physical = true;
  u.direct = uses_direct_form(s);
  const physical_scaling<double> scaling = scaling_of<double>(s);
  u.rate = scaling.tau_rate();
  for (int i = 0; i < 3; ++i) u.sqrt_A[static_cast<std::size_t>(i)] = scaling.sqrt_A()[i];
  return u;
}

nlohmann::ordered_json units_json(const report_units& units) {
  if (!units.physical) return nullptr;
  return {{"time", "s"},
          {"error", "rad/s: |omega - omega_ref|_2 on the body's axes as listed"},
          {"time_normalized", "tau (Eq. 4)"},
          {"error_normalized", "Eq. 20 in the normalized Omega"},
          {"attitude_error", "rad"}};
}

nlohmann::ordered_json run_json(const run_spec& spec, const run_errors& e, nlohmann::ordered_json step,
                                nlohmann::ordered_json tol, bool attitude, const report_units& units) {
  const run_result& r = e.run;
  const bool adaptive = spec.tol.has_value();
  auto if_adaptive = [&](auto v) { return adaptive ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr); };
  auto if_diverged = [&](auto v) { return r.diverged() ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr); };
  nlohmann::ordered_json j = {{"formulation", std::string(formulation_name(spec.form))},
          {"method", std::string(rk::method_name(spec.method))},
          {"step", std::move(step)},
          {"tol", std::move(tol)},
          {"steps", r.steps},
          {"accepted", if_adaptive(r.steps)},
          {"rejected", if_adaptive(r.rejected)},
          {"rhs_evals", r.rhs_evals},
          {"seconds", r.seconds},
          {"max_error", number_or_null(e.max_error)},
          {"final_tau", number_or_null(e.final_tau)},
          {"final_error", number_or_null(e.final_error)},
          {"diverged", r.diverged()},
          {"diverged_at", r.diverged() ? number_or_null(r.diverged_at()) : nlohmann::ordered_json(nullptr)},
          {"why", if_diverged(describe(r.status))},
          {"separatrix_bands", bands_json(r.separatrix_bands)},
          {"small_k_bands", bands_json(r.small_k_bands)},
          {"direct_steps", r.direct_steps},
          {"regime_changes", r.regime_changes}};
  if (!attitude && !units.physical) return j;
  // Rebuilt in order (ordered_json inserts at the end): a physical scene's errors in rad/s first,
  // the normalized ones after them; the attitude's after final_error.
  nlohmann::ordered_json out;
  for (auto& [key, value] : j.items()) {
    if (units.physical && key == "max_error") {
      out["max_error"] = number_or_null(e.max_rate_error);
      out["final_t"] = number_or_null(e.final_t);
      out["final_error"] = number_or_null(e.final_rate_error);
      out["max_error_normalized"] = value;
      continue;
    }
    if (units.physical && key == "final_error") {
      out["final_error_normalized"] = value;
    } else {
      out[key] = value;
    }
    if (attitude && key == "final_error") {
      out["max_attitude_error"] = number_or_null(e.max_attitude_error);
      out["final_attitude_error"] = number_or_null(e.final_attitude_error);
    }
  }
  return out;
}

std::string attitude_mode(const scene& s) {
  return s.couples_attitude() ? "q and the rates as one problem (the torque reads q; each stage's torque at its q)"
                              : "q beside the rates";
}

void record_errors(run_errors& e, std::size_t i, double tau, double error, std::optional<double> attitude,
                   const report_units& units, std::optional<double> rate) {
  if (std::isfinite(error)) {
    e.error[i] = error;
    e.max_error = std::max(e.max_error.value_or(0.0), error);
    e.final_tau = tau;
    e.final_error = error;
  }
  if (units.physical && rate && std::isfinite(*rate)) {
    if (e.rate_error.size() <= i) e.rate_error.resize(e.error.size());
    e.rate_error[i] = *rate;
    e.max_rate_error = std::max(e.max_rate_error.value_or(0.0), *rate);
    e.final_t = units.t_of(tau);
    e.final_rate_error = *rate;
  }
  if (attitude && std::isfinite(*attitude)) {
    e.attitude_error[i] = *attitude;
    e.max_attitude_error = std::max(e.max_attitude_error.value_or(0.0), *attitude);
    e.final_attitude_error = *attitude;
  }
}

std::vector<std::string> error_headers(const report_units& units, bool attitude) {
  std::vector<std::string> h = units.physical ? std::vector<std::string>{"max error (rad/s)", "final t (s)",
                                                                         "final error (rad/s)", "max normalized"}
                                              : std::vector<std::string>{"max error", "final tau", "final error"};
  if (attitude) h.insert(h.end(), {"max att err", "final att err"});
  h.emplace_back("");  // the divergence note
  return h;
}

std::vector<std::string> error_cells(const run_errors& e, const report_units& units, bool attitude) {
  std::vector<std::string> c =
      units.physical
          ? std::vector<std::string>{optional_text(e.max_rate_error, "{:.3e}"), optional_text(e.final_t, "{:.6g}"),
                                     optional_text(e.final_rate_error, "{:.3e}"), optional_text(e.max_error, "{:.3e}")}
          : std::vector<std::string>{optional_text(e.max_error, "{:.3e}"), optional_text(e.final_tau, "{:.6g}"),
                                     optional_text(e.final_error, "{:.3e}")};
  if (attitude)
    c.insert(c.end(), {optional_text(e.max_attitude_error, "{:.3e}"), optional_text(e.final_attitude_error, "{:.3e}")});
  c.push_back(divergence_note(e.run));
  return c;
}

std::string run_label(const report_job& job, const run_spec& spec) {
  const std::string label = fmt::format("{} {}", formulation_name(spec.form), rk::method_name(spec.method));
  return spec.tol ? fmt::format("{} tol {}", label, job.tols[*spec.tol].text) : label;
}

std::string bands_notes(const report_job& job, const std::vector<run_errors>& runs, const report_units& units) {
  std::string out;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const run_result& r = runs[i].run;
    const std::string note = bands_note(r, units);
    if (note.empty()) continue;
    if (out.empty()) out += "\n";
    out += fmt::format("{}: {}\n", run_label(job, job.runs[i]), note);
    // Most of the run outside its elements: its row measures direct Euler steps, not VOP.
    if (2 * r.direct_steps > r.steps)
      out += fmt::format("{}: VOP applied on only {} of its {} steps; the other {} were direct Euler steps (Eq. 5), "
                         "so its row measures mostly the direct integration\n",
                         run_label(job, job.runs[i]), r.steps - r.direct_steps, r.steps, r.direct_steps);
  }
  return out;
}

void write_report(const report_job& job, output_dir& dir, const std::string& errors_csv, const std::string& summary,
                  const std::string& printed, std::ostream& standard_output) {
  write_atomically(dir.path() / "errors.csv", errors_csv);
  write_atomically(dir.path() / "summary.json", summary);
  dir.keep();
  standard_output << printed << std::flush;
  if (job.plot) draw_figure(dir.path(), "plot_fig1.py");
}

}  // namespace eulervop::app
