// The runs of work-precision grids (work_precision_grid.hpp): every case timed (the minimum of a
// few runs) and measured (Eq. 20) against its grid's reference, on a few threads.
#pragma once

#include "compute/work_precision_grid.hpp"

#include <eulervop/core/precision.hpp>
#include <eulervop/reference/settings.hpp>
#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace eulervop::app {

struct wp_result {
  run_result run;       // the first of the timed runs (they differ only in their time)
  double seconds = 0;   // the minimum time over the runs
  std::optional<double> max_error, final_error;  // Eq. 20 over the samples; none after divergence
  // A scene with an attitude: the rotation angle from the reference's q to the run's (rad), as
  // `report` gives it.
  std::optional<double> max_attitude_error, final_attitude_error;
  bool skipped = false;  // not run: a looser rung of its ladder already reached every level
};

struct wp_outcome {
  std::vector<wp_result> results;  // per case, in the grid's order
  double reference_seconds = 0;
  std::size_t reference_segments = 0;
  double reference_tau_end = 0;
};

struct wp_run_options {
  int repeat = 1;             // timed runs per case, the minimum time kept
  int jobs = 1;               // threads
  std::string progress_label;
  // If set, each ladder (one formulation, method and kind, rungs from loose to tight) stops at
  // the first rung whose max error is at most this: a tighter rung costs more and cannot be the
  // cheapest at any level. The rest are marked skipped.
  std::optional<double> stop_below;
};

// Runs every grid's reference (in precision p) and cases on `jobs` threads: the references first,
// then the cases (or, with stop_below, the ladders) longest first. Results land in their case's
// slot, so nothing depends on the scheduling but the times. Errors (Eq. 20) are computed in p at
// each run's samples. numerical_failure from a reference propagates. A scene with an attitude
// carries q in every run and gets its attitude error too; its reference is then integrated once
// at every run's samples, after the runs (so stop_below does not apply: every rung runs).
std::vector<wp_outcome> run_grids(const std::vector<wp_grid>& grids, const eulervop::precision& p,
                                  const picard_settings& settings, const wp_run_options& options);

}  // namespace eulervop::app
