#include "commands/report/report_command.hpp"

#include "compute/scene_time.hpp"
#include "cli/command_flags.hpp"
#include "cli/exit_codes.hpp"
#include "cli/flags.hpp"
#include "cli/scene_overrides.hpp"
#include "commands/report/adaptive_report.hpp"
#include "commands/report/fixed_step_report.hpp"
#include "commands/report/report_job.hpp"
#include "compute/formulation_probe.hpp"
#include "io/output_dir.hpp"
#include "io/reference_csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <utility>

namespace eulervop::app {

namespace {

constexpr std::int64_t default_K_divisor = 200;
constexpr std::int64_t default_samples = 2000;
// The methods without --methods or [run] methods: rk4 and rkf45 at a fixed step; under error
// control (--tols, which leaves [run] methods aside) the paper's Fehlberg pair and DOP853.
const std::vector<rk::method> default_fixed_methods = {rk::method::rk4, rk::method::rkf45};
const std::vector<rk::method> default_adaptive_methods = {rk::method::rkf45, rk::method::dop853};

// With --reference, the file's samples and precision are used: flags that would set them are bad input.
void check_reference_flags(const report_options& o) {
  if (!o.reference_file) return;
  for (const auto& [flag, given] : {std::pair{"--samples", o.overrides.samples.has_value()},
                                    std::pair{"--precision", o.overrides.precision.has_value()},
                                    std::pair{"--degree", o.overrides.degree.has_value()},
                                    std::pair{"--tolerance", o.overrides.tolerance.has_value()},
                                    std::pair{"--verify", o.verify}})
    if (given)
      throw input_error(fmt::format("{}: not used with --reference {} (the file's samples and precision are used)",
                                    flag, *o.reference_file));
}

// A report runs either at one fixed step or under error control (--tols), each with its own flags.
void check_mode_flags(const report_options& o) {
  if (!o.tols) {
    if (o.max_step) throw input_error(fmt::format("--max-step {}: only for the adaptive runs of --tols", *o.max_step));
    return;
  }
  if (o.step)
    throw input_error(fmt::format("--tols {} and --step {}: a report runs either at one fixed step or under error "
                                  "control; give one of them",
                                  *o.tols, *o.step));
  for (const auto& [flag, given] :
       {std::pair{"--reference", o.reference_file.has_value()}, std::pair{"--verify", o.verify}})
    if (given)
      throw input_error(fmt::format("{}: not used with --tols (the adaptive runs are measured at their own step points "
                                    "against the reference computed here)",
                                    flag));
}

// Error samples are step points of the runs, about `samples` of them: the scene's explicit
// sample times do not apply.
void use_error_samples(scene& s) {
  if (!s.samples) s.samples = s.times.empty() ? default_samples : std::max<std::int64_t>(2, std::ssize(s.times));
  s.times.clear();
}

// A body in the direct form runs euler alone (the paper's VOP does not apply), which the table and
// the summary note, with the names its outputs give t and the state; empty otherwise.
std::string direct_form_note(const scene& s) {
  const std::string why = euler_only_reason(s);
  if (why.empty()) return "";
  if (s.is_coefficient_form()) return why + ", so only euler runs: tau is t and Omega is y";
  return why + ", so only euler runs, on Eq. 1 itself: tau is t in s and Omega is omega in rad/s";
}

report_job make_job(const report_options& o) {
  report_job job;
  job.scn = load_scene(o.scene_path);
  scene& s = job.scn;
  use_error_samples(s);
  check_reference_flags(o);
  const applied_overrides applied = apply_scene_overrides(s, o.overrides);
  job.overrides = applied.text();
  job.precision = applied.precision;
  job.settings = applied.settings;
  job.verify = o.verify;
  job.samples = static_cast<std::size_t>(*s.samples);

  check_mode_flags(o);
  if (o.tols) {
    job.tols = tol_ladder("--tols", *o.tols);
    job.max_step = max_step_of(s, o.max_step);
  } else {
    job.step = fixed_step_of(s, o.step, default_K_divisor);
  }
  const bool adaptive = job.adaptive();
  job.note = direct_form_note(s);
  const std::vector<formulation> forms = chosen_formulations(
      o.formulations, s.formulations, formulations_for(s, {formulation::euler, formulation::vop}));
  require_formulations_apply(forms, s, o.formulations ? "--formulations " + *o.formulations : "[run] formulations");
  const std::vector<rk::method> methods =
      chosen_methods(o.methods, adaptive ? std::vector<std::string>{} : s.methods,
                     adaptive ? default_adaptive_methods : default_fixed_methods, !adaptive, adaptive);
  for (formulation f : forms)  // formulations x methods (x tolerances)
    for (rk::method m : methods) {
      if (!adaptive) job.runs.push_back({f, m});
      for (std::size_t t = 0; t < job.tols.size(); ++t) job.runs.push_back({f, m, t});
    }
  probe_formulations(forms, s,
                     adaptive ? std::min(job.max_step.h, tau_end_of<double>(s)) : job.step.h);

  if (o.reference_file) {
    const reference_metadata meta = read_reference_metadata("--reference", *o.reference_file);
    if (!meta.scene_name.empty() && meta.scene_name != s.name)
      throw input_error(fmt::format("--reference {}: the reference is for scene `{}`, the report is for scene `{}`",
                                    *o.reference_file, meta.scene_name, s.name));
    job.file = reference_file_info{*o.reference_file, meta};
  }
  // The attitude beside the rates (docs/attitude-runs.md): a scene with [initial] q; with
  // --reference, only when the file has the attitude too.
  job.attitude = s.has_attitude() && (!job.file || !job.file->meta.attitude.empty());
  if (s.couples_attitude() && !job.attitude)
    throw input_error(fmt::format("--reference {}: the file has no attitude (q0..q3), and the torque of scene `{}` "
                                  "reads it, so the runs carry q and are measured against it",
                                  *o.reference_file, s.name));
  job.out_dir = out_dir_of(o.out_dir, "report");
  job.json = flag_json_format(o.format);
  job.plot = !o.no_plot;
  return job;
}

}  // namespace

void add_report_flags(CLI::App& sub, report_options& o) {
  add_text_flag(sub, {"scene", "SCENE", "Scene file (TOML); default: the embedded paper scene"}, o.scene_path);
  add_text_flag(sub, {"--reference", "FILE", "Reference CSV written by `eulervop reference` (default: computed here)"},
                o.reference_file);
  add_text_flag(sub,
                {"--step", "S", "Fixed step: K/N (K of the initial modulus) or h (default: [run] step, else K/200)"},
                o.step);
  add_text_flag(
      sub, {"--tols", "LIST", "Instead of a fixed step: comma-separated tolerances (atol = rtol) of adaptive runs"},
      o.tols);
  add_text_flag(sub, {"--max-step", "S", "Largest step of the adaptive runs: K/N or h (default: K/2)"}, o.max_step);
  add_text_flag(sub,
                {"--methods", "LIST",
                 "Comma-separated: rk4,rkf45,dp45,rk8; with --tols rkf45,dp45,dop853 (default: [run] methods, else "
                 "rk4,rkf45; with --tols rkf45,dop853)"},
                o.methods);
  add_text_flag(sub,
                {"--formulations", "LIST", "Comma-separated, of euler, vop, vop-theta (default: [run] formulations, else euler,vop)"},
                o.formulations);
  scene_override_set which;
  which.times = false;
  add_scene_override_flags(sub, o.overrides, which, "About this many error samples, at the runs' step points");
  add_output_flags(sub, o.out_dir, o.no_plot, "report", "fig1");
  add_text_flag(sub, {"--format", "F", "Standard output: table (default) or json (summary.json)"}, o.format);
  add_switch(sub, {"--verify", "", "Recompute the reference one precision up for its estimated_max_error"}, o.verify);
}

int run_report(const report_options& options, std::ostream& standard_output) {
  const report_job job = make_job(options);
  in_scene_time(job.scn, [&] {
    if (job.adaptive())
      run_adaptive_report(job, standard_output);
    else
      run_fixed_step_report(job, standard_output);
  });
  return exit_success;
}

}  // namespace eulervop::app
