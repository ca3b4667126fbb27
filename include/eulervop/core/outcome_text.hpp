// The text of an outcome, for people: the one place where outcome.hpp's kinds become prose
// (the program's "why" fields and messages, numerical_failure::what()).
#pragma once

#include <eulervop/core/outcome.hpp>

#include <cstdio>
#include <string>

namespace eulervop {

namespace detail {

inline std::string describe_kind(outcome_kind kind, const outcome& o) {
  switch (kind) {
    case outcome_kind::success: return "completed";
    case outcome_kind::observer_stop: return "stopped by the observer";
    case outcome_kind::step_limit: return "the step limit was reached";
    case outcome_kind::non_finite: return "state became non-finite";
    case outcome_kind::norm_bound: return "state exploded beyond the bound";
    case outcome_kind::step_underflow: return "the step size fell below the rounding of tau";
    case outcome_kind::initial_non_finite: return "initial state is not finite";
    case outcome_kind::segment_non_finite: return "state is not finite";
    case outcome_kind::segment_limit: return "more than " + std::to_string(o.count) + " segments";
    case outcome_kind::segment_collapse:
      return "segment length collapsed while the Chebyshev series would not converge";
    case outcome_kind::no_convergence:
      return "Picard iteration does not converge: " +
             (o.cause == outcome_kind::no_convergence ? std::string("?") : describe_kind(o.cause, o));
    case outcome_kind::residual_non_finite: return "non-finite residual";
    case outcome_kind::iterate_non_finite: return "non-finite state in the iteration";
    case outcome_kind::residual_not_decreasing: return "residual does not decrease";
    case outcome_kind::residual_stalled:
      return "residual " + std::to_string(o.value) + " after " + std::to_string(o.count) + " passes";
    case outcome_kind::correction_diverged: return "double-precision correction diverged";
    case outcome_kind::correction_stalled:
      return "double-precision correction did not converge in " + std::to_string(o.count) + " sweeps";
    case outcome_kind::dense_output_non_finite: return "non-finite state in the dense output";
    case outcome_kind::error_non_finite: return "non-finite Eq. 20 error";
    case outcome_kind::certification_failed:
      // A formula undefined where its argument may be is no matter of precision.
      return "certification does not close: " +
             (o.cause == outcome_kind::certification_failed ? std::string("?") : describe_kind(o.cause, o)) +
             (o.cause == outcome_kind::certify_formula ? "" : "; try a higher precision");
    case outcome_kind::certify_a_priori:
      return "no a-priori error bound closes on the segment (the segment is too long for the bound)";
    case outcome_kind::certify_growth: {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.3g", o.value);
      return std::string("the proven error bound grew to ") + buf + " of the state";
    }
    case outcome_kind::certify_segment_gap: return "a segment does not start where the previous one ends";
    case outcome_kind::certify_non_finite: return "a non-finite value in the segment or its variational matrix";
    case outcome_kind::certify_formula: return "a formula of the torque is undefined where its argument may lie on the segment";
    case outcome_kind::torque_non_finite: return "the torque is not finite";
  }
  return "?";
}

}  // namespace detail

// What happened, without the place: e.g. "state exploded beyond the bound".
inline std::string describe(const outcome& o) { return detail::describe_kind(o.kind, o); }

}  // namespace eulervop
