#include "commands/reference/reference_job.hpp"

#include "cli/scene_overrides.hpp"
#include "compute/reference_compute.hpp"
#include "compute/run_certificate.hpp"
#include "compute/scene_time.hpp"
#include "compute/verify.hpp"
#include "compute/with_scalar.hpp"

#include <eulervop/model/physical_scaling.hpp>

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <utility>
#include <optional>
#include <string>
#include <vector>

namespace eulervop::app {

reference_job reference_job_of(scene s, const reference_options& o, bool times_follow) {
  reference_job job;
  job.scn = std::move(s);
  const applied_overrides applied = apply_scene_overrides(job.scn, o.overrides);
  if (!times_follow && !job.scn.samples && job.scn.times.empty())
    throw input_error(fmt::format("[span] of scene {}: no samples or times; give samples (a count) or times (a "
                                  "list) in the scene, or --samples N or --times LIST",
                                  job.scn.name));
  job.precision = applied.precision;
  job.settings = applied.settings;
  job.layout = reference_layout_of(job.scn);
  job.verify = o.verify;
  job.certify = o.certify;
  job.certify_workers = o.certify_one_thread ? 0 : certify_workers();
  if (job.certify) require_certifiable(job.precision);
  job.omit_timing = o.omit_timing;
  job.command = o.command;
  job.overrides = applied.text();
  return job;
}

reference_job reference_job_of(const reference_options& o) { return reference_job_of(load_scene(o.scene_path), o); }

namespace {

// The scene's own samples (equally spaced or listed), each rounded to binary64.
std::vector<double> rounded_grid(const scene& s) {
  const sample_times<quad> grid = sample_times_of<quad>(s);
  const std::vector<quad>& x = s.is_physical() ? grid.t : grid.tau;
  std::vector<double> out;
  out.reserve(x.size());
  for (const quad& v : x) out.push_back(static_cast<double>(v));
  return out;
}

// A binary64 number as Python and NumPy show it: the shortest text that gives it back, with a
// decimal point ("700.0", "0.1", "1e-07").
std::string shown(double x) {
  std::string s = fmt::format("{}", x);
  if (std::isfinite(x) && s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

// Each time finite, >= 0, after the one before, and within the span: at most its end, or the end
// rounded to binary64 (which the run then reaches).
void check_binary_times(const scene& s, const std::vector<double>& times) {
  if (times.empty()) throw input_error("times: empty; give at least one time");
  const quad end = s.span_end.to_scalar<quad>();
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double x = times[i];
    if (!std::isfinite(x)) throw input_error(fmt::format("times[{}] = {} is not finite", i, shown(x)));
    if (x < 0) throw input_error(fmt::format("times[{}] = {} is negative (the span starts at 0)", i, shown(x)));
    if (i > 0 && !(x > times[i - 1]))
      throw input_error(fmt::format("times[{}] = {} does not increase (times[{}] = {}): the times must increase "
                                    "strictly",
                                    i, shown(x), i - 1, shown(times[i - 1])));
    if (quad(x) > end && x != s.span_end.value)
      throw input_error(fmt::format("times[{}] = {} is beyond {} = {} of scene {} (compared exactly)", i, shown(x),
                                    s.span_key(), s.span_end.text, s.name));
  }
}

}  // namespace

void use_binary_times(reference_job& job, std::optional<std::vector<double>> times) {
  if (times) check_binary_times(job.scn, *times);
  job.binary_times = times ? std::move(*times) : rounded_grid(job.scn);
}

}  // namespace eulervop::app

namespace eulervop::app {

namespace {

// The texts of three or four values, as the rows print them.
template <scalar T, std::size_t N>
std::array<std::string, N> texts_of(const std::array<T, N>& v) {
  std::array<std::string, N> out;
  for (std::size_t i = 0; i < N; ++i) out[i] = to_text(v[i]);
  return out;
}

// Hands each sample to the sink; with a certificate also the row's cells, formatted first, and
// its radii computed for them on the certificate's thread (run_certificate::row), in the header's
// order (reference_csv_header).
template <scalar T>
class row_emitter {
 public:
  row_emitter(const reference_job& job, reference_row_sink& sink, run_certificate* certificate)
      : job_(job), sink_(sink), certificate_(certificate) {
    if (job.layout == reference_layout::physical) scale_.emplace(scaling_of<T>(job.scn));
  }

