// A `reference` run: the scene integrated in the job's precision, each sample's row written as it
// is evaluated, in the job's layout (with its certified radius under --certify), and the metadata
// of the finished run (with --verify's estimate).
#pragma once

#include "compute/scene_library.hpp"
#include "io/reference_csv.hpp"
#include "io/scratch_file.hpp"

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/chebyshev_picard.hpp>

#include <string>

namespace eulervop::app {

// Everything a run needs, validated.
struct reference_job {
  scene scn;                         // the scene with --tau-end/--t-end/--samples/--times applied
  eulervop::precision precision;     // --precision, else [reference] precision
  picard_settings settings;          // --degree/--tolerance, else [reference], else automatic
  reference_layout layout = reference_layout::normalized;  // of the header and of every row
  bool verify = false;
  bool certify = false;
  bool omit_timing = false;          // no "# wall_seconds" lines
  std::string command;               // the "# command:" line, if any
  std::string overrides;             // the flags that changed the scene, for the metadata
};

// Streams the rows to `rows_out` and returns the metadata block's content (layout in the
// README, "Command line"). Throws eulervop::numerical_failure when the integrator gives up.
reference_metadata run_reference_job(const reference_job& job, scratch_file& rows_out);

}  // namespace eulervop::app
