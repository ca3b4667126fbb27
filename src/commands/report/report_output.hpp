// What both modes of `report` print of their runs (the entries of summary.json's "runs", the
// divergence and the VOP fallback stretches under the table) and how a report leaves its
// outputs: errors.csv and summary.json in the output directory, the table or the summary on
// standard output, and Fig. 1.
#pragma once

#include "commands/report/report_job.hpp"
#include "io/output_dir.hpp"

#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <nlohmann/json.hpp>

#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace eulervop::app {

// A run and its Eq. 20 error at each sample (the reference's samples for fixed steps, the run's
// own step points for adaptive ones); nullopt: not reached, or after divergence. A job with the
// attitude also has the attitude error there, the angle of the rotation from the reference's q
// to the run's (rotation_angle, core/quaternion.hpp), in radians.
struct run_errors {
  run_result run;
  std::vector<std::optional<double>> error;
  std::optional<double> max_error, final_tau, final_error;
  std::vector<std::optional<double>> attitude_error;  // attitude jobs only (else empty)
  std::optional<double> max_attitude_error, final_attitude_error;
};

// x in the format `spec`, or "-" when there is none.
std::string optional_text(const std::optional<double>& x, const char* spec);

// "diverged at tau=12.3 (why)" for a diverged run; empty otherwise.
std::string divergence_note(const run_result& r);

// How the runs carry q: beside the rates, or with them as one problem when the torque reads it.
std::string attitude_mode(const scene& s);

// One entry of summary.json's "runs": a fixed run has a step and no tolerance (and no
// accepted/rejected counts), an adaptive run the reverse. With `attitude`, also
// max_attitude_error and final_attitude_error (radians), after final_error.
nlohmann::ordered_json run_json(const run_spec& spec, const run_errors& e, nlohmann::ordered_json step,
                                nlohmann::ordered_json tol, bool attitude);

// Records a sample's errors in `e` (its maxima and finals): `error` at index i, and `attitude`
// when the job has the attitude. Neither is recorded unless finite (never a NaN as an error).
void record_errors(run_errors& e, std::size_t i, double tau, double error, std::optional<double> attitude);

// "euler rk4", or "vop dp45 tol 1e-8" for an adaptive run.
std::string run_label(const report_job& job, const run_spec& spec);

// Where the VOP runs left their elements (separatrix and small-k fallbacks): after a blank line,
// one "<label>: <stretches>" line per run that did; empty when none did.
std::string bands_notes(const report_job& job, const std::vector<run_errors>& runs);

// Writes errors.csv and summary.json into `dir` (and keeps it), prints `printed` (the summary
// with --format json, else the table) and draws Fig. 1 unless --no-plot.
void write_report(const report_job& job, output_dir& dir, const std::string& errors_csv, const std::string& summary,
                  const std::string& printed, std::ostream& standard_output);

}  // namespace eulervop::app
