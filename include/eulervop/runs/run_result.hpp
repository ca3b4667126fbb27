// What a comparison run (comparison_run.hpp) returns: its samples, its counts and its outcome.
#pragma once

#include <eulervop/core/outcome.hpp>
#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/rk/method.hpp>
#include <eulervop/runs/formulation.hpp>

#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

namespace eulervop {

// One run's outcome.
struct run_result {
  formulation form = formulation::euler;
  rk::method method = rk::method::rk4;
  bool adaptive = false;
  // The samples, in time order: the step index (fixed: tau = tau0 + n h; adaptive: the accepted
  // step's index), and for adaptive runs the time as an unevaluated sum tau_hi + tau_lo.
  std::vector<std::size_t> sample_steps;
  std::vector<double> sample_tau, sample_tau_lo;  // adaptive runs only
  std::vector<vec3<double>> Omega;                // the state there (for vop: converted by Eq. 12)
  std::vector<quaternion<double>> q;              // the attitude there, when the settings carry one
                                                  // (else empty; settings.hpp, attitude_settings)
  std::size_t steps = 0;                          // accepted steps
  std::size_t rejected = 0;                       // rejected steps (adaptive runs)
  std::size_t rhs_evals = 0;
  double seconds = 0;                             // wall time of the integration itself
  outcome status;                                 // success, or why the run stopped and the
                                                  // tau of the first bad step
  // VOP formulations: the stretches stepped with Eq. 5, (tau entered, tau left); a stretch still
  // open when the run stops ends at the run's last tau. Near the separatrix (min(k, 1/k) > 1/2
  // on entry), and near c1 = 0 (small k).
  std::vector<std::pair<double, double>> separatrix_bands;
  std::vector<std::pair<double, double>> small_k_bands;
  std::size_t direct_steps = 0;                   // steps taken with Eq. 5 inside those stretches
  std::size_t regime_changes = 0;                 // element re-derivations into the other regime (k <-> 1/k)
  long long phase_turns = 0;                      // vop-theta: whole turns of theta at the end

  bool diverged() const { return !status.ok(); }
  std::optional<double> diverged_at() const { return status.tau; }
};

}  // namespace eulervop
