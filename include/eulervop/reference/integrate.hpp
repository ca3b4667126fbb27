// The reference solution of a problem in one call: the dense output on the whole span, or the
// samples at times known in advance in constant memory.
#pragma once

#include <eulervop/reference/chebyshev_picard.hpp>

#include <cstddef>
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
template <scalar T, class Torque>
void integrate_reference_samples(const euler_problem<T, Torque>& problem, const T& tau_end, const std::vector<T>& taus,
                                 const typename segment_sampler<T>::emit_function& emit,
                                 const picard_settings& settings = {}, const progress_callback& progress = {},
                                 picard_stats* stats = nullptr, const segment_sink<T>& after_segment = {}) {
  segment_sampler<T> sampler(taus, emit);
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

}  // namespace eulervop
