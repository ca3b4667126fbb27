#include "commands/report_command.hpp"

#include "io/atomic_file.hpp"
#include "io/csv_rows.hpp"
#include "io/figure.hpp"
#include "io/output_cells.hpp"
#include "io/output_dir.hpp"
#include "compute/reference_compute.hpp"
#include "io/reference_csv.hpp"
#include "compute/run_names.hpp"
#include "compute/scene_library.hpp"
#include "compute/step_rule.hpp"
#include "io/text_table.hpp"
#include "compute/with_scalar.hpp"
#include "compute/work_precision.hpp"

#include <eulervop/reference/integrate.hpp>
#include <eulervop/runs/comparison_run.hpp>
#include <eulervop/special/elliptic.hpp>
#include <eulervop/model/error_measure.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/integrals.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/core/outcome_text.hpp>
#include <eulervop/rk/explicit_rk.hpp>
#include <eulervop/core/scalar.hpp>

#include <boost/math/special_functions/fpclassify.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace eulervop::app {

namespace fs = std::filesystem;

namespace {

// ---- flags -> a job -------------------------------------------------------------------------

struct run_spec {
  formulation form;
  rk::method method;
  std::optional<std::size_t> tol;  // adaptive: index into the job's tolerances
  std::string column() const { return fmt::format("{}_{}", formulation_name(form), rk::method_name(method)); }
};

// A --reference file and its metadata, read before the computation's scalar type is chosen.
struct reference_file_info {
  std::string path;
  reference_metadata meta;
};

struct report_job {
  scene scn;
  std::string overrides;
  fixed_step_choice step;
  std::vector<ladder_tol> tols;  // adaptive runs (--tols) instead of the fixed step
  double h_max = 0;
  std::string h_max_rule;
  std::vector<run_spec> runs;
  std::size_t samples = 0;
  eulervop::precision precision;  // of a computed reference
  picard_settings settings;
  bool verify = false;
  std::optional<reference_file_info> file;
  fs::path out_dir;
  bool json = false;
  bool plot = true;
  std::string note;  // one line for the table and the summary, when the runs differ from the usual
};

constexpr std::int64_t default_K_divisor = 200;
// The methods of `report --tols` without --methods: the paper's Fehlberg pair and DOP853.
const std::vector<rk::method> default_adaptive_methods = {rk::method::rkf45, rk::method::dop853};
constexpr std::int64_t default_samples = 2000;

// Reads the file's metadata; the scene it names must be the report's.
reference_file_info read_reference_metadata(const std::string& path, const scene& s) {
  std::ifstream in = open_input_file("--reference", path);
  const reference_csv_reader reader(in, "--reference " + path);
  const reference_metadata& m = reader.metadata();
  if (!m.scene_name.empty() && m.scene_name != s.name)
    throw input_error(fmt::format("--reference {}: the reference is for scene `{}`, the report is for scene `{}`", path,
                                  m.scene_name, s.name));
  return {path, m};
}

// With --reference, the file's samples and precision are used: flags that would set them are bad input.
void check_reference_flags(const report_options& o) {
  if (!o.reference_file) return;
  for (const auto& [flag, given] : {std::pair{"--samples", o.overrides.samples.has_value()},
                                    std::pair{"--precision", o.overrides.precision.has_value()},
                                    std::pair{"--degree", o.overrides.degree.has_value()},
                                    std::pair{"--tolerance", o.overrides.tolerance.has_value()},
                                    std::pair{"--verify", o.verify}})
    if (given)
      throw input_error(fmt::format("{}: not used with --reference {} (the file's samples and precision are used)", flag,
                                    *o.reference_file));
}

// The step of the runs: --step, else [run] step, else K/200; or error control (--tols, no step).
void choose_step(report_job& job, const report_options& o) {
  const scene& s = job.scn;
  if (o.tols) {
    if (o.step)
      throw input_error(fmt::format("--tols {} and --step {}: a report runs either at one fixed step or under error "
                                    "control; give one of them",
                                    *o.tols, *o.step));
    for (const auto& [flag, given] : {std::pair{"--reference", o.reference_file.has_value()}, std::pair{"--verify", o.verify}})
      if (given)
        throw input_error(fmt::format("{}: not used with --tols (the adaptive runs are measured at their own step points "
                                      "against the reference computed here)",
                                      flag));
    job.tols = tol_ladder("--tols", *o.tols);
    wp_grid bounds;
    bounds.scn = s;
    resolve_max_step(bounds, o.max_step);
    job.h_max = bounds.h_max;
    job.h_max_rule = bounds.h_max_rule;
  } else if (o.max_step) {
    throw input_error(fmt::format("--max-step {}: only for the adaptive runs of --tols", *o.max_step));
  } else if (o.step) {
    job.step = resolve_step(s, parse_step_flag(*o.step), "--step " + *o.step);
  } else if (s.step) {
    job.step = resolve_step(s, *s.step, "[run] step (override with --step)");
  } else {
    step_spec spec;
    spec.K_divisor = default_K_divisor;
    job.step = resolve_step(s, spec, fmt::format("the default step K/{} (give --step)", default_K_divisor));
  }

}

// Formulations x methods (x tolerances); returns the formulations.
std::vector<formulation> choose_runs(report_job& job, const report_options& o) {
  const scene& s = job.scn;
  const bool direct = uses_direct_form(s);  // the paper's VOP does not apply
  std::vector<formulation> forms;
  if (o.formulations)
    forms = formulations_of(flag_list("--formulations", *o.formulations), "--formulations " + *o.formulations, "");
  else if (!s.formulations.empty())
    forms = formulations_of(s.formulations, "[run] formulations", "; override with --formulations");
  else if (direct)
    forms = {formulation::euler};
  else
    forms = {formulation::euler, formulation::vop};
  if (direct)
    job.note = fmt::format("the paper's VOP does not apply to this body (two moments are equal or within {} of each "
                           "other), so only euler runs, on Eq. 1 itself: tau is t in s and Omega is omega in rad/s",
                           direct_form_gap);
  std::vector<rk::method> methods;
  if (o.methods) {
    methods = methods_of(flag_list("--methods", *o.methods), "--methods " + *o.methods, "");
    check_methods_for_ladders(methods, job.tols.empty(), !job.tols.empty(), "--methods " + *o.methods);
  } else if (!job.tols.empty()) {
    methods = default_adaptive_methods;
  } else if (!s.methods.empty()) {
    methods = methods_of(s.methods, "[run] methods", "; override with --methods");
    check_methods_for_ladders(methods, true, false, "[run] methods");
  } else {
    methods = {rk::method::rk4, rk::method::rkf45};
  }
  for (formulation f : forms)
    for (rk::method m : methods) {
      if (job.tols.empty()) job.runs.push_back({f, m});
      for (std::size_t t = 0; t < job.tols.size(); ++t) job.runs.push_back({f, m, t});
    }

  return forms;
}

report_job make_job(const report_options& o) {
  report_job job;
  job.scn = o.scene_path ? load_scene_file(*o.scene_path) : load_default_scene();
  scene& s = job.scn;

  // Error samples are step points of the runs, about `samples` of them: the scene's explicit
  // sample times do not apply.
  if (!s.samples) s.samples = s.times.empty() ? default_samples : std::max<std::int64_t>(2, std::ssize(s.times));
  s.times.clear();

  check_reference_flags(o);
  const applied_overrides applied = apply_scene_overrides(s, o.overrides);
  job.overrides = applied.text();
  job.precision = applied.precision;
  job.settings = applied.settings;
  job.verify = o.verify;
  job.samples = static_cast<std::size_t>(*s.samples);

  choose_step(job, o);
  const std::vector<formulation> forms = choose_runs(job, o);
  probe_formulations(forms, to_problem<double>(s), job.tols.empty() ? job.step.h : std::min(job.h_max, tau_end_of<double>(s)));

  if (o.reference_file) job.file = read_reference_metadata(*o.reference_file, s);

  job.out_dir = out_dir_of(o.out_dir, "report");
  const std::string format = o.format.value_or("table");
  if (format != "table" && format != "json")
    throw input_error(fmt::format("--format {}: expected table or json", format));
  job.json = format == "json";
  job.plot = !o.no_plot;
  return job;
}

// ---- the computation ---------------------------------------------------------------------------

// What the summary says of a reference computed here.
struct computed_reference_info {
  double seconds = 0;
  std::size_t segments = 0;
};

// The reference at the error sample points, in T.
template <scalar T>
struct reference_samples {
  std::vector<std::size_t> steps;  // step index of each sample, increasing
  std::vector<T> tau;              // its tau: n h exactly (computed) or the file's tau
  std::vector<vec3<T>> Omega;
  std::size_t n_steps = 0;         // the runs go this far
  std::size_t sample_every = 1;    // the runs sample every this many steps (and the last)
  std::string precision;
  std::optional<double> estimated_max_error;
  std::optional<double> seconds;
  std::optional<std::size_t> segments;
  std::string source;
};

// The file's rows in T, after checking that each tau is a step point of the runs.
template <scalar T>
reference_samples<T> load_reference_file(const report_job& job) {
  const reference_file_info& info = *job.file;
  const std::string where = "--reference " + info.path;
  reference_samples<T> out;
  out.precision = info.meta.precision.name();
  if (info.meta.estimated_max_error) out.estimated_max_error = info.meta.estimated_max_error->value;
  out.source = info.path;

  std::ifstream in = open_input_file("--reference", info.path);
  reference_csv_reader reader(in, where);
  // A body in the direct form has t and omega, which are its tau and Omega here.
  const std::size_t col_tau = reader.column(uses_direct_form(job.scn) ? "t" : "tau");
  csv_rows& rows = reader.rows();
  const double h = job.step.h;
  const std::size_t max_step = job.step.n_steps;
  while (rows.next()) {
    const std::size_t line = rows.line();
    const decimal tau = rows.number(col_tau);
    const vec3<T> Om = reader.template Omega<T>();
    if (tau.value < 0) throw input_error(fmt::format("{}: line {}: tau = {} is negative", where, line, tau.text));
    if (!out.tau.empty() && !(tau.value > static_cast<double>(out.tau.back())))
      throw input_error(fmt::format("{}: line {}: tau = {} does not increase", where, line, tau.text));
    // A step point of the runs: tau / h within 1e-9 of a whole number.
    const double r = tau.value / h;
    const double n = std::nearbyint(r);
    if (!(std::abs(r - n) <= 1e-9))
      throw input_error(fmt::format("{}: line {}: tau = {} is not a step point of h = {} (tau/h = {}); choose --step so "
                                    "that it divides every tau of the file",
                                    where, line, tau.text, h, r));
    if (static_cast<std::size_t>(n) > max_step)
      throw input_error(fmt::format("{}: line {}: tau = {} is beyond the span end ({} steps of h = {}); raise --tau-end",
                                    where, line, tau.text, max_step, h));
    out.steps.push_back(static_cast<std::size_t>(n));
    out.tau.push_back(tau.template to_scalar<T>());
    out.Omega.push_back(Om);
  }
  if (out.tau.empty()) throw input_error(fmt::format("{}: no data rows", where));
  out.n_steps = out.steps.back();
  std::size_t g = 0;
  for (std::size_t n : out.steps) g = std::gcd(g, n);
  out.sample_every = std::max<std::size_t>(g, 1);
  return out;
}

// The reference computed here at the sample steps {0, e, 2e, ..., n_steps}.
template <scalar T>
reference_samples<T> compute_reference(const report_job& job) {
  reference_samples<T> out;
  out.precision = job.precision.name();
  out.source = "computed";
  out.n_steps = job.step.n_steps;
  out.sample_every = std::max<std::size_t>(1, out.n_steps / std::max<std::size_t>(job.samples, 1));
  for (std::size_t n = 0; n <= out.n_steps; n += out.sample_every) out.steps.push_back(n);
  if (out.steps.back() != out.n_steps) out.steps.push_back(out.n_steps);
  for (std::size_t n : out.steps) out.tau.push_back(tau_of_step<T>(n, job.step.h));

  const euler_problem<T> problem = to_problem<T>(job.scn);
  T tau_end = tau_end_of<T>(job.scn);
  if (out.tau.back() > tau_end) tau_end = out.tau.back();  // within the 1e-9 h slack of n_steps
  sampled_reference<T> ref = integrate_and_sample<T>(problem, tau_end, out.tau, job.settings, "reference");
  out.Omega = std::move(ref.Omega);
  out.seconds = ref.wall_seconds;
  out.segments = ref.stats.segments;
  if (job.verify) {
    const verify_result v = verify<T>(job.scn, tau_end, out.tau, out.Omega, job.precision);
    out.estimated_max_error = v.max_error.value;
  }
  return out;
}

// One run's errors at the sample points (nullopt: not reached, or after divergence).
// A run and its Eq. 20 error at each sample (the reference's samples for fixed steps, the run's
// own step points for adaptive ones).
struct run_errors {
  run_result run;
  std::vector<std::optional<double>> error;
  std::optional<double> max_error, final_tau, final_error;
};

template <scalar T>
run_errors measure(const run_spec& spec, const euler_problem<double>& problem, const reference_samples<T>& ref,
                   double h) {
  run_errors out;
  out.run = run_fixed(spec.form, spec.method, problem, fixed_run_settings{h, ref.n_steps, ref.sample_every});
  const run_result& r = out.run;
  out.error.resize(ref.steps.size());
  std::size_t pos = 0;
  for (std::size_t i = 0; i < ref.steps.size(); ++i) {
    const std::size_t n = ref.steps[i];
    while (pos < r.sample_steps.size() && r.sample_steps[pos] < n) ++pos;
    if (pos == r.sample_steps.size() || r.sample_steps[pos] != n) continue;
    const double tau = static_cast<double>(n) * h;
    if (r.diverged() && r.diverged_at() && tau >= *r.diverged_at()) continue;
    const double e = static_cast<double>(eq20_error(ref.Omega[i], r.Omega[pos]));
    if (!std::isfinite(e)) continue;  // never a NaN as an error value
    out.error[i] = e;
    out.max_error = std::max(out.max_error.value_or(0.0), e);
    out.final_tau = static_cast<double>(ref.tau[i]);
    out.final_error = e;
  }
  return out;
}

// ---- output -----------------------------------------------------------------------------------

template <scalar T>
std::string errors_csv(const report_job& job, const reference_samples<T>& ref, const std::vector<run_errors>& runs) {
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out), "tau");
  for (const run_spec& r : job.runs) fmt::format_to(std::back_inserter(out), ",{}", r.column());
  out.push_back('\n');
  for (std::size_t i = 0; i < ref.steps.size(); ++i) {
    fmt::format_to(std::back_inserter(out), "{}", static_cast<double>(ref.tau[i]));  // shortest round trip
    for (const run_errors& r : runs) {
      out.push_back(',');
      if (r.error[i]) fmt::format_to(std::back_inserter(out), "{}", *r.error[i]);
    }
    out.push_back('\n');
  }
  return fmt::to_string(out);
}

