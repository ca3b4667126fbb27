// What a `report` computes, as report_command.cpp makes it from the flags (all validated before
// any computation): the scene, the runs (formulations x methods, at one fixed step or x the
// tolerances of --tols), the reference (computed here or read from --reference) and where the
// outputs go.
#pragma once

#include "compute/ladders.hpp"
#include "compute/scene_library.hpp"
#include "compute/step_rule.hpp"
#include "io/reference_csv.hpp"

#include <eulervop/core/precision.hpp>
#include <eulervop/reference/settings.hpp>
#include <eulervop/rk/tableaux.hpp>
#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <fmt/format.h>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace eulervop::app {

// One run of the report: a formulation and a method, adaptive with one of the tolerances.
struct run_spec {
  formulation form;
  rk::method method;
  std::optional<std::size_t> tol;  // adaptive: index into the job's tolerances
  // "euler_rk4": the run's column of errors.csv.
  std::string column() const { return fmt::format("{}_{}", formulation_name(form), rk::method_name(method)); }
};

// A --reference file and its metadata, read before the computation's scalar type is chosen.
struct reference_file_info {
  std::string path;
  reference_metadata meta;
};

struct report_job {
  scene scn;
  std::string overrides;
  fixed_step_choice step;        // the fixed step (without --tols)
  std::vector<ladder_tol> tols;  // adaptive runs (--tols) instead of the fixed step
  max_step_choice max_step;      // their largest step
  std::vector<run_spec> runs;
  std::size_t samples = 0;
  eulervop::precision precision;  // of a computed reference
  picard_settings settings;
  bool verify = false;
  std::optional<reference_file_info> file;
  std::filesystem::path out_dir;
  bool json = false;
  bool plot = true;
  std::string note;  // one line for the table and the summary, when the runs differ from the usual
  // The runs carry the attitude and are measured by it too (docs/attitude-runs.md): a scene with
  // [initial] q, and with --reference a file with its q columns.
  bool attitude = false;

  bool adaptive() const { return !tols.empty(); }
};

}  // namespace eulervop::app
