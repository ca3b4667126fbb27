// The reference solution as the subcommands compute it: integrate a scene's problem with the
// Chebyshev-Picard integrator (with a progress line), and evaluate it at sample times known in
// advance as the segments are accepted (or keep the dense output, where the times are not known
// in advance). Shared by `reference`, `report`, `check` and the grids of `sweep` and `map`.
//
// The integrations are compiled once, in reference_compute.cpp, for double, quad and MPFR and
// for each kind of torque (constant, of time, of time and state: scene_problem.hpp's
// with_problem): the commands that call them do not instantiate the integrator again.
#pragma once

#include "compute/progress.hpp"
#include "compute/scene_library.hpp"
#include "compute/with_scalar.hpp"

#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/core/quaternion.hpp>
#include <eulervop/model/body_rates.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/expression_torque.hpp>
#include <eulervop/reference/dense_trajectory.hpp>
#include <eulervop/reference/segment_sampler.hpp>
#include <eulervop/reference/settings.hpp>

#include <boost/math/special_functions/fpclassify.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace eulervop::app {

template <scalar T>
struct sampled_reference {
  std::vector<vec3<T>> Omega;
  picard_stats stats;
  double wall_seconds = 0;
};

// The dense solution to tau_end, with a progress line labelled `label` (none if it is empty:
// a sweep integrates its reference on a worker thread and draws its own line).
template <scalar T>
struct dense_reference {
  dense_trajectory<T> trajectory;
  picard_stats stats;
  double wall_seconds = 0;
};

