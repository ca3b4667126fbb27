#include "commands/reference_command.hpp"

#include "io/atomic_file.hpp"
#include "compute/certified_reference.hpp"
#include "compute/reference_compute.hpp"
#include "io/reference_csv.hpp"
#include "io/scratch_file.hpp"
#include "compute/scene_library.hpp"
#include "compute/scene_overrides.hpp"
#include "io/shell_word.hpp"
#include "compute/with_scalar.hpp"

#include <eulervop/reference/integrate.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/integrals.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/core/scalar.hpp>

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string_view>
#include <system_error>
#include <vector>

namespace eulervop::app {

namespace {

// ---- flags -> an effective scene and settings ------------------------------------------------

// Everything a run needs, validated.
struct reference_job {
  scene scn;                         // the scene with --tau-end/--t-end/--samples/--times applied
  eulervop::precision precision;     // --precision, else [reference] precision
  picard_settings settings;          // --degree/--tolerance, else [reference], else automatic
  bool verify = false;
  bool certify = false;
  bool omit_timing = false;          // no "# wall_seconds" lines
  std::string command;               // the "# command:" line, if any
  std::string overrides;             // the flags that changed the scene, for the metadata
};

reference_job make_job(const reference_options& o) {
  reference_job job;
  job.scn = o.scene_path ? load_scene_file(*o.scene_path) : load_default_scene();
  const applied_overrides applied = apply_scene_overrides(job.scn, o.overrides);
  job.precision = applied.precision;
  job.settings = applied.settings;
  job.verify = o.verify;
  job.certify = o.certify;
  if (job.certify) require_certifiable(job.scn, job.precision);
  job.omit_timing = o.omit_timing;
  job.command = o.command;
  job.overrides = applied.text();
  return job;
}

// ---- computing -------------------------------------------------------------------------------

// Integrates the job's scene in T and writes a CSV row to `rows_out` as each sample is
// evaluated. `kept`, if given, receives the samples too.
// With --certify, `certificate` checks every segment and each row gets its radius.
template <scalar T>
reference_run stream_rows(const reference_job& job, const T& tau_end, const sample_times<T>& times,
                          scratch_file& rows_out, std::vector<vec3<T>>* kept, run_certificate* certificate) {
  const scene& s = job.scn;
  std::optional<physical_scaling<T>> scale;
  if (s.is_physical()) scale.emplace(scaling_of<T>(s));
  reference_csv_row_writer rows([&](std::string_view chunk) { rows_out.write(chunk); });
  segment_sink<T> certify_segment;
  if (certificate)
    certify_segment = [&](const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
      certificate->add_segment(seg, nodes);
    };
  const reference_run run = integrate_streaming<T>(
      to_problem<T>(s), tau_end, times.tau, job.settings, "reference", [&](std::size_t i, const vec3<T>& Om) {
        if (certificate && scale) {
          const vec3<T> om = scale->omega_of_Omega(Om);
          const std::array<std::string, 3> Omega_cells = {to_text(Om[0]), to_text(Om[1]), to_text(Om[2])};
          const std::array<std::string, 3> omega_cells = {to_text(om[0]), to_text(om[1]), to_text(om[2])};
          rows.certified_row(times.tau[i], Omega_cells, times.t[i], omega_cells,
                             certificate->physical_radii(times.tau[i], times.t[i], Omega_cells, omega_cells));
        } else if (certificate) {
          const std::array<std::string, 3> cells = {to_text(Om[0]), to_text(Om[1]), to_text(Om[2])};
          rows.certified_row(times.tau[i], cells, certificate->radius(times.tau[i], cells));
        } else if (scale && scale->is_direct())
          rows.row(times.t[i], Om);  // the state is omega, and tau is t
        else if (scale)
          rows.row(times.tau[i], Om, times.t[i], scale->omega_of_Omega(Om));
        else
          rows.row(times.tau[i], Om);
        if (kept) kept->push_back(Om);
      },
      certify_segment);
  rows.flush();
  return run;
}

// The metadata block of a finished run (without --verify's lines).
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

// Runs the job in T, streaming the CSV rows to `rows_out`, and returns the metadata of the
// finished run (layout in the README, "Command line").
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
  if (certificate) {
    const std::string worst = certificate->max_radius();
    m.certified_max_error = decimal{worst, std::strtod(worst.c_str(), nullptr)};
    m.certify_method = certificate->method();
    if (job.scn.is_physical()) {
      const std::string worst_omega = certificate->max_radius_omega();
      m.certified_max_error_omega = decimal{worst_omega, std::strtod(worst_omega.c_str(), nullptr)};
    }
  }
  if (job.verify) {
    const verify_result check = verify<T>(job.scn, tau_end, times.tau, kept, job.precision);
    m.estimated_max_error = check.max_error;
    m.verify_precision = check.precision;
    m.verify_method = check.method;
    if (!job.omit_timing) m.wall_seconds_verify = check.wall_seconds;
  }
  return m;
}

reference_metadata run_job(const reference_job& job, scratch_file& rows_out) {
  return with_scalar(job.precision, [&](auto zero) { return run_in<decltype(zero)>(job, rows_out); });
}

// The rows wait beside the output file (its file system holds them in the end anyway); for
// standard output or a device, in the temporary directory (TMPDIR).
std::filesystem::path scratch_directory(const atomic_file* file) {
  if (file && file->replaces_target()) {
    const std::filesystem::path dir = file->target().parent_path();
    return dir.empty() ? std::filesystem::path(".") : dir;
  }
  std::error_code ec;
  std::filesystem::path tmp = std::filesystem::temp_directory_path(ec);
  if (ec) {
    const char* value = std::getenv("TMPDIR");
    throw input_error(fmt::format("TMPDIR {}: not a usable directory for the rows of standard output: {}",
                                  value ? value : "(unset)", ec.message()));
  }
  return tmp;
}

}  // namespace

