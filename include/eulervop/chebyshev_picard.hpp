// Chebyshev-Picard reference integrator with dense output (API; implementation in progress).
#pragma once

#include <eulervop/model.hpp>
#include <eulervop/scalar.hpp>

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace eulervop {

// Knobs of the reference integrator. Zero means "derive from the precision of T".
struct picard_settings {
  unsigned degree = 0;       // Chebyshev degree N (N+1 Gauss-Lobatto nodes per segment)
  double tolerance = 0;      // relative accuracy asked per segment; 0: a few epsilon of T
  double initial_step = 0;   // first segment length in tau; 0: from the initial rotation rate
  std::size_t max_segments = 50'000'000;
};

// Counters of one integration, for reports and benchmarks.
struct picard_stats {
  std::size_t segments = 0;         // accepted segments
  std::size_t rejected = 0;         // segments shrunk and retried
  std::size_t wide_residuals = 0;   // residual evaluations in T
  std::size_t double_sweeps = 0;    // Picard sweeps of the double-precision correction
};

// A numerical failure of the integrator: where (tau) and why. The CLI maps it to exit code 3.
class numerical_failure : public std::runtime_error {
 public:
  numerical_failure(double tau, const std::string& why)
      : std::runtime_error("numerical failure at tau=" + std::to_string(tau) + ": " + why), tau_(tau) {}
  double tau() const { return tau_; }

 private:
  double tau_;
};

// One segment of the dense output: Omega(tau) = base + sum_k coeff[k] T_k(s), with
// s = (tau - tau_mid) / half_length in [-1, 1].
template <class T>
struct chebyshev_segment {
  T tau_begin, tau_end, tau_mid, half_length;
  vec3<T> base;                  // Omega at tau_begin (compensated sum of increments)
  std::vector<vec3<T>> coeffs;   // Chebyshev coefficients of Omega(tau) - base
};

// The reference solution on [tau_begin, tau_end], evaluable anywhere in it to full precision.
template <class T>
class dense_trajectory {
 public:
  const T& tau_begin() const;
  const T& tau_end() const;
  std::size_t segments() const { return segs_.size(); }
  const std::vector<chebyshev_segment<T>>& segment_list() const { return segs_; }
  // Omega(tau). Throws std::out_of_range outside [tau_begin, tau_end].
  vec3<T> operator()(const T& tau) const;

  std::vector<chebyshev_segment<T>> segs_;
};

// Progress callback: the tau reached so far.
using progress_callback = std::function<void(double tau_reached)>;

// Integrates Eq. 5 from problem.tau0 to tau_end (> tau0). Throws numerical_failure.
template <class T>
dense_trajectory<T> integrate_reference(const normalized_problem<T>& problem, const T& tau_end,
                                        const picard_settings& settings = {},
                                        const progress_callback& progress = {},
                                        picard_stats* stats = nullptr);

}  // namespace eulervop
