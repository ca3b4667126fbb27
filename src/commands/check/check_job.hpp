// What a `check` compares, from its flags: the trajectory, the reference (a scene, with the
// precision to integrate it in, or a reference file), the trajectory's column names, the bars
// and the outputs. Every flag is validated here, before any computation.
#pragma once

#include "cli/flags.hpp"
#include "commands/check/check_command.hpp"
#include "compute/scene_library.hpp"
#include "io/table_rows.hpp"

#include <eulervop/core/precision.hpp>
#include <eulervop/reference/settings.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace eulervop::app {

class held_reference;

struct check_job {
  // The trajectory's rows, read twice (once to validate them and find the last time, once as
  // the integration reaches them), and how the outputs name it: a CSV file and its path, or
  // arrays in memory (the Python module's).
  std::function<std::unique_ptr<table_rows>()> open_trajectory;
  std::string trajectory_name;
  std::string reference_path;     // a file's path, or how a reference held in memory is named
  std::shared_ptr<const held_reference> held;  // a reference held in memory, instead of a file
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

// A scene (.toml, or a shipped scene's name) or a reference CSV? By the extension, else by the
// file's first non-blank line.
bool names_scene(const std::string& path);

// Every flag validated; the reference a file (scene or reference CSV), the trajectory a CSV file.
check_job check_job_of(const check_options& options);

// The flags that do not name a file (bars, columns, format, --errors-out), validated.
void apply_check_flags(check_job& job, const check_options& options);

// Against a scene: its reference integrated in --precision (a flag's text), else the scene's.
void check_against(check_job& job, scene s, const std::optional<std::string>& precision);

}  // namespace eulervop::app
