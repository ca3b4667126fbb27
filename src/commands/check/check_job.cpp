#include "commands/check/check_job.hpp"

#include "cli/scene_overrides.hpp"
#include "io/csv_rows.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

namespace eulervop::app {

namespace {

// A scene (.toml) or a reference CSV? By extension, else by the first non-blank line.
bool looks_like_scene(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".toml") return true;
  if (ext == ".csv") return false;
  std::ifstream in = open_input_file("reference", path);
  for (std::string l; std::getline(in, l);) {
    const std::string t = trimmed(l);
    if (t.empty()) continue;
    return !(t.starts_with("#") || t.find(',') != std::string::npos);
  }
  return true;
}

}  // namespace

check_job check_job_of(const check_options& o) {
  check_job job;
  job.trajectory_path = o.trajectory;
  job.reference_path = o.reference;
  job.columns = flag_columns(o.columns);
  job.tol = non_negative_flag("--tol", o.tol);
  job.rel_tol = non_negative_flag("--rel-tol", o.rel_tol);
  job.attitude_tol = non_negative_flag("--attitude-tol", o.attitude_tol);
  job.ignore_attitude = o.ignore_attitude;
  if (job.attitude_tol && job.ignore_attitude)
    throw input_error(fmt::format("--ignore-attitude: given with --attitude-tol {} (give one of them)", *o.attitude_tol));
  if (job.attitude_tol && !job.tol && !job.rel_tol)
    throw input_error(fmt::format("--attitude-tol {}: give --tol or --rel-tol too (the rates are judged with the "
                                  "attitude; a verdict on the attitude alone would pass any rates)",
                                  *o.attitude_tol));
  if (o.scd_atol) job.scd_atol = positive_flag_number("--scd-atol", *o.scd_atol).value;
  if (o.scd_rtol) job.scd_rtol = positive_flag_number("--scd-rtol", *o.scd_rtol).value;
  job.json = flag_json_format(o.format);
  if (o.errors_out && o.errors_out->empty()) throw input_error("--errors-out: empty path");
  job.errors_out = o.errors_out;

  job.from_scene = looks_like_scene(o.reference);
  if (job.from_scene) {
    job.scn = load_scene(o.reference);
    scene_override_flags flags;
    flags.precision = o.precision;
    const applied_overrides applied = apply_scene_overrides(job.scn, flags);
    job.precision = applied.precision;
    job.settings = applied.settings;
  } else if (o.precision) {
    throw input_error(fmt::format("--precision {}: not used with a reference file (its own precision is used)",
                                  *o.precision));
  }
  open_input_file("trajectory", o.trajectory);  // unreadable: bad input before any work
  return job;
}

}  // namespace eulervop::app
