// The reference solution of a problem in one call: the dense output on the whole span, or the
// samples at times known in advance in constant memory.
//
// The compiled kernels (kernels/cells.hpp) hold these for every scalar and torque of the program;
// with EULERVOP_COMPILED_KERNELS defined they are declared extern at the foot of this file.
#pragma once

#include <eulervop/core/quaternion.hpp>
#include <eulervop/kernels/cells.hpp>
#include <eulervop/model/coupled_problem.hpp>
#include <eulervop/model/expression_torque.hpp>
#include <eulervop/model/wide_formula_cells.hpp>
#include <eulervop/reference/attitude_cascade.hpp>
#include <eulervop/reference/chebyshev_picard.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace eulervop {

// Integrates the problem from problem.tau0 to tau_end (> tau0). Throws numerical_failure.
template <scalar T, class Torque>
dense_trajectory<T> integrate_reference(const euler_problem<T, Torque>& problem, const T& tau_end,
                                        const picard_settings& settings = {}, const progress_callback& progress = {},
                                        picard_stats* stats = nullptr) {
  chebyshev_picard<euler_problem<T, Torque>> integrator(settings);
  return integrator.run(problem, tau_end, progress, stats);
}

// Integrates the problem from problem.tau0 to tau_end and evaluates the dense output at `taus`
// (non-decreasing, within [tau0, tau_end]) as the run goes, in constant memory: `emit(index, tau,
// y)` receives each sample in order. The values equal those of integrate_reference's trajectory
// at the same times. `after_segment`, if set, sees each segment after the samples before its
// start were emitted, so a segment's samples come between it and the next one. Throws
// numerical_failure.
// `times` may also be a source that produces each time as it is asked for (segment_sampler.hpp).
template <scalar T, class Torque>
void integrate_reference_samples(const euler_problem<T, Torque>& problem, const T& tau_end,
                                 const std::type_identity_t<sample_time_source<T>>& times,
                                 const typename segment_sampler<T>::emit_function& emit,
                                 const picard_settings& settings = {}, const progress_callback& progress = {},
                                 picard_stats* stats = nullptr, const segment_sink<T>& after_segment = {}) {
  segment_sampler<T> sampler(times, emit);
  chebyshev_picard<euler_problem<T, Torque>> integrator(settings);
  integrator.run_segments(
      problem, tau_end,
      [&](const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
        sampler(seg, nodes);
        if (after_segment) after_segment(seg, nodes);
      },
      progress, stats);
  sampler.finish();
}

template <scalar T, class Torque>
void integrate_reference_samples(const euler_problem<T, Torque>& problem, const T& tau_end, const std::vector<T>& taus,
                                 const typename segment_sampler<T>::emit_function& emit,
                                 const picard_settings& settings = {}, const progress_callback& progress = {},
                                 picard_stats* stats = nullptr, const segment_sink<T>& after_segment = {}) {
  integrate_reference_samples(problem, tau_end, times_in(taus), emit, settings, progress, stats, after_segment);
}

// The attitude beside the rates (attitude_cascade.hpp), in constant memory: emit(index, tau, v)
// receives each sample with v = (y1, y2, y3, q0, q1, q2, q3), y the state as above and q the
// attitude (body to inertial) from q0 at problem.tau0. `rates` maps the state to the body rates
// per unit of the problem's time. Returns the attitude's statistics. `after_segment`, if set, sees
// each combined segment as integrate_reference_samples's does. Throws numerical_failure.
template <scalar T, class Torque>
attitude_stats integrate_attitude_samples(const euler_problem<T, Torque>& problem, const body_rates<T>& rates,
                                          const quaternion<T>& q0, const T& tau_end, const std::type_identity_t<sample_time_source<T>>& times,
                                          const typename segment_sampler<T, 7>::emit_function& emit,
                                          const picard_settings& settings = {}, const progress_callback& progress = {},
                                          picard_stats* stats = nullptr,
                                          const segment_sink<T, 7>& after_segment = {}) {
  attitude_cascade<T> cascade(q0, rates, settings);
  segment_sampler<T, 7> sampler(times, emit);
  chebyshev_picard<euler_problem<T, Torque>> integrator(settings);
  const segment_check<T> check = [&](const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
    return cascade.try_segment(seg, nodes);
  };
  integrator.run_segments(
      problem, tau_end,
      [&](const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
        const chebyshev_segment<T, 7>& combined = cascade.commit(seg);
        sampler(combined, nodes);
        if (after_segment) after_segment(combined, nodes);
      },
      progress, stats, check);
  sampler.finish();
  return cascade.stats();
}

