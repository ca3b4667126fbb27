// What a `check` compares, from its flags: the trajectory, the reference (a scene, with the
// precision to integrate it in, or a reference file), the trajectory's column names, the bars
// and the outputs. Every flag is validated here, before any computation.
#pragma once

#include "cli/flags.hpp"
#include "commands/check/check_command.hpp"
#include "compute/scene_library.hpp"

#include <eulervop/core/precision.hpp>
#include <eulervop/reference/settings.hpp>

#include <optional>
#include <string>

namespace eulervop::app {

struct check_job {
  std::string trajectory_path;
  std::string reference_path;
  bool from_scene = false;
  scene scn;                      // from_scene
  eulervop::precision precision;  // from_scene: --precision, else the scene's
  picard_settings settings;
  column_names columns;           // the trajectory's column for each canonical name (--columns)
  std::optional<double> tol, rel_tol;
  std::optional<double> attitude_tol;  // radians: the bar on each row's attitude error
  bool ignore_attitude = false;        // --ignore-attitude
  double scd_atol = 1e-12, scd_rtol = 1e-12;  // the mixed error of mescd
  std::optional<std::string> errors_out;
  bool json = false;
};

check_job check_job_of(const check_options& options);

}  // namespace eulervop::app