// The VOP fallback stretches (docs/vop-strategies.md): [[tau_in, tau_out], ...].
nlohmann::ordered_json bands_json(const std::vector<std::pair<double, double>>& bands) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const auto& [in, out_tau] : bands) out.push_back({in, out_tau});
  return out;
}

// One entry of summary.json's "runs": a fixed run has a step and no tolerance (and no
// accepted/rejected counts), an adaptive run the reverse.
nlohmann::ordered_json run_json(const run_spec& spec, const run_errors& e, nlohmann::ordered_json step,
                                nlohmann::ordered_json tol) {
  const run_result& r = e.run;
  const bool adaptive = spec.tol.has_value();
  auto if_adaptive = [&](auto v) { return adaptive ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr); };
  auto if_diverged = [&](auto v) { return r.diverged() ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr); };
  return {{"formulation", std::string(formulation_name(spec.form))},
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
}

// "separatrix band tau 14.19..15.19, small-k bands tau 0..0.52, 3.1..3.4 (120 direct Euler steps,
// 1 regime change)": one line under the table for a run that left its elements; empty otherwise.
std::string bands_note(const run_result& r) {
  std::vector<std::string> parts;
  auto list = [&](const char* what, const std::vector<std::pair<double, double>>& bands) {
    if (bands.empty()) return;
    constexpr std::size_t shown = 4;
    std::string text = fmt::format("{} band{} tau ", what, bands.size() > 1 ? "s" : "");
    for (std::size_t i = 0; i < std::min(bands.size(), shown); ++i)
      text += fmt::format("{}{:.4g}..{:.4g}", i ? ", " : "", bands[i].first, bands[i].second);
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

template <scalar T>
nlohmann::ordered_json summary_json(const report_job& job, const reference_samples<T>& ref, const std::vector<run_errors>& runs) {
  nlohmann::ordered_json j;
  j["scene"] = job.scn.name;
  j["reference"] = {{"precision", ref.precision},
                    {"estimated_max_error", number_or_null(ref.estimated_max_error)},
                    {"source", ref.source}};
  if (ref.seconds) j["reference"]["seconds"] = *ref.seconds;
  if (ref.segments) j["reference"]["segments"] = *ref.segments;
  j["step_rule"] = job.step.rule;
  if (!job.note.empty()) j["note"] = job.note;
  j["runs"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    j["runs"].push_back(run_json(job.runs[i], runs[i], job.step.h, nullptr));
  }
  return j;
}

std::string optional_text(const std::optional<double>& x, const char* spec) {
  return x ? fmt::format(fmt::runtime(spec), *x) : std::string("-");
}

template <scalar T>
std::string table_text(const report_job& job, const reference_samples<T>& ref, const std::vector<run_errors>& runs) {
  std::vector<std::vector<std::string>> rows = {
      {"formulation", "method", "h", "steps", "rhs evals", "seconds", "max error", "final tau", "final error"}};
  std::vector<std::string> notes = {""};
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const run_result& r = runs[i].run;
    rows.push_back({std::string(formulation_name(job.runs[i].form)), std::string(rk::method_name(job.runs[i].method)),
                    fmt::format("{:.6g}", job.step.h), fmt::format("{}", r.steps), fmt::format("{}", r.rhs_evals),
                    fmt::format("{:.3f}", r.seconds), optional_text(runs[i].max_error, "{:.3e}"),
                    optional_text(runs[i].final_tau, "{:.6g}"), optional_text(runs[i].final_error, "{:.3e}")});
    notes.push_back(r.diverged() ? fmt::format("diverged at tau={} ({})", optional_text(r.diverged_at(), "{:.6g}"), describe(r.status))
                               : "");
  }
  std::vector<std::size_t> width(rows[0].size(), 0);
  for (const auto& row : rows)
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  fmt::memory_buffer out;
  auto put = [&]<class... Args>(fmt::format_string<Args...> f, Args&&... args) {
    fmt::format_to(std::back_inserter(out), f, std::forward<Args>(args)...);
  };
  put("scene {}{}: {} steps to tau = {:.6g}\n", job.scn.name, job.overrides.empty() ? "" : " (" + job.overrides + ")",
      job.step.n_steps, static_cast<double>(job.step.n_steps) * job.step.h);
  put("step: {}\n", job.step.rule);
  if (!job.note.empty()) put("note: {}\n", job.note);
  put("reference: {} ({}{}), estimated max error {}\n", ref.precision, ref.source,
      ref.seconds ? fmt::format(", {:.1f} s", *ref.seconds) : "", optional_text(ref.estimated_max_error, "{:.2e}"));
  put("error samples: {} (every {} steps)\n\n", ref.steps.size(), ref.sample_every);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    std::string line;
    for (std::size_t c = 0; c < rows[r].size(); ++c) {
      // Text columns left-aligned, numbers right-aligned.
      const std::string cell = c < 2 ? fmt::format("{:<{}}", rows[r][c], width[c]) : fmt::format("{:>{}}", rows[r][c], width[c]);
      line += (c ? "  " : "") + cell;
    }
    if (!notes[r].empty()) line += "  " + notes[r];
    while (!line.empty() && line.back() == ' ') line.pop_back();
    put("{}\n", line);
  }
  // Where the VOP runs left their elements (separatrix and small-k fallbacks), one line per run.
  bool first_note = true;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::string note = bands_note(runs[i].run);
    if (note.empty()) continue;
    if (first_note) put("\n");
    first_note = false;
    put("{} {}: {}\n", formulation_name(job.runs[i].form), rk::method_name(job.runs[i].method), note);
  }
  return fmt::to_string(out);
}

