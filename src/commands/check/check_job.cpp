#include "commands/check/check_job.hpp"

#include "cli/scene_overrides.hpp"
#include "io/csv_rows.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

namespace eulervop::app {

bool names_scene(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".toml") return true;
  if (ext == ".csv") return false;
  // No such file, and a bare name: a shipped scene's (load_scene_file says so if it is none).
  const std::filesystem::path p(path);
  std::error_code ec;
  if (!std::filesystem::exists(p, ec) && !p.has_parent_path() && !p.has_extension()) return true;
  std::ifstream in = open_input_file("reference", path);
  for (std::string l; std::getline(in, l);) {
    const std::string t = trimmed(l);
    if (t.empty()) continue;
    return !(t.starts_with("#") || t.find(',') != std::string::npos);
  }
  return true;
}

void apply_check_flags(check_job& job, const check_options& o) {
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
}

void check_against(check_job& job, scene s, const std::optional<std::string>& precision) {
  job.from_scene = true;
  job.scn = std::move(s);
  scene_override_flags flags;
  flags.precision = precision;
  const applied_overrides applied = apply_scene_overrides(job.scn, flags);
  job.precision = applied.precision;
  job.settings = applied.settings;
}

check_job check_job_of(const check_options& o) {
  check_job job;
  const std::string path = o.trajectory;
  job.open_trajectory = [path] { return std::make_unique<csv_file_rows>("trajectory", path); };
  job.trajectory_name = path;
  job.reference_path = o.reference;
  apply_check_flags(job, o);
  if (names_scene(o.reference)) {
    check_against(job, load_scene(o.reference), o.precision);
  } else if (o.precision) {
    throw input_error(fmt::format("--precision {}: not used with a reference file (its own precision is used)",
                                  *o.precision));
  }
  open_input_file("trajectory", o.trajectory);  // unreadable: bad input before any work
  return job;
}

}  // namespace eulervop::app
