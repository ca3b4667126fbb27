// The double-precision runs the program makes (runs/comparison_run.hpp) on its scenes' problems,
// compiled once, in comparison_runs.cpp: the commands that run them do not instantiate the
// Runge-Kutta drivers of every formulation and method again.
#pragma once

#include <eulervop/model/euler_problem.hpp>
#include <eulervop/runs/comparison_run.hpp>

namespace eulervop {

extern template run_result run_fixed<euler_problem<double>>(formulation, rk::method, const euler_problem<double>&,
                                                            const fixed_run_settings&);
extern template run_result run_adaptive<euler_problem<double>>(formulation, rk::method, const euler_problem<double>&,
                                                               const adaptive_run_settings&);

}  // namespace eulervop
