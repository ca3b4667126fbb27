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
// The problem is Euler's equations in double (model/euler_problem.hpp) with any torque: the
// paper's constant G, or one of time and state, evaluated at each stage's time and state in every
// formulation (the VOP formulations from the Omega of their elements). The runs step onto the
// torque's breakpoints (detail/euler_runs.hpp), and the explosion bound of every formulation is
// taken from the torque's size over the span (detail/divergence.hpp, detail/run_torque.hpp).
//
// Attitude (settings.hpp, attitude_settings): every formulation then also carries q,
// dq/dtau = 1/2 q (x) (0, body rates), on the same stages as its rates or elements, sampled beside
// them in run_result::q (detail/attitude.hpp, docs/attitude-runs.md). The rates are bit for bit
// those of the run without it. The rate-only runs are separate instantiations, compiled as before.
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/torque.hpp>
#include <eulervop/rk/embedded_pairs.hpp>
#include <eulervop/rk/method.hpp>
#include <eulervop/rk/tableaux.hpp>
#include <eulervop/runs/detail/divergence.hpp>
#include <eulervop/runs/detail/euler_runs.hpp>
#include <eulervop/runs/detail/run_torque.hpp>
#include <eulervop/runs/detail/vop_adaptive_run.hpp>
#include <eulervop/runs/detail/vop_fixed_run.hpp>
#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <concepts>
#include <stdexcept>

namespace eulervop {

namespace detail {

template <class Problem>
void require_comparison_problem() {
  static_assert(euler_form_problem<Problem> && std::same_as<typename Problem::value_type, double>,
                "the comparison runs integrate Euler's equations (model/euler_problem.hpp) in double");
}

// The paper's VOP (Eqs. 12-16) is built on Eq. 5's elements: no direct form.
template <class Problem>
void require_normalized(formulation f, const Problem& p) {
  if (f != formulation::euler && !p.normalized())
    throw std::domain_error("the paper's VOP needs the normalized Eq. 5, and this body is integrated in the direct "
                            "form of Eq. 1 (two moments equal or nearly so)");
}

// The runs with attitude (s.attitude set): out of line, apart from the rate-only ones.
template <class Problem>
[[gnu::noinline]] void run_fixed_attitude(run_result& out, formulation f, rk::method m, const Problem& p,
                                          const fixed_run_settings& s, double bound) {
  if (f == formulation::euler) {
    run_euler_fixed<Problem, true>(out, p, s, bound);
    return;
  }
  rk::dispatch_method(m, [&](auto tag) {
    if (f == formulation::vop)
      vop_fixed_run<decltype(tag), false, Problem, true>(out, p, s, bound)();
    else
      vop_fixed_run<decltype(tag), true, Problem, true>(out, p, s, bound)();
  });
}

template <class Problem>
[[gnu::noinline]] void run_adaptive_attitude(run_result& out, formulation f, rk::method m, const Problem& p,
                                             const adaptive_run_settings& s, double bound) {
  rk::dispatch_pair(m, [&](auto pair) {
    using Pair = decltype(pair);
    switch (f) {
      case formulation::euler: run_euler_adaptive<Pair, Problem, true>(out, p, s, bound); break;
      case formulation::vop: vop_adaptive_run<Pair, false, Problem, true>(out, p, s, bound)(); break;
      case formulation::vop_theta: vop_adaptive_run<Pair, true, Problem, true>(out, p, s, bound)(); break;
    }
  });
}

// The attitude variant `run`, where the torque type compiles one (model/torque.hpp,
// compiles_attitude_runs).
template <class Problem, class Run>
void run_attitude(Run&& run) {
  if constexpr (compiles_attitude_runs<typename Problem::torque_type>)
    run();
  else
    throw std::invalid_argument("this torque type compiles no attitude runs (its attitude_runs is false)");
}

}  // namespace detail

// Integrates the problem with formulation `f` and method `m` at fixed step in double.
template <class Problem>
run_result run_fixed(formulation f, rk::method m, const Problem& p, const fixed_run_settings& s) {
  detail::require_comparison_problem<Problem>();
  run_result out;
  out.form = f;
  out.method = m;
  detail::require_normalized(f, p);
  const double tau_end = p.initial_time() + s.h * static_cast<double>(s.n_steps);
  const double bound =
      detail::explosion_bound(p.initial_state(), detail::torque_size(p, tau_end), tau_end, f == formulation::vop);
  if (s.attitude) [[unlikely]] {
    detail::run_attitude<Problem>([&] { detail::run_fixed_attitude(out, f, m, p, s, bound); });
    return out;
  }
  if (f == formulation::euler) {
    detail::run_euler_fixed(out, p, s, bound);
    return out;
  }
  rk::dispatch_method(m, [&](auto tag) {
    if (f == formulation::vop)
      detail::vop_fixed_run<decltype(tag), false, Problem>(out, p, s, bound)();
    else
      detail::vop_fixed_run<decltype(tag), true, Problem>(out, p, s, bound)();
  });
  return out;
}

// Integrates the problem with formulation `f` under error control with the embedded pair of `m`
// (rkf45, dp45 or dop853; std::invalid_argument otherwise), from tau0 to s.tau_end.
template <class Problem>
run_result run_adaptive(formulation f, rk::method m, const Problem& p, const adaptive_run_settings& s) {
  detail::require_comparison_problem<Problem>();
  run_result out;
  out.form = f;
  out.method = m;
  out.adaptive = true;
  detail::require_normalized(f, p);
  const double bound =
      detail::explosion_bound(p.initial_state(), detail::torque_size(p, s.tau_end), s.tau_end, f == formulation::vop);
  if (s.attitude) [[unlikely]] {
    detail::run_attitude<Problem>([&] { detail::run_adaptive_attitude(out, f, m, p, s, bound); });
    return out;
  }
  rk::dispatch_pair(m, [&](auto pair) {
    using Pair = decltype(pair);
    switch (f) {
      case formulation::euler: detail::run_euler_adaptive<Pair>(out, p, s, bound); break;
      case formulation::vop: detail::vop_adaptive_run<Pair, false, Problem>(out, p, s, bound)(); break;
      case formulation::vop_theta: detail::vop_adaptive_run<Pair, true, Problem>(out, p, s, bound)(); break;
    }
  });
  return out;
}

}  // namespace eulervop
