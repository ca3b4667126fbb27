#include "compute/step_rule.hpp"

#include "compute/scene_library.hpp"

#include <eulervop/special/elliptic.hpp>

#include <fmt/format.h>

#include <cmath>

namespace eulervop::app {

fixed_step_choice step_length(const scene& s, const step_spec& spec, const std::string& origin) {
  fixed_step_choice out;
  if (spec.K_divisor) {
    if (s.is_coefficient_form())
      throw input_error(fmt::format("{}: K/N needs the modulus of Eq. 5, and this scene is in the coefficient form "
                                    "([equations]); give the step in t",
                                    origin));
    if (uses_direct_form(s))
      throw input_error(
          fmt::format("{}: K/N needs the modulus of Eq. 5, and this body is integrated in the direct form "
                      "of Eq. 1 (two moments are equal or nearly so); give the step in seconds",
                      origin));
    const auto N = static_cast<double>(*spec.K_divisor);
    const vec3<double> Om = initial_state_of<double>(s);
    const double c1 = std::hypot(Om[0], Om[1]), c2 = std::hypot(Om[1], Om[2]);
    if (!(c1 > 0 || c2 > 0))
      throw input_error(fmt::format("{}: K/N needs a rotating initial state (Omega(0) = 0); give the step as a number",
                                    origin));
    if (c1 == c2)
      throw input_error(fmt::format("{}: K/N is undefined at k0 = c1/c2 = 1 (the separatrix, K = infinity); give the "
                                    "step as a number",
                                    origin));
    if (c1 < c2) {
      const double k0 = c1 / c2;
      const double K = elliptic_modulus<double>(k0).K();
      out.h = K / (N * c2);
      out.rule = fmt::format("h = K(k0)/({} c2) = {} with k0 = c1/c2 = {}, K = {}, c2 = {}", *spec.K_divisor, out.h,
                             k0, K, c2);
    } else {
      // Rotation near the minor axis: the period is set by the reciprocal modulus (docs/vop-strategies.md).
      const double k0 = c1 / c2;  // may be inf when c2 = 0
      const double K = elliptic_modulus<double>(c2 / c1).K();
      out.h = K / (N * c1);
      out.reciprocal = true;
      out.rule = fmt::format(
          "h = K(1/k0)/({} c1) = {} with the reciprocal modulus, since k0 = c1/c2 = {} >= 1; K = {}, "
          "c1 = {}",
          *spec.K_divisor, out.h, k0, K, c1);
    }
  } else {
    const double value = spec.value->value;
    if (s.is_physical()) {
      out.h = value * scaling_of<double>(s).tau_rate();
      out.rule = fmt::format("h = {} s in t = {} in tau", spec.value->text, out.h);
    } else {
      out.h = value;
      out.rule = fmt::format("h = {}", spec.value->text);
    }
  }
  if (!(out.h > 0) || !std::isfinite(out.h))
    throw input_error(fmt::format("{}: the step h = {} in tau is not a positive finite number", origin, out.h));
  return out;
}

fixed_step_choice resolve_step(const scene& s, const step_spec& spec, const std::string& origin) {
  fixed_step_choice out = step_length(s, spec, origin);
  const double tau_span = tau_end_of<double>(s);
  const double n = std::floor(tau_span / out.h + 1e-9);
  constexpr double max_steps = 2e9;
  if (n < 1)
    throw input_error(fmt::format("{}: the step h = {} in tau is longer than the span (tau_end = {})", origin, out.h,
                                  tau_span));
  if (n > max_steps)
    throw input_error(fmt::format("{}: h = {} in tau needs {:.3g} steps to tau_end = {} (at most {:.0e})", origin,
                                  out.h, n, tau_span, max_steps));
  out.n_steps = static_cast<std::size_t>(n);
  return out;
}

}  // namespace eulervop::app
