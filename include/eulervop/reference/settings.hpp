// The knobs and counters of the reference integrator (chebyshev_picard.hpp).
#pragma once

#include <cstddef>
#include <functional>

namespace eulervop {

// Knobs of the reference integrator. Zero means "derive from the precision of T".
struct picard_settings {
  unsigned degree = 0;       // Chebyshev degree N (N+1 Gauss-Lobatto nodes per segment)
  double tolerance = 0;      // relative tolerance (truncation per segment: a sixteenth of it); 0: epsilon of T
  double initial_step = 0;   // first segment length in tau; 0: from the initial rotation rate
  std::size_t max_segments = 50'000'000;
};

// Counters of one integration, for reports and benchmarks.
struct picard_stats {
  unsigned degree = 0;
  double tolerance = 0;
  std::size_t segments = 0;        // accepted segments
  std::size_t rejected = 0;        // segments shrunk and retried
  std::size_t wide_residuals = 0;  // residual evaluations in T (each one matrix product in T)
  std::size_t residual_updates = 0;  // residuals updated in double-double after a correction
  std::size_t double_sweeps = 0;   // sweeps of the double-precision correction
};

// Progress callback: the tau reached so far, and the segments accepted.
using progress_callback = std::function<void(double tau_reached, std::size_t segments)>;

}  // namespace eulervop
