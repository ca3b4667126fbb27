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
// those of the run without it. The rate-only runs are separate instantiations.
//
// Each (formulation, fixed or adaptive, rates or attitude) is a cell (detail/run_cells.hpp) of the
// constant torque or of varying_torque (every torque of time, state or attitude, of the program's
// types or of any other, its kind data: varying_torque.hpp), compiled in kernels/cells.hpp and
// declared extern below with the kernels. A problem with any other torque type runs as one of
// those two (detail::as_compiled), so no torque type instantiates drivers of its own.
#pragma once

#include <eulervop/core/vec3.hpp>
#include <eulervop/kernels/cells.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/expression_torque.hpp>
#include <eulervop/model/staged_attitude_torque.hpp>
#include <eulervop/model/torque.hpp>
#include <eulervop/rk/method.hpp>
#include <eulervop/runs/detail/divergence.hpp>
#include <eulervop/runs/detail/run_cells.hpp>
#include <eulervop/runs/detail/run_torque.hpp>
#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>
#include <eulervop/runs/varying_torque.hpp>

#include <concepts>
#include <stdexcept>
#include <type_traits>

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

// The two torque types the run drivers are compiled for (kernels/cells.hpp): the paper's constant
// G, and varying_torque, whose kind is data. Every other torque type runs as one of them.
template <class Torque>
concept compiled_run_torque = std::same_as<Torque, constant_torque<double>> || std::same_as<Torque, varying_torque<double>>;

// The same problem with its torque as one of the compiled types: a constant torque as its one
// vector, any other as a varying_torque of its kind (a copy: the run pins and evaluates its own).
template <class Torque>
auto as_compiled(const euler_problem<double, Torque>& p) {
  using G = std::conditional_t<is_constant_torque_v<Torque>, constant_torque<double>, varying_torque<double>>;
  euler_problem<double, G> q;
  if constexpr (is_constant_torque_v<Torque>) {
    q.torque.G = p.torque.value(p.tau0, p.Omega0);
  } else if constexpr (std::is_constructible_v<varying_torque<double>::kinds, const Torque&>) {  // one of its kinds
    q.torque = varying_torque<double>(p.torque);
  } else {
    q.torque = varying_torque<double>(detail::erased_torque<double>(p.torque));
  }
  q.Omega0 = p.Omega0;
  q.tau0 = p.tau0;
  q.form = p.form;
  q.a = p.a;
  return q;
}

// The program's torques are kinds of their own (no virtual call); any other type goes behind one.
static_assert(std::is_constructible_v<varying_torque<double>::kinds, const time_torque<double>&> &&
              std::is_constructible_v<varying_torque<double>::kinds, const state_torque<double>&> &&
              std::is_constructible_v<varying_torque<double>::kinds, const staged_attitude_torque<double>&>);

// Calls cell(std::integral_constant<formulation, F>, std::bool_constant<Attitude>) for the
// formulation f, with the attitude when `attitude` is set. A torque that reads the attitude runs
// only with it (std::invalid_argument otherwise).
template <class Problem, class Cell>
void dispatch_cell(formulation f, const Problem& p, bool attitude, Cell&& cell) {
  const auto with_attitude = [&](auto form) {
    bool reads_attitude = false;
    if constexpr (requires { p.torque.reads_attitude(); }) reads_attitude = p.torque.reads_attitude();
    if (attitude) {
      cell(form, std::true_type{});
    } else {
      if (reads_attitude) throw std::invalid_argument("this torque reads the attitude: its runs carry q (attitude settings)");
      cell(form, std::false_type{});
    }
  };
  switch (f) {
    case formulation::euler: with_attitude(std::integral_constant<formulation, formulation::euler>{}); break;
    case formulation::vop: with_attitude(std::integral_constant<formulation, formulation::vop>{}); break;
    case formulation::vop_theta: with_attitude(std::integral_constant<formulation, formulation::vop_theta>{}); break;
  }
}

}  // namespace detail

