// `eulervop check SCENE_OR_REFERENCE TRAJECTORY.csv [options]`: how far another tool's
// trajectory is from the reference.
//
// The trajectory is a CSV with a header; its columns are found by name (tau, Omega1..3, or
// t, omega1..3 for a physical scene; --columns renames). Against a scene (.toml) the reference
// is integrated to the trajectory's last time and evaluated by dense output at every row's
// time (against_scene.hpp); against a reference CSV of `eulervop reference` every row's time
// must be one of the file's sample times, to 1e-12 relative (against_file.hpp). Both files are
// streamed, never held in memory. Besides the Eq. 20 errors it reports the oracle metrics of the
// IVP Test Set (scd, mescd), the largest error per component, the drift of c1^2 and c2^2 (Eq. 7)
// against the reference's, and the error along and across the reference's direction of motion
// (check_tally.hpp). A trajectory with columns q0..q3 (an attitude) gets each row's rotation
// angle to the reference's attitude too; the reference must then have one. A first row at time 0
// that is not the scene's initial state is named, with the quaternion convention it looks written
// in (scalar last, the inverse) when a reordering of its q matches; figures that mean nothing for
// the scene (Eq. 7 under a torque) are left out, and every figure carries its unit
// (scene_terms.hpp, check_output.hpp).
//
// The errors are in the trajectory's own variables (compared_variables.hpp): for t,omega1..3 of a
// physical scene, in rad/s on the body's axes as the scene lists them, --tol included; the Eq. 20
// error in the normalized variables is reported beside them.
//
// Every quantity the trajectory holds is judged: with q0..q3, a bar on the rates needs
// --attitude-tol (or --ignore-attitude, said in the result line), and --attitude-tol needs a bar on
// the rates. Without any bar there is no verdict (exit 0, JSON "pass": null).
//
// Exit codes: 0 within tolerance (or no tolerance given), 1 outside it (--tol, --rel-tol or
// --attitude-tol), 2 bad input (one line naming the file, the line and the column, or the flag
// missing), 3 numerical failure of the reference.
#pragma once

#include "cli/cli11_fwd.hpp"

#include <optional>
#include <ostream>
#include <string>

namespace eulervop::app {

struct check_options {
  std::string reference;                  // a scene (.toml) or a reference CSV
  std::string trajectory;                 // the CSV to check
  std::optional<std::string> columns;     // "tau=time,Omega1=w1,..."
  std::optional<std::string> precision;   // scene only: double | quad | mpfr:BITS
  std::optional<std::string> tol;         // absolute bar on the Eq. 20 error
  std::optional<std::string> rel_tol;     // bar relative to |Omega_ref|
  std::optional<std::string> attitude_tol;  // bar on the attitude error (radians)
  bool ignore_attitude = false;           // judge the rates alone, though the trajectory has q0..q3
  std::optional<std::string> errors_out;  // per-row errors, CSV (written atomically)
  std::optional<std::string> format;      // table | json
  std::optional<std::string> scd_atol;    // mixed error's atol (mescd), default 1e-12
  std::optional<std::string> scd_rtol;    // mixed error's rtol (mescd), default 1e-12
};

// Registers the command's flags on `sub`, bound to `options`.
void add_check_flags(CLI::App& sub, check_options& options);

// Runs the check and returns the exit code (0 within tolerance, 1 outside). Throws input_error
// for bad input and eulervop::numerical_failure when the reference integrator gives up.
int run_check(const check_options& options, std::ostream& standard_output);

}  // namespace eulervop::app
