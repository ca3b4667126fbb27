#include "compute/comparison_runs.hpp"

namespace eulervop {

template run_result run_fixed<euler_problem<double>>(formulation, rk::method, const euler_problem<double>&,
                                                     const fixed_run_settings&);
template run_result run_adaptive<euler_problem<double>>(formulation, rk::method, const euler_problem<double>&,
                                                        const adaptive_run_settings&);

}  // namespace eulervop
