// What both modes of `report` print of their runs (the entries of summary.json's "runs", the
// divergence and the VOP fallback stretches under the table) and how a report leaves its
// outputs: errors.csv and summary.json in the output directory, the table or the summary on
// standard output, and Fig. 1.
#pragma once

#include "commands/report/report_job.hpp"
#include "io/output_dir.hpp"

#include <eulervop/core/scalar.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace eulervop::app {

// The scene's own units, in which a report speaks of a physical scene: t in s (tau = t dtau/dt,
// Eq. 4) and the rates' error in rad/s on the listed axes (omega = P^T sqrt(A) Omega, Eq. 2, so
// |omega - omega*|_2 = |sqrt(A) (Omega - Omega*)|_2). The normalized figures stay beside them. In
// the direct form the integrator's variables are t and omega already (rate 1, sqrt(A) = 1). Other
// scenes have no units but the integrator's.
struct report_units {
  bool physical = false;
  bool direct = false;                      // the direct form: the normalized figures are these
  double rate = 1;                          // dtau/dt
  std::array<double, 3> sqrt_A{1, 1, 1};    // principal order, as the integrator's Omega
  static report_units of(const scene& s);
  double t_of(double tau) const { return tau / rate; }
  template <scalar T>
  double rate_error(const vec3<T>& reference, const vec3<double>& run) const {
    using std::sqrt;
    T sum(0);
    for (int i = 0; i < 3; ++i) {
      const T d = (reference[i] - T(run[i])) * T(sqrt_A[i]);
      sum += d * d;
    }
    return static_cast<double>(sqrt(sum));
  }
};

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
  // Physical scenes: the rates' error in rad/s at each sample (report_units), its maximum, and
  // the last sample's t (s) and error.
  std::vector<std::optional<double>> rate_error;
  std::optional<double> max_rate_error, final_t, final_rate_error;
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
// A physical scene's entry speaks its units (report_units): max_error and final_error in rad/s,
// final_t in s, with the normalized max_error_normalized, final_tau and final_error_normalized
// beside them.
nlohmann::ordered_json run_json(const run_spec& spec, const run_errors& e, nlohmann::ordered_json step,
                                nlohmann::ordered_json tol, bool attitude, const report_units& units);

// summary.json's "units" for a physical scene: what its times and errors are measured in (other
// scenes speak the integrator's own variables, as always).
nlohmann::ordered_json units_json(const report_units& units);

// Records a sample's errors in `e` (its maxima and finals): `error` at index i, and `attitude`
// when the job has the attitude. Neither is recorded unless finite (never a NaN as an error).
// With `units` physical, the rates' error in rad/s (`rate`) too.
void record_errors(run_errors& e, std::size_t i, double tau, double error, std::optional<double> attitude,
                   const report_units& units = {}, std::optional<double> rate = std::nullopt);

// The table's error columns after a run's own (steps, time): their headers, and a run's cells,
// with the divergence note last. Max and final error in the scene's units (report_units) with the
// normalized maximum beside them for a physical scene, then the attitude's with one.
std::vector<std::string> error_headers(const report_units& units, bool attitude);
std::vector<std::string> error_cells(const run_errors& e, const report_units& units, bool attitude);

// "euler rk4", or "vop dp45 tol 1e-8" for an adaptive run.
std::string run_label(const report_job& job, const run_spec& spec);

// Where the VOP runs left their elements (separatrix and small-k fallbacks): after a blank line,
// one "<label>: <stretches>" line per run that did (in s for a physical scene), and one line more
// for a run that took direct Euler steps for most of its span; empty when none did.
std::string bands_notes(const report_job& job, const std::vector<run_errors>& runs, const report_units& units);

// Writes errors.csv and summary.json into `dir` (and keeps it), prints `printed` (the summary
// with --format json, else the table) and draws Fig. 1 unless --no-plot.
void write_report(const report_job& job, output_dir& dir, const std::string& errors_csv, const std::string& summary,
                  const std::string& printed, std::ostream& standard_output);

}  // namespace eulervop::app
