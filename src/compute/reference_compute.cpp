#include "compute/reference_compute.hpp"

#include <eulervop/reference/integrate.hpp>

namespace eulervop::app {

template <scalar T, class Torque>
dense_reference<T> integrate_dense(const euler_problem<T, Torque>& problem, const T& tau_end,
                                   const picard_settings& settings, const std::string& label) {
  dense_reference<T> out;
  out.wall_seconds = run_with_progress(label, static_cast<double>(tau_end), [&](const progress_callback& progress) {
    out.trajectory = integrate_reference(problem, tau_end, settings, progress, &out.stats);
  });
  return out;
}

// Integrates the problem to tau_end and evaluates the dense output at every tau (non-decreasing,
// each within [tau0, tau_end]) as the segments are accepted, handing each sample to `on_sample`
// and keeping nothing (only the latest segment): memory beyond the caller's times grows with
// neither the span nor the samples. A non-finite sample is a numerical_failure at its tau. The
// wall time includes `on_sample`.
template <scalar T, class Torque>
reference_run integrate_streaming(const euler_problem<T, Torque>& problem, const T& tau_end,
                                  const std::type_identity_t<sample_time_source<T>>& times,
                                  const picard_settings& settings, const std::string& label,
                                  const sample_function<T>& on_sample, const segment_sink<T>& after_segment) {
  reference_run out;
  out.wall_seconds = run_with_progress(label, static_cast<double>(tau_end), [&](const progress_callback& progress) {
    integrate_reference_samples(
        problem, tau_end, times,
        [&](std::size_t index, const T& tau, const vec3<T>& Om) { on_sample(index, require_finite(Om, tau)); },
        settings, progress, &out.stats, after_segment);
  });
  return out;
}

// The same, keeping the samples: memory grows with the samples, not with the span.
template <scalar T, class Torque>
sampled_reference<T> integrate_and_sample(const euler_problem<T, Torque>& problem, const T& tau_end,
                                          const std::vector<T>& taus, const picard_settings& settings,
                                          const std::string& label) {
  sampled_reference<T> out;
  out.Omega.reserve(taus.size());
  const reference_run run = integrate_streaming<T>(problem, tau_end, taus, settings, label,
                                                   [&](std::size_t, const vec3<T>& Om) { out.Omega.push_back(Om); });
  out.stats = run.stats;
  out.wall_seconds = run.wall_seconds;
  return out;
}

// The same for times in any order: streamed when they do not decrease, else evaluated from the
// dense output, which keeps every segment (memory grows with the span).
template <scalar T, class Torque>
reference_run integrate_at(const euler_problem<T, Torque>& problem, const T& tau_end, const std::vector<T>& taus,
                           const picard_settings& settings, const std::string& label,
                           const sample_function<T>& on_sample) {
  if (std::is_sorted(taus.begin(), taus.end()))
    return integrate_streaming<T>(problem, tau_end, taus, settings, label, on_sample);
  const dense_reference<T> ref = integrate_dense<T>(problem, tau_end, settings, label);
  for (std::size_t i = 0; i < taus.size(); ++i) on_sample(i, sample_dense(ref.trajectory, taus[i]));
  return {ref.stats, ref.wall_seconds};
}

// A sample of (y, q), seven values at tau, checked and handed to on_sample as y and q.
template <scalar T>
auto split_attitude_sample(const attitude_sample_function<T>& on_sample) {
  return [&on_sample](std::size_t index, const T& tau, const std::array<T, 7>& v) {
    const vec3<T> y = {v[0], v[1], v[2]};
    const quaternion<T> q{v[3], v[4], v[5], v[6]};
    on_sample(index, require_finite(y, tau), require_finite(q, tau));
  };
}

template <scalar T, class Torque>
reference_run integrate_attitude_streaming(const euler_problem<T, Torque>& problem, const body_rates<T>& rates,
                                           const quaternion<T>& q0, const T& tau_end,
                                           const std::type_identity_t<sample_time_source<T>>& times,
                                           const picard_settings& settings, const std::string& label,
                                           const attitude_sample_function<T>& on_sample,
                                           const segment_sink<T, 7>& after_segment) {
  reference_run out;
  out.wall_seconds = run_with_progress(label, static_cast<double>(tau_end), [&](const progress_callback& progress) {
    integrate_attitude_samples(problem, rates, q0, tau_end, times, split_attitude_sample(on_sample), settings, progress,
                               &out.stats, after_segment);
  });
  return out;
}

template <scalar T>
reference_run integrate_scene_attitude(const scene& s, const T& tau_end,
                                       const std::type_identity_t<sample_time_source<T>>& times,
                                       const picard_settings& settings, const std::string& label,
                                       const attitude_sample_function<T>& on_sample,
                                       const segment_sink<T, 7>& after_segment) {
  if (!s.couples_attitude())
    return with_problem<T>(s, [&](const auto& problem) {
      return integrate_attitude_streaming<T>(problem, body_rates_of<T>(s), attitude_of<T>(s), tau_end, times, settings,
                                             label, on_sample, after_segment);
    });
  const coupled_problem<T> problem = to_coupled_problem<T>(s);
  reference_run out;
  out.wall_seconds = run_with_progress(label, static_cast<double>(tau_end), [&](const progress_callback& progress) {
    const coupled_stats c = integrate_coupled_samples(problem, tau_end, times, split_attitude_sample(on_sample), settings,
                                                      progress, &out.stats, after_segment);
    out.norm_drift = c.norm_drift;
  });
  return out;
}

#define EULERVOP_REFERENCE_COMPUTE(T, G)                                                                         \
  template dense_reference<T> integrate_dense(const euler_problem<T, G>&, const T&, const picard_settings&,         \
                                              const std::string&);                                               \
  template reference_run integrate_streaming(const euler_problem<T, G>&, const T&, const sample_time_source<T>&,   \
                                             const picard_settings&, const std::string&, const sample_function<T>&, \
                                             const segment_sink<T>&);                                             \
  template sampled_reference<T> integrate_and_sample(const euler_problem<T, G>&, const T&, const std::vector<T>&,  \
                                                     const picard_settings&, const std::string&);                 \
  template reference_run integrate_at(const euler_problem<T, G>&, const T&, const std::vector<T>&,                 \
                                      const picard_settings&, const std::string&, const sample_function<T>&);     \
  template reference_run integrate_attitude_streaming(const euler_problem<T, G>&, const body_rates<T>&,          \
                                                      const quaternion<T>&, const T&, const sample_time_source<T>&, \
                                                      const picard_settings&, const std::string&,                 \
                                                      const attitude_sample_function<T>&, const segment_sink<T, 7>&);
#define EULERVOP_REFERENCE_COMPUTE_ALL(T)                                                                  \
  template reference_run integrate_scene_attitude(const scene&, const T&, const sample_time_source<T>&,    \
                                                  const picard_settings&, const std::string&,             \
                                                  const attitude_sample_function<T>&,                     \
                                                  const segment_sink<T, 7>&);                             \
  EULERVOP_REFERENCE_COMPUTE(T, constant_torque<T>) \
  EULERVOP_REFERENCE_COMPUTE(T, time_torque<T>)     \
  EULERVOP_REFERENCE_COMPUTE(T, state_torque<T>)
EULERVOP_REFERENCE_COMPUTE_ALL(double)
EULERVOP_REFERENCE_COMPUTE_ALL(quad)
EULERVOP_REFERENCE_COMPUTE_ALL(mpfr_real)
#undef EULERVOP_REFERENCE_COMPUTE_ALL
#undef EULERVOP_REFERENCE_COMPUTE

}  // namespace eulervop::app
