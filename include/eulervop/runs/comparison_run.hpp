// The double-precision comparison runs of the paper (Section 3): one formulation of the problem
// (formulation.hpp) integrated with one explicit Runge-Kutta method, at a fixed step (run_fixed)
// or under error control (run_adaptive), sampled for the Eq. 20 error.
//
//   euler      detail/euler_runs.hpp: the problem's equations, through rk::problem_system;
//   vop, vop-theta
//              detail/vop_fixed_run.hpp, detail/vop_adaptive_run.hpp: the elements of
//              vop/vop_system.hpp and vop/vop_theta_system.hpp, with direct steps of Eq. 5 across
//              their singular bands (detail/vop_run_state.hpp).
// Adaptive runs use the embedded pairs of rk/embedded_pairs.hpp (rkf45, dp45, dop853) with atol,
// rtol and a maximum step; the VOP runs measure the error in scaled elements
// (detail/vop_adaptive_run.hpp).
//
// The problem is Euler's equations in double (model/euler_problem.hpp) with a constant torque G:
// the paper's VOP varies the constants of the torque-free motion under Eq. 5 with constant G
// (Eqs. 12-16), and the explosion bound of every formulation is taken from |G|
// (detail/divergence.hpp).
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/torque.hpp>
#include <eulervop/rk/embedded_pairs.hpp>
#include <eulervop/rk/method.hpp>
#include <eulervop/rk/tableaux.hpp>
#include <eulervop/runs/detail/divergence.hpp>
#include <eulervop/runs/detail/euler_runs.hpp>
#include <eulervop/runs/detail/vop_adaptive_run.hpp>
#include <eulervop/runs/detail/vop_fixed_run.hpp>
#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <concepts>
#include <stdexcept>

namespace eulervop {

namespace detail {

// The constant torque G of a problem of the comparison runs (see the header note).
template <class Problem>
vec3<double> comparison_torque(const Problem& p) {
  static_assert(euler_form_problem<Problem> && std::same_as<typename Problem::value_type, double>,
                "the comparison runs integrate Euler's equations (model/euler_problem.hpp) in double");
  static_assert(is_constant_torque_v<typename Problem::torque_type>,
                "the comparison runs need Eq. 5 with a constant torque: the VOP formulations (Eqs. 12-16) vary "
                "the constants of the torque-free motion under a constant G, and this problem's torque depends "
                "on the time or the state");
  return p.torque.value(p.initial_time(), p.initial_state());
}

// The paper's VOP (Eqs. 12-16) is built on Eq. 5's elements: no direct form.
template <class Problem>
void require_normalized(formulation f, const Problem& p) {
  if (f != formulation::euler && !p.normalized())
    throw std::domain_error("the paper's VOP needs the normalized Eq. 5, and this body is integrated in the direct "
                            "form of Eq. 1 (two moments equal or nearly so)");
}

}  // namespace detail

// Integrates the problem with formulation `f` and method `m` at fixed step in double.
template <class Problem>
run_result run_fixed(formulation f, rk::method m, const Problem& p, const fixed_run_settings& s) {
  const vec3<double> G = detail::comparison_torque(p);
  run_result out;
  out.form = f;
  out.method = m;
  detail::require_normalized(f, p);
  const double tau_end = p.initial_time() + s.h * static_cast<double>(s.n_steps);
  const double bound = detail::explosion_bound(p.initial_state(), G, tau_end, f == formulation::vop);
  if (f == formulation::euler) {
    detail::run_euler_fixed(out, p, s, bound);
    return out;
  }
  rk::dispatch_method(m, [&](auto tag) {
    if (f == formulation::vop)
      detail::vop_fixed_run<decltype(tag), false, Problem>(out, p, G, s, bound)();
    else
      detail::vop_fixed_run<decltype(tag), true, Problem>(out, p, G, s, bound)();
  });
  return out;
}

// Integrates the problem with formulation `f` under error control with the embedded pair of `m`
// (rkf45, dp45 or dop853; std::invalid_argument otherwise), from tau0 to s.tau_end.
template <class Problem>
run_result run_adaptive(formulation f, rk::method m, const Problem& p, const adaptive_run_settings& s) {
  const vec3<double> G = detail::comparison_torque(p);
  run_result out;
  out.form = f;
  out.method = m;
  out.adaptive = true;
  detail::require_normalized(f, p);
  const double bound = detail::explosion_bound(p.initial_state(), G, s.tau_end, f == formulation::vop);
  rk::dispatch_pair(m, [&](auto pair) {
    using Pair = decltype(pair);
    switch (f) {
      case formulation::euler: detail::run_euler_adaptive<Pair>(out, p, s, bound); break;
      case formulation::vop: detail::vop_adaptive_run<Pair, false, Problem>(out, p, G, s, bound)(); break;
      case formulation::vop_theta: detail::vop_adaptive_run<Pair, true, Problem>(out, p, G, s, bound)(); break;
    }
  });
  return out;
}

}  // namespace eulervop