  // The sample at tau (and t), with q when the scene has an attitude.
  void operator()(const T& tau, const T* t, const vec3<T>& y, const quaternion<T>* q) {
    sink_.values(tau, t, y, q);
    if (!certificate_) return;
    certified_cells cells;
    cells.state = texts_of(y);
    if (scale_) cells.omega = texts_of(scale_->omega_of_Omega(y));
    if (q) cells.q = texts_of(std::array<T, 4>{q->w, q->x, q->y, q->z});
    std::string time = to_text(tau), scene_time = t ? to_text(*t) : time;
    certificate_->row([this, tau, t = t ? *t : tau, cells = std::move(cells), time = std::move(time),
                       scene_time = std::move(scene_time)] {
      const certified_radii r = certificate_->radii(tau, t, cells);
      sink_.certified(row_cells(cells, time, scene_time, r), r);
    });
  }

 private:
  std::vector<std::string> row_cells(const certified_cells& cells, const std::string& time,
                                     const std::string& scene_time, const certified_radii& r) const {
    std::vector<std::string> out;
    const auto add = [&out](const auto& texts) { out.insert(out.end(), texts.begin(), texts.end()); };
    if (job_.layout == reference_layout::physical) {
      out.push_back(scene_time);
      add(*cells.omega);
      if (cells.q) add(*cells.q);
      out.push_back(time);
      add(cells.state);
      out.push_back(r.state);
      out.push_back(*r.omega);
    } else {
      // normalized (tau, Omega), direct (t, omega) or the coefficient form (t, y)
      out.push_back(job_.layout == reference_layout::normalized ? time : scene_time);
      add(cells.state);
      if (cells.q) add(*cells.q);
      out.push_back(r.state);
    }
    if (r.q) out.push_back(*r.q);
    return out;
  }

