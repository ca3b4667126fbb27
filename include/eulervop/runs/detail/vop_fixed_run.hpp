// The VOP formulations of the comparison runs (comparison_run.hpp) at a fixed step.
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/rk/explicit_rk.hpp>
#include <eulervop/rk/problem_system.hpp>
#include <eulervop/runs/detail/divergence.hpp>
#include <eulervop/runs/detail/vop_run_state.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <algorithm>
#include <chrono>
#include <cstddef>

namespace eulervop::detail {

// The VOP formulations at a fixed step: vop_run_state's representations stepped with one
// explicit_rk stepper (the same tableau and compensated summation as rk::integrate_fixed), so
// the method and step never change.
template <class Tableau, bool Theta, class Problem>
class vop_fixed_run {
 public:
  using V = vec3<double>;

  // G: the problem's constant torque.
  vop_fixed_run(run_result& out, const Problem& p, const V& G, const fixed_run_settings& s, double bound)
      : out_(out), s_(s), tau0_(p.initial_time()), bound_(bound), every_(std::max<std::size_t>(s.sample_every, 1)),
        run_(out, p.initial_state(), p.initial_time(), G, s.bands, first_), euler_{p} {}

  void operator()() {
    out_.sample_steps.reserve(s_.n_steps / every_ + 2);
    out_.Omega.reserve(s_.n_steps / every_ + 2);
    V state = first_, comp{0, 0, 0};
    sample(0, state);
    const auto start = std::chrono::steady_clock::now();
    // The loop reads its constants from locals, not through `this` (which it would reload).
    const double tau0 = tau0_, h = s_.h, bound = bound_;
    const std::size_t n_steps = s_.n_steps, every = every_;
    double t = tau0;
    std::size_t n = 0;
    V next{}, comp_next{};
    while (n < n_steps) {
      const double t_next = tau0 + h * static_cast<double>(n + 1);
      comp_next = comp;
      if (!step(state, t, h, next, comp_next)) [[unlikely]] {
        state = run_.leave_elements(t, state);
        comp = V{0, 0, 0};
        continue;
      }
      if (!finite_within(next, bound)) [[unlikely]] {
        out_.status = {divergence_kind(next), t_next};
        break;
      }
      state = next;
      comp = comp_next;
      ++n;
      t = t_next;
      run_.after_step(t, state, comp);
      if (n % every == 0 || n == n_steps) [[unlikely]]
        sample(n, state);
    }
    out_.steps = n;
    out_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out_.rhs_evals = stepper_.rhs_evaluations();
    run_.finish(t);
  }

 private:
  // One step of h of the current representation from (t, state). False when an element step left
  // the elements' domain: the caller redoes it with Eq. 5.
  [[gnu::always_inline]] bool step(const V& state, double t, double h, V& next, V& comp_next) {
    if (run_.in_elements()) {
      stepper_.do_step(run_.system(), state, t, h, next, comp_next);
      return run_.element_step_in_domain(next);
    }
    stepper_.do_step(euler_, state, t, h, next, comp_next);
    return true;
  }
  void sample(std::size_t n, V state) {
    out_.sample_steps.push_back(n);
    out_.Omega.push_back(run_.Omega(state));
  }

  run_result& out_;
  const fixed_run_settings& s_;
  double tau0_, bound_;
  std::size_t every_;  // sample_every, at least 1
  V first_{};          // the starting state, in the representation vop_run_state chose
  vop_run_state<Theta> run_;
  rk::explicit_rk<Tableau, V> stepper_;
  rk::problem_system<Problem> euler_;
};

}  // namespace eulervop::detail
