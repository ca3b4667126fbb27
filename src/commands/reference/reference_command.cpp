#include "commands/reference/reference_command.hpp"

#include "compute/scene_time.hpp"
#include "cli/exit_codes.hpp"
#include "cli/scene_overrides.hpp"
#include "compute/certified_reference.hpp"
#include "compute/reference_compute.hpp"
#include "compute/verify.hpp"
#include "compute/scene_library.hpp"
#include "compute/with_scalar.hpp"
#include "io/atomic_file.hpp"
#include "io/reference_csv.hpp"
#include "io/scratch_file.hpp"

#include <eulervop/core/scalar.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/reference/segment_sampler.hpp>

#include <array>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eulervop::app {

namespace reference_flags {
const flag_def verify{"--verify", "",
                      "Recompute one precision up and report # estimated_max_error (a body's also in rad/s: "
                      "# estimated_max_error_omega)"};
const flag_def certify{"--certify", "",
                       "Prove a bound on every row's distance to the exact solution: a radius column and "
                       "# certified_max_error (docs/certified.md)"};
}  // namespace reference_flags

namespace {

// Everything a run needs, validated.
struct reference_job {
  scene scn;                         // the scene with --tau-end/--t-end/--samples/--times applied
  eulervop::precision precision;     // --precision, else [reference] precision
  picard_settings settings;          // --degree/--tolerance, else [reference], else automatic
  reference_layout layout = reference_layout::normalized;  // of the header and of every row
  bool verify = false;
  bool certify = false;
  bool omit_timing = false;          // no "# wall_seconds" lines
  unsigned certify_workers = 0;      // threads that prepare the certificate's segments
  std::string command;               // the "# command:" line, if any
  std::string overrides;             // the flags that changed the scene, for the metadata
};

// The flags applied to the scene and validated (a scene --certify cannot prove is bad input),
// before any computation.
reference_job make_job(const reference_options& o) {
  reference_job job;
  job.scn = load_scene(o.scene_path);
  const applied_overrides applied = apply_scene_overrides(job.scn, o.overrides);
  if (!job.scn.samples && job.scn.times.empty())
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

// The texts of three or four values, as the rows print them.
template <scalar T, std::size_t N>
std::array<std::string, N> texts_of(const std::array<T, N>& v) {
  std::array<std::string, N> out;
  for (std::size_t i = 0; i < N; ++i) out[i] = to_text(v[i]);
  return out;
}

// One row of a reference file, in the job's layout: the state (Omega, omega in the direct form, or
// y), for a physical body in the normalized form also t and omega in rad/s, and q with an
// attitude. With a certificate the row's cells are formatted first and its radii computed for
// them, on the certificate's thread (run_certificate::row), then appended in the header's order.
template <scalar T>
class row_emitter {
 public:
  row_emitter(const reference_job& job, reference_csv_row_writer& rows, run_certificate* certificate)
      : job_(job), rows_(rows), certificate_(certificate) {
    if (job.layout == reference_layout::physical) scale_.emplace(scaling_of<T>(job.scn));
  }

  // The sample at tau (and t), with q when the scene has an attitude.
  void operator()(const T& tau, const T* t, const vec3<T>& y, const quaternion<T>* q) {
    const bool physical = job_.layout == reference_layout::physical;
    if (!certificate_) {
      if (physical && q) rows_.row(tau, y, *t, scale_->omega_of_Omega(y), *q);
      else if (physical) rows_.row(tau, y, *t, scale_->omega_of_Omega(y));
      else if (q) rows_.row(t ? *t : tau, y, *q);
      else rows_.row(t ? *t : tau, y);
      return;
    }
    certified_cells cells;
    cells.state = texts_of(y);
    if (physical) cells.omega = texts_of(scale_->omega_of_Omega(y));
    if (q) cells.q = texts_of(std::array<T, 4>{q->w, q->x, q->y, q->z});
    std::string time = to_text(tau), scene_time = t ? to_text(*t) : time;
    certificate_->row([this, tau, t = t ? *t : tau, cells = std::move(cells), time = std::move(time),
                       scene_time = std::move(scene_time)] {
      const certified_radii r = certificate_->radii(tau, t, cells);
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
      rows_.certified_row(out);
    });
  }

 private:
  const reference_job& job_;
  reference_csv_row_writer& rows_;
  run_certificate* certificate_;
  std::optional<physical_scaling<T>> scale_;
};

// Integrates the job's scene in T and writes each sample's row, in the job's layout, to
// `rows_out` as it is evaluated: the rates alone, or with q beside them (integrated beside the
// rates, reference/attitude_cascade.hpp, or with them as one problem for a torque of the
// attitude, model/coupled_problem.hpp). `kept` and `kept_q`, if given, receive the samples too.
// With --certify, `certificate` checks every segment and each row carries its radii.
template <scalar T>
reference_run stream_rows(const reference_job& job, const T& tau_end, const sample_times<T>& times,
                          scratch_file& rows_out, std::vector<vec3<T>>* kept, std::vector<quaternion<T>>* kept_q,
                          run_certificate* certificate) {
  reference_csv_row_writer rows([&](std::string_view chunk) { rows_out.write(chunk); });
  // The certificate's threads write rows: they stop before `rows` goes, even on an exception.
  const std::unique_ptr<run_certificate, void (*)(run_certificate*)> closing(
      certificate, [](run_certificate* c) { if (c) c->close(); });
  row_emitter<T> emit(job, rows, certificate);
  const auto time_of = [&](std::size_t i) { return times.t.empty() ? nullptr : &times.t[i]; };
  reference_run run;
  if (job.scn.has_attitude()) {
    segment_sink<T, 7> certify_segment;
    if (certificate)
      certify_segment = [&](const chebyshev_segment<T, 7>& seg, const std::vector<T>& nodes) {
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
      certify_segment = [&](const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
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
  rows.flush();
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

// Runs the job in T, streaming the CSV rows to `rows_out`.
template <scalar T>
reference_metadata run_in(const reference_job& job, scratch_file& rows_out) {
  const T tau_end = tau_end_of<T>(job.scn);
  const sample_times<T> times = sample_times_of<T>(job.scn);
  // --verify compares the samples with a wider run's, so it keeps them: memory then grows with
  // the number of samples (never with the span). Without it nothing is kept.
  std::vector<vec3<T>> kept;
  std::vector<quaternion<T>> kept_q;
  std::optional<run_certificate> certificate;
  if (job.certify) certificate.emplace(job.scn, job.precision, job.certify_workers);
  const bool attitude = job.scn.has_attitude();
  const reference_run run = stream_rows<T>(job, tau_end, times, rows_out, job.verify ? &kept : nullptr,
                                           job.verify && attitude ? &kept_q : nullptr,
                                           certificate ? &*certificate : nullptr);
  reference_metadata m = metadata_of(job, run);
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

// Runs the job in its precision, streaming the CSV rows to `rows_out`, and returns the metadata
// block's content (layout in the README, "Command line").
reference_metadata run_job(const reference_job& job, scratch_file& rows_out) {
  return with_scalar(job.precision, [&](auto zero) { return run_in<decltype(zero)>(job, rows_out); });
}

}  // namespace

void add_reference_flags(CLI::App& sub, reference_options& o) {
  add_text_flag(sub, {"scene", "SCENE", "Scene file (TOML); default: the embedded paper scene"}, o.scene_path);
  add_scene_override_flags(sub, o.overrides, scene_override_set{},
                           "Number of equally spaced samples, endpoints included");
  add_text_flag(sub, {"--out", "FILE", "Output file (default: standard output)"}, o.out);
  add_switch(sub, reference_flags::verify, o.verify);
  add_switch(sub, reference_flags::certify, o.certify);
}

int run_reference(const reference_options& options, std::ostream& standard_output) {
  const reference_job job = make_job(options);
  // Open the output first, so an unwritable path fails before any computation.
  std::unique_ptr<atomic_file> file;
  if (options.out) file = std::make_unique<atomic_file>(*options.out);
  // The header states the finished run (segments, wall time, --verify's estimate) but comes
  // first: the rows are streamed to a scratch file during the run, then copied after it.
  scratch_file rows(scratch_directory_for(file.get()));
  const std::string header =
      in_scene_time(job.scn, [&] { return reference_csv_header(run_job(job, rows), job.layout); });
  if (file) {
    file->write(header);
    rows.copy_to([&](std::string_view chunk) { file->write(chunk); });
    file->commit();
  } else {
    standard_output << header;
    rows.copy_to([&](std::string_view chunk) { standard_output.write(chunk.data(), std::ssize(chunk)); });
    standard_output << std::flush;
  }
  return exit_success;
}

}  // namespace eulervop::app
