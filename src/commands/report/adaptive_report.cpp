#include "commands/report/adaptive_report.hpp"

#include <eulervop/runs/comparison_run.hpp>
#include "commands/report/adaptive_output.hpp"
#include "commands/report/report_output.hpp"
#include "compute/reference_compute.hpp"
#include "compute/with_scalar.hpp"
#include "io/output_dir.hpp"

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/model/error_measure.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace eulervop::app {

namespace {

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
  const report_units units = report_units::of(job.scn);
  for (run_errors& a : runs) {
    a.error.resize(a.run.Omega.size());
    if (units.physical) a.rate_error.resize(a.run.Omega.size());
  }
  const merged_sample_times<T> times = merge_sample_times<T>(runs);
  // The runs end at tau_end rounded to double, which may lie above it in T (a physical scene's
  // tau_end = t_end dtau/dt): the reference then goes on to that last step point.
  T end = tau_end;
  if (!times.tau.empty() && times.tau.back() > end) end = times.tau.back();
  const auto rates_error = [&](std::size_t j, const vec3<T>& Om) {
    const auto [i, k] = times.owner[j];
    const double e = static_cast<double>(eq20_error(Om, runs[i].run.Omega[k]));
    if (std::isfinite(e)) runs[i].error[k] = e;  // never a NaN as an error value
    if (!units.physical) return;
    const double rate = units.rate_error(Om, runs[i].run.Omega[k]);
    if (std::isfinite(rate)) runs[i].rate_error[k] = rate;
  };
  if (job.attitude)  // the rates and the attitude together, at the merged times
    for (run_errors& a : runs) a.attitude_error.resize(a.run.Omega.size());
  const reference_run ref =
      job.attitude
          ? integrate_scene_attitude<T>(job.scn, end, times.tau, job.settings, "reference",
                                        [&](std::size_t j, const vec3<T>& Om, const quaternion<T>& q) {
                                          rates_error(j, Om);
                                          const auto [i, k] = times.owner[j];
                                          const quaternion<double>& qr = runs[i].run.q[k];
                                          const double a = static_cast<double>(
                                              rotation_angle(q, quaternion<T>{T(qr.w), T(qr.x), T(qr.y), T(qr.z)}));
                                          if (std::isfinite(a)) runs[i].attitude_error[k] = a;
                                        })
          : with_problem<T>(job.scn, [&](const auto& problem) {
              return integrate_at<T>(problem, end, times.tau, job.settings, "reference", rates_error);
            });
  for (run_errors& a : runs) {
    for (std::size_t k = 0; k < a.error.size(); ++k) {
      if (!a.error[k]) continue;
      a.max_error = std::max(a.max_error.value_or(0.0), *a.error[k]);
      a.final_tau = a.run.sample_tau[k];
      a.final_error = a.error[k];
    }
    for (std::size_t k = 0; k < a.rate_error.size(); ++k) {
      if (!a.rate_error[k]) continue;
      a.max_rate_error = std::max(a.max_rate_error.value_or(0.0), *a.rate_error[k]);
      a.final_t = units.t_of(a.run.sample_tau[k]);
      a.final_rate_error = a.rate_error[k];
    }
    for (std::size_t k = 0; k < a.attitude_error.size(); ++k) {
      if (!a.attitude_error[k]) continue;
      a.max_attitude_error = std::max(a.max_attitude_error.value_or(0.0), *a.attitude_error[k]);
      a.final_attitude_error = a.attitude_error[k];
    }
  }
  return {ref.wall_seconds, ref.stats.segments};
}

// Every formulation x method x tolerance, to the span end.
std::vector<run_errors> adaptive_runs(const report_job& job, double tau_end) {
  std::vector<run_errors> runs;
  with_run_problem(job.scn, [&](const auto& problem) {
    for (const run_spec& spec : job.runs) {
      adaptive_run_settings s;
      s.tau_end = tau_end;
      s.atol = s.rtol = job.tols[*spec.tol].value;
      s.h_max = job.max_step.h;
      s.samples = job.samples;
      if (job.attitude) s.attitude = attitude_settings{body_rates_of<double>(job.scn), attitude_of<double>(job.scn)};
      run_errors a;
      a.run = run_adaptive(spec.form, spec.method, problem, s);
      runs.push_back(std::move(a));
    }
  });
  return runs;
}

template <scalar T>
void adaptive_report_in(const report_job& job, std::ostream& standard_output) {
  output_dir dir(job.out_dir, "errors.csv");
  const T tau_end = tau_end_of<T>(job.scn);
  std::vector<run_errors> runs = adaptive_runs(job, static_cast<double>(tau_end));
  const computed_reference_info info = measure_adaptive<T>(job, tau_end, runs);
  const std::string summary = adaptive_summary_json(job, info, runs).dump(2) + "\n";
  write_report(job, dir, adaptive_errors_csv(job, runs), summary, job.json ? summary : adaptive_table(job, info, runs),
               standard_output);
}

}  // namespace

void run_adaptive_report(const report_job& job, std::ostream& standard_output) {
  with_scalar(job.precision, [&](auto zero) { adaptive_report_in<decltype(zero)>(job, standard_output); });
}

}  // namespace eulervop::app
