// The steps of the comparison runs: a fixed step "K/N" (a fraction of the quarter period K of
// the initial motion) or a number in the scene's time variable, resolved to a step h in tau; and
// the largest step of the adaptive runs.
#pragma once

#include "compute/scene_library.hpp"

#include <eulervop/core/scalar_traits.hpp>

#include <cstddef>
#include <string>

namespace eulervop::app {

// The fixed step of the comparison runs, in tau.
struct fixed_step_choice {
  double h = 0;
  std::size_t n_steps = 0;     // floor(tau_span / h + 1e-9): the runs end at n_steps h <= tau_end
  bool reciprocal = false;     // "K/N" with k0 > 1: K(1/k0) / (N c1)
  std::string rule;            // how h was obtained, for the summary
};

// The adaptive runs' largest step, in tau, and how it was obtained.
struct max_step_choice {
  double h = 0;
  std::string rule;
};

// Resolves a step specification for scene `s` ("K/N": h = K(k0) / (N c2_0), or for k0 > 1
// K(1/k0) / (N c1_0); a number: h in the scene's time variable, converted to tau). `origin`
// names where the step came from ("--step K/0", "[run] step") in messages.
fixed_step_choice resolve_step(const scene& s, const step_spec& spec, const std::string& origin);
// The same length alone (n_steps stays 0): for a maximum step, which may exceed the span.
fixed_step_choice step_length(const scene& s, const step_spec& spec, const std::string& origin);

// n h, exactly in quad and MPFR (a 53-bit h times an integer below 2^53).
template <scalar T>
T tau_of_step(std::size_t n, double h) {
  return T(static_cast<double>(n)) * T(h);
}

}  // namespace eulervop::app
