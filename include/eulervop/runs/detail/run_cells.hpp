// The cells of the double-precision runs (comparison_run.hpp): one formulation, at a fixed step
// or under error control, rates only or with the attitude. Each cell is one function template,
// so the compiled kernels (kernels/cells.hpp) hold each in a unit of its own, and a torque type
// instantiates only the cells it is run in.
#pragma once

#include <eulervop/model/torque.hpp>
#include <eulervop/rk/embedded_pairs.hpp>
#include <eulervop/rk/method.hpp>
#include <eulervop/rk/tableaux.hpp>
#include <eulervop/runs/detail/euler_runs.hpp>
#include <eulervop/runs/detail/vop_adaptive_run.hpp>
#include <eulervop/runs/detail/vop_fixed_run.hpp>
#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

namespace eulervop::detail {

// Formulation F at the fixed step of `s` with method `m`; the attitude beside the rates when
// Attitude is set.
template <class Problem, formulation F, bool Attitude>
void run_fixed_cell(run_result& out, rk::method m, const Problem& p, const fixed_run_settings& s, double bound) {
  if constexpr (F == formulation::euler) {
    run_euler_fixed<Problem, Attitude>(out, p, s, bound);
  } else {
    rk::dispatch_method(m, [&](auto tag) {
      vop_fixed_run<decltype(tag), F == formulation::vop_theta, Problem, Attitude>(out, p, s, bound)();
    });
  }
}

// Formulation F under error control with the embedded pair of `m`.
template <class Problem, formulation F, bool Attitude>
void run_adaptive_cell(run_result& out, rk::method m, const Problem& p, const adaptive_run_settings& s,
                       double bound) {
  rk::dispatch_pair(m, [&](auto pair) {
    using Pair = decltype(pair);
    if constexpr (F == formulation::euler)
      run_euler_adaptive<Pair, Problem, Attitude>(out, p, s, bound);
    else
      vop_adaptive_run<Pair, F == formulation::vop_theta, Problem, Attitude>(out, p, s, bound)();
  });
}

}  // namespace eulervop::detail