template <scalar T, class Torque>
attitude_stats integrate_attitude_samples(const euler_problem<T, Torque>& problem, const body_rates<T>& rates,
                                          const quaternion<T>& q0, const T& tau_end, const std::vector<T>& taus,
                                          const typename segment_sampler<T, 7>::emit_function& emit,
                                          const picard_settings& settings = {}, const progress_callback& progress = {},
                                          picard_stats* stats = nullptr,
                                          const segment_sink<T, 7>& after_segment = {}) {
  return integrate_attitude_samples(problem, rates, q0, tau_end, times_in(taus), emit, settings, progress, stats,
                                    after_segment);
}

// The same, keeping every segment: the dense (y, q) on the whole span.
template <scalar T, class Torque>
dense_trajectory<T, 7> integrate_attitude(const euler_problem<T, Torque>& problem, const body_rates<T>& rates,
                                          const quaternion<T>& q0, const T& tau_end,
                                          const picard_settings& settings = {}, picard_stats* stats = nullptr,
                                          attitude_stats* attitude = nullptr) {
  attitude_cascade<T> cascade(q0, rates, settings);
  std::vector<chebyshev_segment<T, 7>> segs;
  chebyshev_picard<euler_problem<T, Torque>> integrator(settings);
  std::vector<T> nodes_kept;
  const segment_check<T> check = [&](const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
    return cascade.try_segment(seg, nodes);
  };
  integrator.run_segments(
      problem, tau_end,
      [&](const chebyshev_segment<T>& seg, const std::vector<T>& nodes) {
        segs.push_back(cascade.commit(seg));
        if (nodes_kept.empty()) nodes_kept = nodes;
      },
      {}, stats, check);
  if (attitude) *attitude = cascade.stats();
  return dense_trajectory<T, 7>(std::move(segs), nodes_kept);
}

// What a coupled run reports beside the integrator's statistics.
struct coupled_stats {
  double norm_drift = 0;  // the largest | |q| - 1 | at the nodes of the accepted segments
};

namespace detail {
// | |q| - 1 | at the nodes of a segment of (y, q), the largest of them, folded into `drift`.
template <scalar T>
void fold_norm_drift(const chebyshev_segment<T, 7>& seg, double& drift) {
  using std::abs;
  for (const auto& v : seg.values) {
    T n2 = T(0);
    for (std::size_t i = 3; i < 7; ++i) {
      const T qi = seg.base[i] + (seg.base_lo[i] + v[i]);
      n2 += qi * qi;
    }
    // |q| - 1 = (|q|^2 - 1) / (|q| + 1), about half of |q|^2 - 1 near 1.
    drift = std::max(drift, static_cast<double>(abs(n2 - 1)) / 2);
  }
}
}  // namespace detail

// The rates and the attitude as one problem (model/coupled_problem.hpp), in constant memory:
// emit(index, tau, v) receives each sample with v = (y1, y2, y3, q0, q1, q2, q3), as
// integrate_attitude_samples gives them, and `after_segment` each segment. Throws numerical_failure.
template <scalar T>
coupled_stats integrate_coupled_samples(const coupled_problem<T>& problem, const T& tau_end,
                                        const std::type_identity_t<sample_time_source<T>>& times,
                                        const typename segment_sampler<T, 7>::emit_function& emit,
                                        const picard_settings& settings = {}, const progress_callback& progress = {},
                                        picard_stats* stats = nullptr,
                                        const segment_sink<T, 7>& after_segment = {}) {
  coupled_stats out;
  segment_sampler<T, 7> sampler(times, emit);
  chebyshev_picard<coupled_problem<T>> integrator(settings);
  integrator.run_segments(
      problem, tau_end,
      [&](const chebyshev_segment<T, 7>& seg, const std::vector<T>& nodes) {
        detail::fold_norm_drift(seg, out.norm_drift);
        sampler(seg, nodes);
        if (after_segment) after_segment(seg, nodes);
      },
      progress, stats);
  sampler.finish();
  return out;
}

template <scalar T>
coupled_stats integrate_coupled_samples(const coupled_problem<T>& problem, const T& tau_end, const std::vector<T>& taus,
                                        const typename segment_sampler<T, 7>::emit_function& emit,
                                        const picard_settings& settings = {}, const progress_callback& progress = {},
                                        picard_stats* stats = nullptr,
                                        const segment_sink<T, 7>& after_segment = {}) {
  return integrate_coupled_samples(problem, tau_end, times_in(taus), emit, settings, progress, stats, after_segment);
}

