#include "commands/report/fixed_step_report.hpp"

#include <eulervop/runs/comparison_run.hpp>
#include "commands/report/fixed_step_output.hpp"
#include "commands/report/report_output.hpp"
#include "compute/reference_compute.hpp"
#include "compute/verify.hpp"
#include "compute/step_rule.hpp"
#include "compute/with_scalar.hpp"
#include "io/csv_rows.hpp"
#include "io/output_dir.hpp"
#include "io/reference_csv.hpp"

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/model/error_measure.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <numeric>

namespace eulervop::app {

namespace {

// The attitude error of a run's q against the reference's, in T: the angle of the rotation
// between them (core/quaternion.hpp), radians.
template <scalar T>
double attitude_error(const quaternion<T>& reference, const quaternion<double>& run) {
  return static_cast<double>(rotation_angle(reference, quaternion<T>{T(run.w), T(run.x), T(run.y), T(run.z)}));
}

// The reference at the error sample points, in T.
template <scalar T>
struct reference_samples {
  fixed_reference_info info;
  std::vector<std::size_t> steps;  // step index of each sample, increasing
  std::vector<T> tau;              // its tau: n h exactly (computed) or the file's tau
  std::vector<vec3<T>> Omega;
  std::vector<quaternion<T>> q;    // the attitude there (attitude jobs only)
  std::size_t n_steps = 0;         // the runs go this far
};

// A row of the --reference file, checked: tau >= 0, increasing, a step point of the runs
// (tau / h within 1e-9 of a whole number) within their span. Returns its step index.
std::size_t step_of_row(const report_job& job, const std::string& where, std::size_t line, const decimal& tau,
                        std::optional<double> previous) {
  const double h = job.step.h;
  if (tau.value < 0) throw input_error(fmt::format("{}: line {}: tau = {} is negative", where, line, tau.text));
  if (previous && !(tau.value > *previous))
    throw input_error(fmt::format("{}: line {}: tau = {} does not increase", where, line, tau.text));
  const double r = tau.value / h;
  const double n = std::nearbyint(r);
  if (!(std::abs(r - n) <= 1e-9))
    throw input_error(fmt::format("{}: line {}: tau = {} is not a step point of h = {} (tau/h = {}); choose --step so "
                                  "that it divides every tau of the file",
                                  where, line, tau.text, h, r));
  if (static_cast<std::size_t>(n) > job.step.n_steps)
    throw input_error(fmt::format("{}: line {}: tau = {} is beyond the span end ({} steps of h = {}); raise --tau-end",
                                  where, line, tau.text, job.step.n_steps, h));
  return static_cast<std::size_t>(n);
}

// The file's rows in T, after checking that each tau is a step point of the runs.
template <scalar T>
reference_samples<T> load_reference_file(const report_job& job) {
  const reference_file_info& file = *job.file;
  const std::string where = "--reference " + file.path;
  reference_samples<T> out;
  out.info.precision = file.meta.precision.name();
  if (file.meta.estimated_max_error) out.info.estimated_max_error = file.meta.estimated_max_error->value;
  out.info.source = file.path;

  std::ifstream in = open_input_file("--reference", file.path);
  reference_csv_reader reader(in, where);
  // A body in the direct form has t and omega (the coefficient form t and y), which are its tau
  // and Omega here.
  const std::size_t col_tau = reader.column(uses_direct_form(job.scn) ? "t" : "tau");
  // An attitude job's file has the attitude (report_command.cpp checks its metadata): q0..q3.
  std::array<std::size_t, 4> col_q{};
  if (job.attitude)
    for (std::size_t c = 0; c < 4; ++c) col_q[c] = reader.column(fmt::format("q{}", c), " (the attitude)");
  csv_rows& rows = reader.rows();
  while (rows.next()) {
    const decimal tau = rows.number(col_tau);
    const vec3<T> Om = reader.template Omega<T>();
    if (job.attitude)
      out.q.push_back({rows.number(col_q[0]).template to_scalar<T>(), rows.number(col_q[1]).template to_scalar<T>(),
                       rows.number(col_q[2]).template to_scalar<T>(), rows.number(col_q[3]).template to_scalar<T>()});
    const std::optional<double> previous =
        out.tau.empty() ? std::nullopt : std::optional<double>(static_cast<double>(out.tau.back()));
    out.steps.push_back(step_of_row(job, where, rows.line(), tau, previous));
    out.tau.push_back(tau.template to_scalar<T>());
    out.Omega.push_back(Om);
  }
  if (out.tau.empty()) throw input_error(fmt::format("{}: no data rows", where));
  out.n_steps = out.steps.back();
  std::size_t g = 0;
  for (std::size_t n : out.steps) g = std::gcd(g, n);
  out.info.sample_every = std::max<std::size_t>(g, 1);
  return out;
}

// The reference computed here at the sample steps {0, e, 2e, ..., n_steps}.
template <scalar T>
reference_samples<T> compute_reference(const report_job& job) {
  reference_samples<T> out;
  out.info.precision = job.precision.name();
  out.info.source = "computed";
  out.n_steps = job.step.n_steps;
  const std::size_t every = std::max<std::size_t>(1, out.n_steps / std::max<std::size_t>(job.samples, 1));
  out.info.sample_every = every;
  for (std::size_t n = 0; n <= out.n_steps; n += every) out.steps.push_back(n);
  if (out.steps.back() != out.n_steps) out.steps.push_back(out.n_steps);
  for (std::size_t n : out.steps) out.tau.push_back(tau_of_step<T>(n, job.step.h));

  T tau_end = tau_end_of<T>(job.scn);
  if (out.tau.back() > tau_end) tau_end = out.tau.back();  // within the 1e-9 h slack of n_steps
  if (job.attitude) {
    // The rates and the attitude together (reference/attitude_cascade.hpp).
    out.Omega.resize(out.tau.size());
    out.q.resize(out.tau.size());
    const reference_run ref = integrate_scene_attitude<T>(job.scn, tau_end, out.tau, job.settings, "reference",
                                                          [&](std::size_t i, const vec3<T>& y, const quaternion<T>& q) {
                                                            out.Omega[i] = y;
                                                            out.q[i] = q;
                                                          });
    out.info.seconds = ref.wall_seconds;
    out.info.segments = ref.stats.segments;
  } else {
    sampled_reference<T> ref = with_problem<T>(job.scn, [&](const auto& problem) {
      return integrate_and_sample<T>(problem, tau_end, out.tau, job.settings, "reference");
    });
    out.Omega = std::move(ref.Omega);
    out.info.seconds = ref.wall_seconds;
    out.info.segments = ref.stats.segments;
  }
  if (job.verify) {
    const verify_result v =
        verify<T>(job.scn, tau_end, out.tau, out.Omega, job.precision, job.attitude ? &out.q : nullptr);
    out.info.estimated_max_error = v.max_error.value;
    if (v.max_attitude_error) out.info.estimated_max_attitude_error = v.max_attitude_error->value;
  }
  return out;
}

// One run at the report's step and its errors at the reference's samples (nullopt: not reached,
// or after divergence); with the attitude, q too (settings.hpp) and its error.
template <scalar T, class Problem>
run_errors measure(const report_job& job, const run_spec& spec, const Problem& problem,
                   const reference_samples<T>& ref, double h) {
  run_errors out;
  fixed_run_settings settings{h, ref.n_steps, ref.info.sample_every};
  if (job.attitude) {
    settings.attitude = attitude_settings{body_rates_of<double>(job.scn), attitude_of<double>(job.scn)};
    out.attitude_error.resize(ref.steps.size());
  }
  out.run = run_fixed(spec.form, spec.method, problem, settings);
  const run_result& r = out.run;
  const report_units units = report_units::of(job.scn);
  out.error.resize(ref.steps.size());
  if (units.physical) out.rate_error.resize(ref.steps.size());
  std::size_t pos = 0;
  for (std::size_t i = 0; i < ref.steps.size(); ++i) {
    const std::size_t n = ref.steps[i];
    while (pos < r.sample_steps.size() && r.sample_steps[pos] < n) ++pos;
    if (pos == r.sample_steps.size() || r.sample_steps[pos] != n) continue;
    const double tau = static_cast<double>(n) * h;
    if (r.diverged() && r.diverged_at() && tau >= *r.diverged_at()) continue;
    const double e = static_cast<double>(eq20_error(ref.Omega[i], r.Omega[pos]));
    const std::optional<double> rate =
        units.physical ? std::optional<double>(units.rate_error(ref.Omega[i], r.Omega[pos])) : std::nullopt;
    const std::optional<double> attitude =
        job.attitude ? std::optional<double>(attitude_error(ref.q[i], r.q[pos])) : std::nullopt;
    record_errors(out, i, static_cast<double>(ref.tau[i]), e, attitude, units, rate);  // never a NaN
  }
  return out;
}

template <scalar T>
void fixed_step_report_in(const report_job& job, std::ostream& standard_output) {
  // Everything that can be bad input is checked before the directory is touched.
  std::optional<reference_samples<T>> from_file;
  if (job.file) from_file = load_reference_file<T>(job);
  output_dir dir(job.out_dir, "errors.csv");

  reference_samples<T> ref = from_file ? std::move(*from_file) : compute_reference<T>(job);
  for (const T& tau : ref.tau) ref.info.tau.push_back(static_cast<double>(tau));
  std::vector<run_errors> runs;
  with_run_problem(job.scn, [&](const auto& problem) {
    for (const run_spec& spec : job.runs) runs.push_back(measure<T>(job, spec, problem, ref, job.step.h));
  });

  const std::string summary = fixed_summary_json(job, ref.info, runs).dump(2) + "\n";
  write_report(job, dir, fixed_errors_csv(job, ref.info, runs), summary,
               job.json ? summary : fixed_table(job, ref.info, runs), standard_output);
}

}  // namespace

void run_fixed_step_report(const report_job& job, std::ostream& standard_output) {
  const eulervop::precision p = job.file ? job.file->meta.reading_precision() : job.precision;
  with_scalar(p, [&](auto zero) { fixed_step_report_in<decltype(zero)>(job, standard_output); });
}

}  // namespace eulervop::app
