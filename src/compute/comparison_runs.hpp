// The double-precision runs the program makes (runs/comparison_run.hpp) on its scenes' problems,
// compiled once, in comparison_runs.cpp, for each kind of torque (constant, of time, of time and
// state): the commands that run them do not instantiate the Runge-Kutta drivers of every
// formulation and method again.
#pragma once

#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/expression_torque.hpp>
#include <eulervop/runs/comparison_run.hpp>

#define EULERVOP_COMPARISON_RUNS(EXTERN, G)                                                                       \
  EXTERN template run_result run_fixed<euler_problem<double, G>>(formulation, rk::method,                        \
                                                                 const euler_problem<double, G>&,               \
                                                                 const fixed_run_settings&);                    \
  EXTERN template run_result run_adaptive<euler_problem<double, G>>(formulation, rk::method,                     \
                                                                    const euler_problem<double, G>&,            \
                                                                    const adaptive_run_settings&);

namespace eulervop {

EULERVOP_COMPARISON_RUNS(extern, constant_torque<double>)
EULERVOP_COMPARISON_RUNS(extern, time_torque<double>)
EULERVOP_COMPARISON_RUNS(extern, state_torque<double>)

}  // namespace eulervop
