// A reference run as a job: the scene with its flags applied and validated, run in its precision,
// its rows handed one by one to a sink as they are evaluated. `eulervop reference` and `batch`
// write the rows as CSV (reference_command.cpp); the Python module keeps them in memory
// (held_reference.hpp). Either way the rows are the same numbers.
#pragma once

#include "commands/reference/reference_command.hpp"
#include "compute/certified_row.hpp"
#include "compute/scene_library.hpp"
#include "io/reference_csv.hpp"

#include <eulervop/core/precision.hpp>
#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/settings.hpp>

#include <optional>
#include <string>
#include <vector>

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
  unsigned certify_workers = 0;      // threads that prepare the certificate's segments
  std::string command;               // the "# command:" line, if any
  std::string overrides;             // the flags that changed the scene, for the metadata
  // Sample times as binary64 numbers, each taken at its exact value, in the scene's own time (t,
  // or tau for a normalized scene): the Python module's. Set by use_binary_times.
  std::optional<std::vector<double>> binary_times;
};

// The flags applied to the scene and validated (a scene --certify cannot prove is bad input),
// before any computation.
// `times_follow`: the caller gives the sample times (use_binary_times), so the scene need have none.
reference_job reference_job_of(scene s, const reference_options& o, bool times_follow = false);
reference_job reference_job_of(const reference_options& o);  // the scene of o.scene_path, or the default

// The rows are sampled at binary64 times: `times` when given (strictly increasing, finite, within
// the span; the last may be the span end rounded to binary64, then integrated to), else the
// scene's own samples each rounded to binary64 first. input_error names times[i] and its value.
void use_binary_times(reference_job& job, std::optional<std::vector<double>> times);

// Where a run's rows go. values() receives every row in order as soon as it is evaluated: its
// integrator time tau, a physical scene's time t in s (null for other scenes, whose own time is
// tau), the state (Omega, or omega in the direct form, or y) and q with an attitude.
// With --certify, certified() then receives every row again, in order, once its radii are known:
// the cells as printed, in the header's order, the radii last.
class reference_row_sink {
 public:
  virtual ~reference_row_sink() = default;
  virtual void values(const double& tau, const double* t, const vec3<double>& y, const quaternion<double>* q) = 0;
  virtual void values(const quad& tau, const quad* t, const vec3<quad>& y, const quaternion<quad>* q) = 0;
  virtual void values(const mpfr_real& tau, const mpfr_real* t, const vec3<mpfr_real>& y,
                      const quaternion<mpfr_real>* q) = 0;
  virtual void certified(const std::vector<std::string>& cells, const certified_radii& radii) = 0;
};

// Runs the job in its precision, handing the rows to `sink`; returns the metadata block's content
// (with --verify's and --certify's lines). Throws numerical_failure when the integrator gives up.
reference_metadata run_reference_job(const reference_job& job, reference_row_sink& sink);

}  // namespace eulervop::app