// ---- the adaptive report (--tols) ------------------------------------------------------------------

std::string run_label(const report_job& job, const run_spec& spec) {
  return fmt::format("{} {} tol {}", formulation_name(spec.form), rk::method_name(spec.method), job.tols[*spec.tol].text);
}

nlohmann::ordered_json adaptive_summary(const report_job& job, const computed_reference_info& ref,
                                        const std::vector<run_errors>& runs) {
  nlohmann::ordered_json j;
  j["scene"] = job.scn.name;
  j["reference"] = {{"precision", job.precision.name()},
                    {"estimated_max_error", nullptr},
                    {"source", "computed"},
                    {"seconds", ref.seconds},
                    {"segments", ref.segments}};
  if (!job.note.empty()) j["note"] = job.note;
  j["max_step"] = {{"h", job.h_max}, {"rule", job.h_max_rule}};
  j["runs"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    j["runs"].push_back(run_json(job.runs[i], runs[i], nullptr, job.tols[*job.runs[i].tol].value));
  }
  return j;
}

// errors.csv of an adaptive report: one row per sample of each run (the runs' step points differ).
std::string adaptive_errors_csv(const report_job& job, const std::vector<run_errors>& runs) {
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out), "formulation,method,tol,tau,error\n");
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const run_spec& spec = job.runs[i];
    const run_result& r = runs[i].run;
    for (std::size_t k = 0; k < r.Omega.size(); ++k) {
      if (!runs[i].error[k]) continue;
      fmt::format_to(std::back_inserter(out), "{},{},{},{},{}\n", formulation_name(spec.form), rk::method_name(spec.method),
                     job.tols[*spec.tol].value, r.sample_tau[k], *runs[i].error[k]);
    }
  }
  return fmt::to_string(out);
}