// Integrates the problem with formulation `f` and method `m` at fixed step in double. A torque of
// time or state, of any type, runs as a varying_torque (varying_torque.hpp): one driver for all.
template <class Problem>
run_result run_fixed(formulation f, rk::method m, const Problem& p, const fixed_run_settings& s) {
  detail::require_comparison_problem<Problem>();
  if constexpr (!detail::compiled_run_torque<typename Problem::torque_type>) {
    return run_fixed(f, m, detail::as_compiled(p), s);
  } else {
    run_result out;
    out.form = f;
    out.method = m;
    detail::require_normalized(f, p);
    const double tau_end = p.initial_time() + s.h * static_cast<double>(s.n_steps);
    const double bound =
        detail::explosion_bound(p.initial_state(), detail::torque_size(p, tau_end), tau_end, f == formulation::vop);
    detail::dispatch_cell(f, p, s.attitude.has_value(), [&](auto form, auto attitude) {
      detail::run_fixed_cell<Problem, decltype(form)::value, decltype(attitude)::value>(out, m, p, s, bound);
    });
    return out;
  }
}

// Integrates the problem with formulation `f` under error control with the embedded pair of `m`
// (rkf45, dp45 or dop853; std::invalid_argument otherwise), from tau0 to s.tau_end.
template <class Problem>
run_result run_adaptive(formulation f, rk::method m, const Problem& p, const adaptive_run_settings& s) {
  detail::require_comparison_problem<Problem>();
  if constexpr (!detail::compiled_run_torque<typename Problem::torque_type>) {
    return run_adaptive(f, m, detail::as_compiled(p), s);
  } else {
    run_result out;
    out.form = f;
    out.method = m;
    out.adaptive = true;
    detail::require_normalized(f, p);
    const double bound = detail::explosion_bound(p.initial_state(), detail::torque_size(p, s.tau_end), s.tau_end,
                                                 f == formulation::vop);
    detail::dispatch_cell(f, p, s.attitude.has_value(), [&](auto form, auto attitude) {
      detail::run_adaptive_cell<Problem, decltype(form)::value, decltype(attitude)::value>(out, m, p, s, bound);
    });
    return out;
  }
}

// The cells of one torque type G<double> of the runs (kernels/cells.hpp: constant_torque and
// varying_torque): formulation FORM, rates only or with
// the attitude, at a fixed step or under error control. EXTERN is `extern` to declare them, empty
// to define them.
#define EULERVOP_RUN_FIXED_CELL(EXTERN, G, FORM, ATTITUDE)                                                  \
  EXTERN template void detail::run_fixed_cell<euler_problem<double, G<double>>, formulation::FORM, ATTITUDE>(  \
      run_result&, rk::method, const euler_problem<double, G<double>>&, const fixed_run_settings&, double);
#define EULERVOP_RUN_ADAPTIVE_CELL(EXTERN, G, FORM, ATTITUDE)                                                  \
  EXTERN template void detail::run_adaptive_cell<euler_problem<double, G<double>>, formulation::FORM, ATTITUDE>( \
      run_result&, rk::method, const euler_problem<double, G<double>>&, const adaptive_run_settings&, double);
#define EULERVOP_RUN_CELL_(EXTERN, G, FORM, ATTITUDE)  \
  EULERVOP_RUN_FIXED_CELL(EXTERN, G, FORM, ATTITUDE) \
  EULERVOP_RUN_ADAPTIVE_CELL(EXTERN, G, FORM, ATTITUDE)
#define EULERVOP_EXTERN_RUN_CELLS_(G, ...)        \
  EULERVOP_RUN_CELL_(extern, G, euler, false)     \
  EULERVOP_RUN_CELL_(extern, G, vop, false)       \
  EULERVOP_RUN_CELL_(extern, G, vop_theta, false) \
  EULERVOP_RUN_CELL_(extern, G, euler, true)      \
  EULERVOP_RUN_CELL_(extern, G, vop, true)        \
  EULERVOP_RUN_CELL_(extern, G, vop_theta, true)
#ifdef EULERVOP_COMPILED_KERNELS
EULERVOP_KERNEL_RUN_TORQUES(EULERVOP_EXTERN_RUN_CELLS_, )
#endif
#undef EULERVOP_EXTERN_RUN_CELLS_
#undef EULERVOP_RUN_CELL_

}  // namespace eulervop
