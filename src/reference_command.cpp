#include "reference_command.hpp"

#include "atomic_file.hpp"
#include "reference_compute.hpp"
#include "reference_csv.hpp"
#include "scene_library.hpp"
#include "scene_overrides.hpp"
#include "shell_word.hpp"
#include "with_scalar.hpp"

#include <eulervop/chebyshev_picard.hpp>
#include <eulervop/model.hpp>
#include <eulervop/scalar.hpp>

#include <fmt/format.h>

#include <memory>
#include <sstream>
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
  job.omit_timing = o.omit_timing;
  job.command = o.command;
  job.overrides = applied.text();
  return job;
}

// ---- computing -------------------------------------------------------------------------------

// The whole CSV of a run in T (layout in the README, "Command line").
template <scalar T>
std::string run_in(const reference_job& job) {
  const scene& s = job.scn;
  const normalized_problem<T> problem = to_problem<T>(s);
  const T tau_end = tau_end_of<T>(s);
  const sample_times<T> times = sample_times_of<T>(s);
  const sampled_reference<T> ref = integrate_and_sample<T>(problem, tau_end, times.tau, job.settings, "reference");

  reference_metadata m;
  m.scene_name = s.name;
  m.scene_source = s.origin;
  m.command = job.command;
  m.overrides = job.overrides;
  m.precision = job.precision;
  m.method = method_text(job.settings, ref.stats);
  if (!job.omit_timing) m.wall_seconds = ref.wall_seconds;
  if (job.verify) {
    const verify_result check = verify<T>(s, tau_end, times.tau, ref.Omega, job.precision);
    m.estimated_max_error = check.max_error;
    m.verify_precision = check.precision;
    m.verify_method = check.method;
    if (!job.omit_timing) m.wall_seconds_verify = check.wall_seconds;
  }
  m.scene_text = s.source_text;

  reference_csv_writer out(m, s.is_physical());
  if (s.is_physical()) {
    const physical_scaling<T> scale = scaling_of<T>(s);
    for (std::size_t i = 0; i < times.tau.size(); ++i)
      out.row(times.tau[i], ref.Omega[i], times.t[i], scale.omega_of_Omega(ref.Omega[i]));
  } else {
    for (std::size_t i = 0; i < times.tau.size(); ++i) out.row(times.tau[i], ref.Omega[i]);
  }
  return out.text();
}

std::string run_job(const reference_job& job) {
  return with_scalar(job.precision, [&](auto zero) { return run_in<decltype(zero)>(job); });
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
  return sub;
}

void run_reference(const reference_options& options, std::ostream& standard_output) {
  const reference_job job = make_job(options);
  // Open the output first, so an unwritable path fails before any computation.
  std::unique_ptr<atomic_file> file;
  if (options.out) file = std::make_unique<atomic_file>(*options.out);
  const std::string csv = run_job(job);
  if (file) {
    file->write(csv);
    file->commit();
  } else {
    standard_output << csv << std::flush;
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
