// How an integration ended: one type for the double-precision runs (rk/fixed_step.hpp,
// rk/adaptive_driver.hpp, runs/comparison_run.hpp) and for the reference (chebyshev_picard.hpp),
// after heyoka's taylor_outcome. The core records what happened and where, with the numbers a
// message needs; the text for people is made at the edge, by describe() (outcome_text.hpp).
#pragma once

#include <cstddef>
#include <optional>

namespace eulervop {

enum class outcome_kind {
  success,         // the whole span was integrated
  observer_stop,   // the observer returned false
  step_limit,      // the step budget ran out (rk::adaptive_options::max_steps)
  // A double-precision run that stopped:
  non_finite,      // a step produced Inf or NaN (or the step size became non-finite)
  norm_bound,      // a step produced a state beyond the bound: the run "exploded"
  step_underflow,  // the step fell below 16 ulp of tau: too stiff or singular
  // The reference integrator that gave up:
  initial_non_finite,  // the initial state is not finite
  segment_non_finite,  // an accepted segment ends in a non-finite state
  segment_limit,       // more than `count` segments (picard_settings::max_segments)
  segment_collapse,    // segments shrank to nothing while the Chebyshev tail stayed too large
  no_convergence,      // the Picard iteration failed on ever shorter segments; `cause` says how
  // ... and how one segment's Picard iteration failed (the cause of no_convergence):
  residual_non_finite,      // the residual of the Picard map is not finite
  iterate_non_finite,       // the iterate at the nodes is not finite
  residual_not_decreasing,  // the double-double residual is not below half the double one
  residual_stalled,         // residual `value` (max-norm) after `count` passes in T
  correction_diverged,      // the double-precision correction grows
  correction_stalled,       // the correction did not converge in `count` sweeps
  // A reference that was computed but cannot be used:
  dense_output_non_finite,  // the dense output evaluates to a non-finite state
  error_non_finite,         // the Eq. 20 error against it is not finite
  // A certificate (certify/ball_certifier.hpp) that could not be proven; `cause` says why:
  certification_failed,
  certify_a_priori,      // no a-priori bound closes on the segment
  certify_growth,        // the propagated bound grew beyond `value` (relative to the state)
  certify_segment_gap,   // a segment does not start where the previous one ends
  certify_non_finite,    // a non-finite value in the segment or the variational matrix
  certify_formula,       // a formula of the torque has no enclosure on the segment (the detail says why)
  // A torque given by a formula (model/expression_torque.hpp) that is not finite where evaluated:
  torque_non_finite,
};

struct outcome {
  outcome_kind kind = outcome_kind::success;
  std::optional<double> tau;  // where: the end of the step that failed, or the segment's start
  outcome_kind cause = outcome_kind::success;  // no_convergence: how the last attempt failed
  double value = 0;       // residual_stalled: the residual's max-norm
  std::size_t count = 0;  // residual_stalled: passes; correction_stalled: sweeps; segment_limit

  bool ok() const { return kind == outcome_kind::success; }
};

}  // namespace eulervop
