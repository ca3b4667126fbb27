#include "commands/reference/reference_run.hpp"

#include "compute/certified_reference.hpp"
#include "compute/reference_compute.hpp"
#include "compute/with_scalar.hpp"

#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/core/scalar.hpp>

#include <array>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eulervop::app {

namespace {

// The row of each sample in the job's layout, handed to `rows_out` in chunks. With a
// certificate, each row carries the radius of the state as printed.
template <scalar T>
class layout_rows {
 public:
  layout_rows(const reference_job& job, const sample_times<T>& times, scratch_file& rows_out,
              run_certificate* certificate)
      : layout_(job.layout),
        times_(times),
        certificate_(certificate),
        rows_([&rows_out](std::string_view chunk) { rows_out.write(chunk); }) {
    if (layout_ == reference_layout::physical) scale_.emplace(scaling_of<T>(job.scn));
  }

  void operator()(std::size_t i, const vec3<T>& Om) {
    const T& tau = times_.tau[i];
    switch (layout_) {
      case reference_layout::normalized:
        if (!certificate_) return rows_.row(tau, Om);
        return certified_row(tau, Om);
      case reference_layout::physical:
        if (!certificate_) return rows_.row(tau, Om, times_.t[i], scale_->omega_of_Omega(Om));
        return certified_physical_row(tau, times_.t[i], Om);
      case reference_layout::direct: return rows_.row(times_.t[i], Om);  // the state is omega, and tau is t
    }
  }
  void flush() { rows_.flush(); }

 private:
  static std::array<std::string, 3> texts(const vec3<T>& v) { return {to_text(v[0]), to_text(v[1]), to_text(v[2])}; }

  void certified_row(const T& tau, const vec3<T>& Om) {
    const std::array<std::string, 3> cells = texts(Om);
    rows_.certified_row(tau, cells, certificate_->radius(tau, cells));
  }
  void certified_physical_row(const T& tau, const T& t, const vec3<T>& Om) {
    const std::array<std::string, 3> Omega_cells = texts(Om);
    const std::array<std::string, 3> omega_cells = texts(scale_->omega_of_Omega(Om));
    rows_.certified_row(tau, Omega_cells, t, omega_cells,
                        certificate_->physical_radii(tau, t, Omega_cells, omega_cells));
  }

  reference_layout layout_;
  const sample_times<T>& times_;
  run_certificate* certificate_;
  std::optional<physical_scaling<T>> scale_;
  reference_csv_row_writer rows_;
};

// Integrates the job's scene in T and writes each sample's row to `rows_out` as it is evaluated.
// `kept`, if given, receives the samples too. With --certify, `certificate` checks every segment.
template <scalar T>
reference_run stream_rows(const reference_job& job, const T& tau_end, const sample_times<T>& times,
                          scratch_file& rows_out, std::vector<vec3<T>>* kept, run_certificate* certificate) {
  layout_rows<T> rows(job, times, rows_out, certificate);
  segment_sink<T> certify_segment;
  if (certificate)
    certify_segment = [&](const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
      certificate->add_segment(seg, nodes);
    };
  const reference_run run = integrate_streaming<T>(
      to_problem<T>(job.scn), tau_end, times.tau, job.settings, "reference",
      [&](std::size_t i, const vec3<T>& Om) {
        rows(i, Om);
        if (kept) kept->push_back(Om);
      },
      certify_segment);
  rows.flush();
  return run;
}

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
  m.scene_text = job.scn.source_text;
  return m;
}

decimal decimal_of(const std::string& text) { return decimal{text, std::strtod(text.c_str(), nullptr)}; }

// --certify's lines: the largest radius (and that of omega for a physical scene) and the method.
void add_certificate(const reference_job& job, const run_certificate& certificate, reference_metadata& m) {
  m.certified_max_error = decimal_of(certificate.max_radius());
  m.certify_method = certificate.method();
  if (job.layout == reference_layout::physical)
    m.certified_max_error_omega = decimal_of(certificate.max_radius_omega());
}

// Runs the job in T, streaming the CSV rows to `rows_out`.
template <scalar T>
reference_metadata run_in(const reference_job& job, scratch_file& rows_out) {
  const T tau_end = tau_end_of<T>(job.scn);
  const sample_times<T> times = sample_times_of<T>(job.scn);
  // --verify compares the samples with a wider run's, so it keeps them: memory then grows with
  // the number of samples (never with the span). Without it nothing is kept.
  std::vector<vec3<T>> kept;
  std::optional<run_certificate> certificate;
  if (job.certify) certificate.emplace(job.scn, job.precision);
  const reference_run run = stream_rows<T>(job, tau_end, times, rows_out, job.verify ? &kept : nullptr,
                                           certificate ? &*certificate : nullptr);
  reference_metadata m = metadata_of(job, run);
  if (certificate) add_certificate(job, *certificate, m);
  if (job.verify) {
    const verify_result check = verify<T>(job.scn, tau_end, times.tau, kept, job.precision);
    m.estimated_max_error = check.max_error;
    m.verify_precision = check.precision;
    m.verify_method = check.method;
    if (!job.omit_timing) m.wall_seconds_verify = check.wall_seconds;
  }
  return m;
}

}  // namespace

reference_metadata run_reference_job(const reference_job& job, scratch_file& rows_out) {
  return with_scalar(job.precision, [&](auto zero) { return run_in<decltype(zero)>(job, rows_out); });
}

}  // namespace eulervop::app