  const reference_job& job_;
  reference_row_sink& sink_;
  run_certificate* certificate_;
  std::optional<physical_scaling<T>> scale_;
};

// The sample times in T: the scene's, or the job's binary64 times taken exactly (tau from t in T
// for a physical scene, as sample_times_of maps them).
template <scalar T>
sample_times<T> times_of(const reference_job& job) {
  if (!job.binary_times) return sample_times_of<T>(job.scn);
  sample_times<T> out;
  std::vector<T> x(job.binary_times->begin(), job.binary_times->end());
  if (!job.scn.is_physical()) {
    out.tau = std::move(x);
    return out;
  }
  const physical_scaling<T> scale = scaling_of<T>(job.scn);
  for (const T& t : x) out.tau.push_back(scale.tau_of_t(t));
  out.t = std::move(x);
  return out;
}

// Integrates the job's scene in T and hands each sample to `emit` as it is evaluated: the rates
// alone, or with q beside them (integrated beside the rates, reference/attitude_cascade.hpp, or
// with them as one problem for a torque of the attitude, model/coupled_problem.hpp). `kept` and
// `kept_q`, if given, receive the samples too. With --certify, `certificate` checks every segment,
// told the rows' times at the first (as it waits for the module there anyway).
template <scalar T>
reference_run stream_rows(const reference_job& job, const T& tau_end, const sample_times<T>& times,
                          row_emitter<T>& emit, std::vector<vec3<T>>* kept, std::vector<quaternion<T>>* kept_q,
                          run_certificate* certificate) {
  // The certificate's threads hand rows on: they stop before the sink goes, even on an exception.
  const std::unique_ptr<run_certificate, void (*)(run_certificate*)> closing(
      certificate, [](run_certificate* c) { if (c) c->close(); });
  const auto time_of = [&](std::size_t i) { return times.t.empty() ? nullptr : &times.t[i]; };
  reference_run run;
  if (job.scn.has_attitude()) {
    segment_sink<T, 7> certify_segment;
    if (certificate)
      certify_segment = [&, first = true](const chebyshev_segment<T, 7>& seg, const std::vector<T>& nodes) mutable {
        if (std::exchange(first, false)) certificate->expect_rows(times.tau);
        certificate->add_segment(seg, nodes);
      };
    const auto on_sample = [&](std::size_t i, const vec3<T>& y, const quaternion<T>& q) {
      emit(times.tau[i], time_of(i), y, &q);
      if (kept) kept->push_back(y);
      if (kept_q) kept_q->push_back(q);
    };
    run = integrate_scene_attitude<T>(job.scn, tau_end, times.tau, job.settings, "reference", on_sample,
                                      certify_segment);
  } else {
    segment_sink<T> certify_segment;
    if (certificate)
      certify_segment = [&, first = true](const chebyshev_segment<T>& seg, const std::vector<T>& nodes) mutable {
        if (std::exchange(first, false)) certificate->expect_rows(times.tau);
        certificate->add_segment(seg, nodes);
      };
    const auto on_sample = [&](std::size_t i, const vec3<T>& y) {
      emit(times.tau[i], time_of(i), y, nullptr);
      if (kept) kept->push_back(y);
    };
    run = with_problem<T>(job.scn, [&](const auto& problem) {
      return integrate_streaming<T>(problem, tau_end, times.tau, job.settings, "reference", on_sample, certify_segment);
    });
  }
  if (certificate) certificate->finish();
  return run;
}

decimal decimal_of(const std::string& text) { return decimal{text, std::strtod(text.c_str(), nullptr)}; }

// The metadata block of a finished run (without --verify's and --certify's lines).
reference_metadata metadata_of(const reference_job& job, const reference_run& run) {
  reference_metadata m;
  m.scene_name = job.scn.name;
  m.scene_source = job.scn.origin;
  m.command = job.command;
  m.overrides = job.overrides;
  m.precision = job.precision;
  m.method = method_text(job.settings, run.stats);
  if (!job.omit_timing) m.wall_seconds = run.wall_seconds;
  m.notes = job.scn.notes;
  if (job.scn.has_attitude()) m.attitude = attitude_convention(job.precision);
  if (run.norm_drift) {
    m.coupled = "the torque reads the attitude: the rates and q0..q3 integrated as one problem of 7 states";
    m.q_norm_drift = decimal_of(fmt::format("{:.3g}", *run.norm_drift));
  }
  m.scene_text = job.scn.source_text;
  return m;
}

// --certify's lines: the largest radius of each column (the state; omega in rad/s for a physical
// scene, which in the direct form is the state; q) and the method.
void add_certificate(const reference_job& job, const run_certificate& certificate, reference_metadata& m) {
  const certified_maxima& max = certificate.maxima();
  m.certified_max_error = decimal_of(max.state);
  m.certify_method = certificate.method();
  if (job.layout == reference_layout::physical) m.certified_max_error_omega = decimal_of(max.omega);
  if (job.layout == reference_layout::direct) m.certified_max_error_omega = decimal_of(max.state);
  if (!max.q.empty()) m.certified_max_error_q = decimal_of(max.q);
}

// Runs the job in T.
template <scalar T>
reference_metadata run_in(const reference_job& job, reference_row_sink& sink) {
  const sample_times<T> times = times_of<T>(job);
  T tau_end = tau_end_of<T>(job.scn);
  if (times.tau.back() > tau_end) tau_end = times.tau.back();  // the span end rounded to binary64
  // --verify compares the samples with a wider run's, so it keeps them: memory then grows with
  // the number of samples (never with the span). Without it nothing is kept.
  std::vector<vec3<T>> kept;
  std::vector<quaternion<T>> kept_q;
  std::unique_ptr<run_certificate> certificate;
  if (job.certify) certificate = make_run_certificate(job.scn, job.precision, job.certify_workers);
  const bool attitude = job.scn.has_attitude();
  row_emitter<T> emit(job, sink, certificate.get());
  const reference_run run = stream_rows<T>(job, tau_end, times, emit, job.verify ? &kept : nullptr,
                                           job.verify && attitude ? &kept_q : nullptr,
                                           certificate.get());
  reference_metadata m = metadata_of(job, run);
  if (job.binary_times) m.times = binary_times_note;
  if (certificate) add_certificate(job, *certificate, m);
  if (job.verify) {
    const verify_result check =
        verify<T>(job.scn, tau_end, times.tau, kept, job.precision, attitude ? &kept_q : nullptr);
    m.estimated_max_error = check.max_error;
    m.estimated_max_error_omega = check.max_error_omega;
    m.estimated_max_attitude_error = check.max_attitude_error;
    m.verify_precision = check.precision;
    m.verify_method = check.method;
    if (!job.omit_timing) m.wall_seconds_verify = check.wall_seconds;
  }
  return m;
}

}  // namespace

reference_metadata run_reference_job(const reference_job& job, reference_row_sink& sink) {
  return in_scene_time(job.scn, [&] {
    return with_scalar(job.precision, [&](auto zero) { return run_in<decltype(zero)>(job, sink); });
  });
}

}  // namespace eulervop::app