std::string adaptive_table(const report_job& job, const computed_reference_info& ref,
                           const std::vector<run_errors>& runs) {
  std::string out;
  out += fmt::format("scene {}{}: to tau = {:.6g} under error control (atol = rtol = tol)\n", job.scn.name,
                     job.overrides.empty() ? "" : " (" + job.overrides + ")", tau_end_of<double>(job.scn));
  out += fmt::format("maximum step: {}\n", job.h_max_rule);
  if (!job.note.empty()) out += fmt::format("note: {}\n", job.note);
  out += fmt::format("reference: {} (computed, {:.1f} s)\n", job.precision.name(), ref.seconds);
  out += fmt::format("error samples: about {} per run, at its accepted steps\n\n", job.samples);
  std::vector<std::vector<std::string>> rows = {{"formulation", "method", "tol", "steps", "rejected", "rhs evals",
                                                 "seconds", "max error", "final tau", "final error", ""}};
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const run_result& r = runs[i].run;
    const run_spec& spec = job.runs[i];
    rows.push_back({std::string(formulation_name(spec.form)), std::string(rk::method_name(spec.method)),
                    job.tols[*spec.tol].text, fmt::format("{}", r.steps), fmt::format("{}", r.rejected),
                    fmt::format("{}", r.rhs_evals), fmt::format("{:.3f}", r.seconds),
                    optional_text(runs[i].max_error, "{:.3e}"), optional_text(runs[i].final_tau, "{:.6g}"),
                    optional_text(runs[i].final_error, "{:.3e}"),
                    r.diverged() ? fmt::format("diverged at tau={} ({})", optional_text(r.diverged_at(), "{:.6g}"), describe(r.status))
                               : ""});
  }
  out += aligned_table(rows, 2);
  bool first_note = true;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::string note = bands_note(runs[i].run);
    if (note.empty()) continue;
    if (first_note) out += "\n";
    first_note = false;
    out += fmt::format("{}: {}\n", run_label(job, job.runs[i]), note);
  }
  return out;
}