// Runs integrate(progress), a function of a progress_callback, under a progress display labelled
// `label` (none when empty) that goes to `total`, in tau, shown in the scene's time
// (scene_time(), progress.hpp); returns the wall time.
template <class Integrate>
double run_with_progress(const std::string& label, double total, Integrate&& integrate) {
  const auto start = std::chrono::steady_clock::now();
  const scene_clock& clock = scene_time();
  const std::unique_ptr<progress_display> progress =
      label.empty() ? nullptr : open_progress(label, total * clock.per_tau, clock.unit);
  integrate([&](double tau, std::size_t segments) {
    if (progress) progress->update(tau * clock.per_tau, segments);
  });
  if (progress) progress->clear();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <scalar T, class Torque>
dense_reference<T> integrate_dense(const euler_problem<T, Torque>& problem, const T& tau_end,
                                   const picard_settings& settings, const std::string& label);

// A sample at `tau`, checked: a non-finite value is a numerical_failure there, so that no NaN is
// ever printed as a result (docs/design.md section 5.3).
template <scalar T>
const vec3<T>& require_finite(const vec3<T>& Om, const T& tau) {
  for (const T& x : Om)
    if (!(boost::math::isfinite)(x))
      throw numerical_failure({outcome_kind::dense_output_non_finite, static_cast<double>(tau)});
  return Om;
}

template <scalar T>
const quaternion<T>& require_finite(const quaternion<T>& q, const T& tau) {
  for (const T* x : {&q.w, &q.x, &q.y, &q.z})
    if (!(boost::math::isfinite)(*x))
      throw numerical_failure({outcome_kind::dense_output_non_finite, static_cast<double>(tau)});
  return q;
}

// The dense output at `tau` (within the integrated span), checked.
template <scalar T>
vec3<T> sample_dense(const dense_trajectory<T>& trajectory, const T& tau) {
  return require_finite(trajectory(tau), tau);
}

// What a run leaves once its samples have gone to a callback.
struct reference_run {
  picard_stats stats;
  double wall_seconds = 0;
  // For the rates and q as one problem (a torque of the attitude): the largest | |q| - 1 | at the
  // nodes (reference/integrate.hpp's coupled_stats).
  std::optional<double> norm_drift;
};

// Receives sample `index` (of the taus given) and the reference there, in order.
template <scalar T>
using sample_function = std::function<void(std::size_t index, const vec3<T>& Omega)>;

// Integrates the problem to tau_end and evaluates the dense output at every tau (non-decreasing,
// each within [tau0, tau_end]) as the segments are accepted, handing each sample to `on_sample`
// and keeping nothing (only the latest segment): memory beyond the caller's times grows with
// neither the span nor the samples. A non-finite sample is a numerical_failure at its tau. The
// wall time includes `on_sample`.
// `times` may produce each time as it is asked for (segment_sampler.hpp): then nothing grows
// with the samples either.
template <scalar T, class Torque>
reference_run integrate_streaming(const euler_problem<T, Torque>& problem, const T& tau_end,
                                  const std::type_identity_t<sample_time_source<T>>& times,
                                  const picard_settings& settings, const std::string& label,
                                  const sample_function<T>& on_sample, const segment_sink<T>& after_segment = {});

template <scalar T, class Torque>
reference_run integrate_streaming(const euler_problem<T, Torque>& problem, const T& tau_end, const std::vector<T>& taus,
                                  const picard_settings& settings, const std::string& label,
                                  const sample_function<T>& on_sample, const segment_sink<T>& after_segment = {}) {
  return integrate_streaming<T>(problem, tau_end, times_in(taus), settings, label, on_sample, after_segment);
}

// The same, keeping the samples: memory grows with the samples, not with the span.
template <scalar T, class Torque>
sampled_reference<T> integrate_and_sample(const euler_problem<T, Torque>& problem, const T& tau_end,
                                          const std::vector<T>& taus, const picard_settings& settings,
                                          const std::string& label);

// The same for times in any order: streamed when they do not decrease, else evaluated from the
// dense output, which keeps every segment (memory grows with the span).
template <scalar T, class Torque>
reference_run integrate_at(const euler_problem<T, Torque>& problem, const T& tau_end, const std::vector<T>& taus,
                           const picard_settings& settings, const std::string& label,
                           const sample_function<T>& on_sample);

// Receives sample `index` and (y, q): the state in the integrator's variables, then the attitude.
template <scalar T>
using attitude_sample_function = std::function<void(std::size_t index, const vec3<T>& y, const quaternion<T>& q)>;

// The same with the attitude beside the rates (reference/attitude_cascade.hpp): q from q0 at
// tau0, turned by the body rates `rates` gives of the state. A non-finite sample is a
// numerical_failure at its tau.
template <scalar T, class Torque>
reference_run integrate_attitude_streaming(const euler_problem<T, Torque>& problem, const body_rates<T>& rates,
                                           const quaternion<T>& q0, const T& tau_end,
                                           const std::type_identity_t<sample_time_source<T>>& times,
                                           const picard_settings& settings, const std::string& label,
                                           const attitude_sample_function<T>& on_sample,
                                           const segment_sink<T, 7>& after_segment = {});

template <scalar T, class Torque>
reference_run integrate_attitude_streaming(const euler_problem<T, Torque>& problem, const body_rates<T>& rates,
                                           const quaternion<T>& q0, const T& tau_end, const std::vector<T>& taus,
                                           const picard_settings& settings, const std::string& label,
                                           const attitude_sample_function<T>& on_sample,
                                           const segment_sink<T, 7>& after_segment = {}) {
  return integrate_attitude_streaming<T>(problem, rates, q0, tau_end, times_in(taus), settings, label, on_sample,
                                         after_segment);
}

// The rates and the attitude of a scene with one (s.has_attitude()) at `taus` (non-decreasing):
// q beside the rates (integrate_attitude_streaming) when the torque does not read q, and the two
// as one problem of 7 states when it does (model/coupled_problem.hpp; run.norm_drift is then
// set). on_sample receives the state in the integrator's variables and q, and `after_segment` each
// segment of (y, q) after the samples before its start. A non-finite sample is a numerical_failure
// at its tau.
template <scalar T>
reference_run integrate_scene_attitude(const scene& s, const T& tau_end,
                                       const std::type_identity_t<sample_time_source<T>>& times,
                                       const picard_settings& settings, const std::string& label,
                                       const attitude_sample_function<T>& on_sample,
                                       const segment_sink<T, 7>& after_segment = {});

template <scalar T>
reference_run integrate_scene_attitude(const scene& s, const T& tau_end, const std::vector<T>& taus,
                                       const picard_settings& settings, const std::string& label,
                                       const attitude_sample_function<T>& on_sample,
                                       const segment_sink<T, 7>& after_segment = {}) {
  return integrate_scene_attitude<T>(s, tau_end, times_in(taus), settings, label, on_sample, after_segment);
}

// The settings the integrator actually used (it derives degree and tolerance from the
// precision when they are left at 0).
inline std::string method_text(const picard_settings& settings, const picard_stats& stats) {
  const unsigned degree = stats.degree ? stats.degree : settings.degree;
  const double tolerance = stats.tolerance > 0 ? stats.tolerance : settings.tolerance;
  return fmt::format("chebyshev-picard degree={} tolerance={:.3g} segments={} rejected={}", degree, tolerance,
                     stats.segments, stats.rejected);
}

}  // namespace eulervop::app
