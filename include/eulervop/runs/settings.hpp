// The settings of a comparison run (comparison_run.hpp): the step or the tolerances, the sampling,
// where the VOP formulations step with Eq. 5 instead (vop_band_thresholds; the bands are
// described in detail/vop_run_state.hpp), and the attitude to carry beside the rates, if any.
#pragma once

#include <eulervop/core/quaternion.hpp>
#include <eulervop/model/body_rates.hpp>

#include <cstddef>
#include <optional>

namespace eulervop {

// Where the VOP formulations step with Eq. 5 instead (detail/vop_run_state.hpp; the values are
// chosen from the measurements in docs/vop-strategies.md).
struct vop_band_thresholds {
  double separatrix_band = 0.05;         // cap of the band in 1 - min(k, 1/k)
  double separatrix_torque_scale = 0.25; // the band is min(cap, this |G| / (c1 c2))
  double small_k_torque_ratio = 10;      // direct steps while |G| / (c1 c2) exceeds this
};

// The attitude a run carries beside its rates (detail/attitude.hpp, docs/attitude-runs.md): q
// from q0 at tau0, dq/dtau = 1/2 q (x) (0, rates(y)), with y the run's Omega (Eq. 5, or Eq. 1 in
// the direct form) and `rates` the body rates per unit tau in the scene's axes
// (model/body_rates.hpp). It never changes the rates, their steps or their samples.
struct attitude_settings {
  body_rates<double> rates;
  quaternion<double> q0{1, 0, 0, 0};
};

// Fixed step h, n_steps of it; the state is sampled at every step index that is a multiple of
// sample_every, and at the last step.
struct fixed_run_settings {
  double h = 0;
  std::size_t n_steps = 0;
  std::size_t sample_every = 1;
  vop_band_thresholds bands{};
  std::optional<attitude_settings> attitude{};  // none: the rates alone (run_result::q empty)
};

// Error control to tau_end: atol, rtol (rk/error_norm.hpp), steps no longer than h_max (0: the span).
// About `samples` states are kept (every m-th accepted step, m doubling as the run grows), and
// the last one.
struct adaptive_run_settings {
  double tau_end = 0;
  double atol = 0;
  double rtol = 0;
  double h_max = 0;
  std::size_t samples = 200;
  vop_band_thresholds bands{};
  std::optional<attitude_settings> attitude{};  // none: the rates alone (run_result::q empty)
};

}  // namespace eulervop