// The sample times of all adaptive runs (tau_hi + tau_lo, in T) in increasing order, and the
// run and sample each one belongs to.
template <scalar T>
struct merged_sample_times {
  std::vector<T> tau;
  std::vector<std::pair<std::size_t, std::size_t>> owner;  // (run, sample)
};

template <scalar T>
merged_sample_times<T> merge_sample_times(const std::vector<run_errors>& runs) {
  merged_sample_times<T> all;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const run_result& r = runs[i].run;
    for (std::size_t k = 0; k < r.Omega.size(); ++k) {
      all.tau.push_back(T(r.sample_tau[k]) + T(r.sample_tau_lo[k]));
      all.owner.emplace_back(i, k);
    }
  }
  std::vector<std::size_t> order(all.tau.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all.tau[a] < all.tau[b]; });
  merged_sample_times<T> sorted;
  for (std::size_t j : order) {
    sorted.tau.push_back(all.tau[j]);
    sorted.owner.push_back(all.owner[j]);
  }
  return sorted;
}

// Every adaptive run's errors against one reference. The runs are done first: their sample
// times (their accepted steps, known only once they end) are then evaluated in increasing order
// as the reference's segments are accepted, so no segment is kept.
template <scalar T>
computed_reference_info measure_adaptive(const report_job& job, const T& tau_end, std::vector<run_errors>& runs) {
  for (run_errors& a : runs) a.error.resize(a.run.Omega.size());
  const merged_sample_times<T> times = merge_sample_times<T>(runs);
  const reference_run ref = integrate_at<T>(
      to_problem<T>(job.scn), tau_end, times.tau, job.settings, "reference", [&](std::size_t j, const vec3<T>& Om) {
        const auto [i, k] = times.owner[j];
        const double e = static_cast<double>(eq20_error(Om, runs[i].run.Omega[k]));
        if (std::isfinite(e)) runs[i].error[k] = e;  // never a NaN as an error value
      });
  for (run_errors& a : runs) {
    for (std::size_t k = 0; k < a.error.size(); ++k) {
      if (!a.error[k]) continue;
      a.max_error = std::max(a.max_error.value_or(0.0), *a.error[k]);
      a.final_tau = a.run.sample_tau[k];
      a.final_error = a.error[k];
    }
  }
  return {ref.wall_seconds, ref.stats.segments};
}

