#include "reference_command.hpp"

#include "atomic_file.hpp"
#include "decimal.hpp"
#include "input_error.hpp"
#include "reference_compute.hpp"
#include "scene.hpp"
#include "scene_overrides.hpp"
#include "scene_problem.hpp"

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

// The whole CSV (issue 2, section 6) of a run in T.
template <scalar T>
std::string run_in(const reference_job& job) {
  const scene& s = job.scn;
  const normalized_problem<T> problem = to_problem<T>(s);
  const T tau_end = tau_end_of<T>(s);
  const sample_times<T> times = sample_times_of<T>(s);
  const sampled_reference<T> ref = integrate_and_sample<T>(problem, tau_end, times.tau, job.settings, "reference");

  std::optional<verify_result> check;
  if (job.verify) check = verify<T>(s, tau_end, times.tau, ref.Omega, job.precision);

  fmt::memory_buffer out;
  auto line = [&]<class... Args>(fmt::format_string<Args...> format, Args&&... args) {
    fmt::format_to(std::back_inserter(out), format, std::forward<Args>(args)...);
    out.push_back('\n');
  };
  line("# eulervop {}", EULERVOP_VERSION);
  line("# scene: {}", s.name);
  line("# scene_source: {}", s.origin);
  if (!job.command.empty()) line("# command: {}", job.command);
  if (!job.overrides.empty()) line("# overrides: {}", job.overrides);
  line("# precision: {}", precision_text(job.precision));
  line("# method: {}", method_text(job.settings, ref.stats));
  if (!job.omit_timing) line("# wall_seconds: {:.3f}", ref.wall_seconds);
  if (check) {
    line("# estimated_max_error: {}", check->max_error);
    line("# verify_precision: {}", check->precision);
    line("# verify_method: {}", check->method);
    if (!job.omit_timing) line("# wall_seconds_verify: {:.3f}", check->wall_seconds);
  }
  std::istringstream scene_lines(s.source_text);
  for (std::string l; std::getline(scene_lines, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    line("# scene_text: {}", l);
  }

  if (s.is_physical()) {
    line("tau,Omega1,Omega2,Omega3,t,omega1,omega2,omega3");
    const physical_scaling<T> scale = scaling_of<T>(s);
    for (std::size_t i = 0; i < times.tau.size(); ++i) {
      const vec3<T>& Om = ref.Omega[i];
      const vec3<T> om = scale.omega_of_Omega(Om);
      line("{},{},{},{},{},{},{},{}", to_text(times.tau[i]), to_text(Om[0]), to_text(Om[1]), to_text(Om[2]),
           to_text(times.t[i]), to_text(om[0]), to_text(om[1]), to_text(om[2]));
    }
  } else {
    line("tau,Omega1,Omega2,Omega3");
    for (std::size_t i = 0; i < times.tau.size(); ++i) {
      const vec3<T>& Om = ref.Omega[i];
      line("{},{},{},{}", to_text(times.tau[i]), to_text(Om[0]), to_text(Om[1]), to_text(Om[2]));
    }
  }
  return fmt::to_string(out);
}

std::string run_job(const reference_job& job) {
  switch (job.precision.type) {
    case eulervop::precision::kind::binary64: return run_in<double>(job);
    case eulervop::precision::kind::binary128: return run_in<quad>(job);
    case eulervop::precision::kind::mpfr: {
      // Every MPFR value of the run is created (and destroyed) inside this scope.
      const mpfr_precision_scope scope(job.precision.bits);
      return run_in<mpfr_real>(job);
    }
  }
  throw std::logic_error("unknown precision kind");
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

std::string shell_word(const std::string& a) {
  const bool plain = !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                       "0123456789-_./:=,+@%") == std::string::npos;
  if (plain) return a;
  std::string q = "'";
  for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
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
