// The sampling of an adaptive comparison run (comparison_run.hpp).
#pragma once

#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/vec3.hpp>
#include <eulervop/runs/run_result.hpp>

#include <algorithm>
#include <cstddef>

namespace eulervop::detail {

// Keeps about `target` samples of an adaptive run: every m-th accepted step, m doubling (and the
// kept samples thinned to every other one) whenever twice the target is reached. wants(step) is
// one comparison, so a run asks it after every step and converts a VOP state to Omega only for
// the steps it keeps.
class sample_thinner {
 public:
  sample_thinner(run_result& out, std::size_t target) : out_(out), target_(std::max<std::size_t>(target, 2)) {}

  bool wants(std::size_t step) const { return step == next_; }

  void put(std::size_t step, double tau, double tau_lo, const vec3<double>& Omega) {
    out_.sample_steps.push_back(step);
    out_.sample_tau.push_back(tau);
    out_.sample_tau_lo.push_back(tau_lo);
    out_.Omega.push_back(Omega);
    next_ = step + stride_;
    if (out_.sample_steps.size() < 2 * target_) return;
    stride_ *= 2;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < out_.sample_steps.size(); ++i) {
      if (out_.sample_steps[i] % stride_ != 0) continue;
      out_.sample_steps[kept] = out_.sample_steps[i];
      out_.sample_tau[kept] = out_.sample_tau[i];
      out_.sample_tau_lo[kept] = out_.sample_tau_lo[i];
      out_.Omega[kept] = out_.Omega[i];
      if (!out_.q.empty()) out_.q[kept] = out_.q[i];
      ++kept;
    }
    out_.sample_steps.resize(kept);
    out_.sample_tau.resize(kept);
    out_.sample_tau_lo.resize(kept);
    out_.Omega.resize(kept);
    if (!out_.q.empty()) out_.q.resize(kept);
    next_ = (step / stride_ + 1) * stride_;
  }
  // The same with the attitude there (a run with attitude puts every sample so).
  void put(std::size_t step, double tau, double tau_lo, const vec3<double>& Omega, const quaternion<double>& q) {
    out_.q.push_back(q);
    put(step, tau, tau_lo, Omega);
  }
  // Whether the run's last state (at `step`) still needs to be put.
  bool lacks_last(std::size_t step) const { return out_.sample_steps.empty() || out_.sample_steps.back() != step; }

 private:
  run_result& out_;
  std::size_t target_;
  std::size_t stride_ = 1;
  std::size_t next_ = 0;
};

}  // namespace eulervop::detail