template <scalar T>
void execute_adaptive(const report_job& job, std::ostream& standard_output) {
  output_dir dir(job.out_dir, "errors.csv");
  const T tau_end = tau_end_of<T>(job.scn);
  const euler_problem<double> problem = to_problem<double>(job.scn);
  std::vector<run_errors> runs;
  for (const run_spec& spec : job.runs) {
    adaptive_run_settings s;
    s.tau_end = static_cast<double>(tau_end);
    s.atol = s.rtol = job.tols[*spec.tol].value;
    s.h_max = job.h_max;
    s.samples = job.samples;
    run_errors a;
    a.run = run_adaptive(spec.form, spec.method, problem, s);
    runs.push_back(std::move(a));
  }
  const computed_reference_info info = measure_adaptive<T>(job, tau_end, runs);
  const std::string summary = adaptive_summary(job, info, runs).dump(2) + "\n";
  write_atomically(dir.path() / "errors.csv", adaptive_errors_csv(job, runs));
  write_atomically(dir.path() / "summary.json", summary);
  dir.keep();
  if (job.json)
    standard_output << summary;
  else
    standard_output << adaptive_table(job, info, runs);
  standard_output << std::flush;
  if (job.plot) draw_figure(dir.path(), "plot_fig1.py");
}

template <scalar T>
void execute(const report_job& job, std::ostream& standard_output) {
  if (!job.tols.empty()) return execute_adaptive<T>(job, standard_output);
  // Everything that can be bad input is checked before the directory is touched.
  std::optional<reference_samples<T>> from_file;
  if (job.file) from_file = load_reference_file<T>(job);
  output_dir dir(job.out_dir, "errors.csv");

  const reference_samples<T> ref = from_file ? std::move(*from_file) : compute_reference<T>(job);
  const euler_problem<double> problem = to_problem<double>(job.scn);
  std::vector<run_errors> runs;
  for (const run_spec& spec : job.runs) runs.push_back(measure<T>(spec, problem, ref, job.step.h));

  const std::string summary = summary_json<T>(job, ref, runs).dump(2) + "\n";
  write_atomically(dir.path() / "errors.csv", errors_csv<T>(job, ref, runs));
  write_atomically(dir.path() / "summary.json", summary);
  dir.keep();

  if (job.json)
    standard_output << summary;
  else
    standard_output << table_text<T>(job, ref, runs);
  standard_output << std::flush;
  if (job.plot) draw_figure(dir.path(), "plot_fig1.py");
}

}  // namespace