// The same, keeping every segment: the dense (y, q) on the whole span.
template <scalar T>
dense_trajectory<T, 7> integrate_coupled(const coupled_problem<T>& problem, const T& tau_end,
                                         const picard_settings& settings = {}, picard_stats* stats = nullptr,
                                         coupled_stats* coupled = nullptr) {
  chebyshev_picard<coupled_problem<T>> integrator(settings);
  std::vector<chebyshev_segment<T, 7>> segs;
  std::vector<T> nodes_kept;
  coupled_stats out;
  integrator.run_segments(
      problem, tau_end,
      [&](const chebyshev_segment<T, 7>& seg, const std::vector<T>& nodes) {
        detail::fold_norm_drift(seg, out.norm_drift);
        segs.push_back(seg);
        if (nodes_kept.empty()) nodes_kept = nodes;
      },
      {}, stats);
  if (coupled) *coupled = out;
  return dense_trajectory<T, 7>(std::move(segs), nodes_kept);
}

// The cells of one scalar T and torque G<T> (kernels/cells.hpp): EXTERN is `extern` to declare
// them, empty to define them. The rates alone, with the integrator's segment loop, which the
// attitude's cell of the same T and G calls rather than compiles again:
#define EULERVOP_REFERENCE_CELL(EXTERN, T, G)                                                                   \
  EXTERN template void chebyshev_picard<euler_problem<T, G<T>>>::run_segments(                                  \
      const euler_problem<T, G<T>>&, const T&, const segment_sink<T>&, const progress_callback&, picard_stats*,  \
      const segment_check<T>&);                                                                                 \
  EXTERN template dense_trajectory<T> integrate_reference(const euler_problem<T, G<T>>&, const T&,              \
                                                          const picard_settings&, const progress_callback&,    \
                                                          picard_stats*);                                      \
  EXTERN template void integrate_reference_samples(const euler_problem<T, G<T>>&, const T&,                     \
                                                   const sample_time_source<T>&,                                \
                                                   const typename segment_sampler<T>::emit_function&,          \
                                                   const picard_settings&, const progress_callback&,           \
                                                   picard_stats*, const segment_sink<T>&);
// ... and with the attitude beside them:
#define EULERVOP_REFERENCE_ATTITUDE_CELL(EXTERN, T, G)                                                           \
  EXTERN template attitude_stats integrate_attitude_samples(                                                     \
      const euler_problem<T, G<T>>&, const body_rates<T>&, const quaternion<T>&, const T&,                      \
      const sample_time_source<T>&,                                                                              \
      const typename segment_sampler<T, 7>::emit_function&, const picard_settings&, const progress_callback&,     \
      picard_stats*, const segment_sink<T, 7>&);                                                                 \
  EXTERN template dense_trajectory<T, 7> integrate_attitude(const euler_problem<T, G<T>>&, const body_rates<T>&, \
                                                            const quaternion<T>&, const T&, const picard_settings&, \
                                                            picard_stats*, attitude_stats*);
// ... what the cells of one scalar share: the integrator's matrices and the attitude's solver:
#define EULERVOP_REFERENCE_SHARED_CELL(EXTERN, T)  \
  EXTERN template struct detail::picard_matrices<T>; \
  EXTERN template class attitude_cascade<T>;
// ... and the coupled problem of one scalar:
#define EULERVOP_REFERENCE_COUPLED_CELL(EXTERN, T)                                                               \
  EXTERN template coupled_stats integrate_coupled_samples(                                                       \
      const coupled_problem<T>&, const T&, const sample_time_source<T>&,                                         \
      const typename segment_sampler<T, 7>::emit_function&,                                                      \
      const picard_settings&, const progress_callback&, picard_stats*, const segment_sink<T, 7>&);               \
  EXTERN template dense_trajectory<T, 7> integrate_coupled(const coupled_problem<T>&, const T&,                 \
                                                           const picard_settings&, picard_stats*, coupled_stats*);
#ifdef EULERVOP_COMPILED_KERNELS
#define EULERVOP_EXTERN_REFERENCE_CELLS_(T, G) \
  EULERVOP_REFERENCE_CELL(extern, T, G)        \
  EULERVOP_REFERENCE_ATTITUDE_CELL(extern, T, G)
EULERVOP_FOR_EACH_SCALAR_AND_TORQUE(EULERVOP_EXTERN_REFERENCE_CELLS_)
#undef EULERVOP_EXTERN_REFERENCE_CELLS_
#define EULERVOP_EXTERN_COUPLED_CELL_(T, ...) \
  EULERVOP_REFERENCE_COUPLED_CELL(extern, T)   \
  EULERVOP_REFERENCE_SHARED_CELL(extern, T)
EULERVOP_KERNEL_SCALARS(EULERVOP_EXTERN_COUPLED_CELL_, )
#undef EULERVOP_EXTERN_COUPLED_CELL_
#endif

}  // namespace eulervop