CLI::App* add_reference_command(CLI::App& app, reference_options& o) {
  CLI::App* sub = app.add_subcommand("reference", "Compute the high-precision reference solution as CSV");
  sub->add_option_function<std::string>(
         "scene", [&o](const std::string& v) { o.scene_path = v; },
         "Scene file (TOML); default: the embedded paper scene")
      ->type_name("SCENE");
  add_scene_override_options(*sub, o.overrides, scene_override_set{},
                             "Number of equally spaced samples, endpoints included");
  sub->add_option_function<std::string>(
         "--out", [&o](const std::string& v) { o.out = v; }, "Output file (default: standard output)")
      ->type_name("FILE");
  sub->add_flag("--verify", o.verify, "Recompute one precision up and report # estimated_max_error");
  sub->add_flag("--certify", o.certify,
                "Prove a bound on every row's distance to the exact solution: a radius column and "
                "# certified_max_error (docs/certified.md)");
  return sub;
}

void run_reference(const reference_options& options, std::ostream& standard_output) {
  const reference_job job = make_job(options);
  // Open the output first, so an unwritable path fails before any computation.
  std::unique_ptr<atomic_file> file;
  if (options.out) file = std::make_unique<atomic_file>(*options.out);
  // The header states the finished run (segments, wall time, --verify's estimate) but comes
  // first: the rows are streamed to a scratch file during the run, then copied after it.
  scratch_file rows(scratch_directory(file.get()));
  const reference_layout layout = uses_direct_form(job.scn) ? reference_layout::direct
                                  : job.scn.is_physical()     ? reference_layout::physical
                                                              : reference_layout::normalized;
  const std::string header = reference_csv_header(run_job(job, rows), layout);
  if (file) {
    file->write(header);
    rows.copy_to([&](std::string_view chunk) { file->write(chunk); });
    file->commit();
  } else {
    standard_output << header;
    rows.copy_to([&](std::string_view chunk) { standard_output.write(chunk.data(), std::ssize(chunk)); });
    standard_output << std::flush;
  }
}

std::string command_text(int argc, const char* const* argv) {
  std::string text = "eulervop";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out") {
      ++i;  // and its value
      continue;
    }
    if (a.starts_with("--out=")) continue;
    text += " " + shell_word(a);
  }
  return text;
}

}  // namespace eulervop::app