CLI::App* add_report_command(CLI::App& app, report_options& o) {
  CLI::App* sub = app.add_subcommand(
      "report", "Run Euler and VOP in double at a fixed step or under error control; Eq. 20 errors, summary and Fig. 1");
  auto bind = [&](const std::string& name, std::optional<std::string>& target, const std::string& help) {
    return add_text_option(*sub, name, target, help);
  };
  bind("scene", o.scene_path, "Scene file (TOML); default: the embedded paper scene")->type_name("SCENE");
  bind("--reference", o.reference_file, "Reference CSV written by `eulervop reference` (default: computed here)")
      ->type_name("FILE");
  bind("--step", o.step, "Fixed step: K/N (K of the initial modulus) or h (default: [run] step, else K/200)")
      ->type_name("S");
  bind("--tols", o.tols, "Instead of a fixed step: comma-separated tolerances (atol = rtol) of adaptive runs")
      ->type_name("LIST");
  bind("--max-step", o.max_step, "Largest step of the adaptive runs: K/N or h (default: K/2)")->type_name("S");
  bind("--methods", o.methods,
       "Comma-separated: rk4,rkf45,dp45,rk8; with --tols rkf45,dp45,dop853 (default: [run] methods, else rk4,rkf45; "
       "with --tols rkf45,dop853)")
      ->type_name("LIST");
  bind("--formulations", o.formulations, "Comma-separated: euler,vop (default: [run] formulations, else euler,vop)")
      ->type_name("LIST");
  scene_override_set which;
  which.times = false;
  add_scene_override_options(*sub, o.overrides, which, "About this many error samples, at the runs' step points");
  add_output_flags(*sub, o.out_dir, o.no_plot, "report", "fig1");
  bind("--format", o.format, "Standard output: table (default) or json (summary.json)")->type_name("F");
  sub->add_flag("--verify", o.verify, "Recompute the reference one precision up for its estimated_max_error");
  return sub;
}

void run_report(const report_options& options, std::ostream& standard_output) {
  const report_job job = make_job(options);
  const eulervop::precision p = job.file ? job.file->meta.reading_precision() : job.precision;
  with_scalar(p, [&](auto zero) { execute<decltype(zero)>(job, standard_output); });
}

}  // namespace eulervop::app
