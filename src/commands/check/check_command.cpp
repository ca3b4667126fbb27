#include "commands/check/check_command.hpp"

#include "cli/command_flags.hpp"
#include "commands/check/against_file.hpp"
#include "commands/check/against_scene.hpp"
#include "commands/check/check_job.hpp"
#include "commands/check/check_output.hpp"
#include "compute/scene_time.hpp"

namespace eulervop::app {

void add_check_flags(CLI::App& sub, check_options& o) {
  add_required_positional(
      sub, {"reference", "SCENE_OR_REFERENCE", "A scene (.toml), or a reference CSV written by `eulervop reference`"},
      o.reference);
  add_required_positional(sub,
                          {"trajectory", "TRAJECTORY",
                           "The trajectory: CSV with header tau,Omega1,Omega2,Omega3 (or t,omega1..3), and q0..q3 for "
                           "an attitude"},
                          o.trajectory);
  add_text_flag(sub,
                {"--columns", "MAP", "Column names of the file: tau=time,Omega1=w1,... (default: the canonical names)"},
                o.columns);
  add_text_flag(sub, {"--precision", "P", "Scene only: double, quad or mpfr:BITS (default: the scene's [reference])"},
                o.precision);
  add_text_flag(sub,
                {"--tol", "ABS",
                 "Pass if every row's error (two-norm of the rates, in the trajectory's units: rad/s for "
                 "t,omega1..3) <= ABS (+ R |ref| with --rel-tol)"},
                o.tol);
  add_text_flag(sub, {"--rel-tol", "R", "Pass if every row's error <= R |ref|, the reference rates' norm (+ ABS with --tol)"},
                o.rel_tol);
  add_text_flag(sub,
                {"--attitude-tol", "RAD",
                 "Pass if every row's attitude error (the angle to the reference's q) <= RAD; required with "
                 "--tol or --rel-tol when the trajectory has q0..q3"},
                o.attitude_tol);
  add_switch(sub, {"--ignore-attitude", "", "Judge the rates alone though the trajectory has q0..q3 (the result says so)"},
             o.ignore_attitude);
  add_text_flag(sub, {"--errors-out", "FILE", "Write the per-row errors to FILE (CSV: line,time,error,bar[,attitude_error])"},
                o.errors_out);
  add_text_flag(sub, {"--format", "F", "Standard output: table (default) or json"}, o.format);
  add_text_flag(
      sub, {"--scd-atol", "A", "atol of the mixed error |dy| / (atol/rtol + |y_ref|) behind mescd (default 1e-12)"},
      o.scd_atol);
  add_text_flag(sub, {"--scd-rtol", "R", "rtol of that mixed error (default 1e-12)"}, o.scd_rtol);
}

int run_check(const check_options& options, std::ostream& standard_output) {
  const check_job job = check_job_of(options);
  const check_result result =
      job.from_scene ? in_scene_time(job.scn, [&] { return check_against_scene(job); }) : check_against_file(job);
  return print_check(job, result, standard_output);
}

}  // namespace eulervop::app
