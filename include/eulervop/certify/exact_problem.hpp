// The exact data of a certificate's setup: Eq. 5's problem with G and Omega(0) the intervals of
// decimals as written (MPFI's mpfi_set_str: "0.1" means one tenth, not its binary neighbour). A
// scene's exact problem is in scene/scene_exact_problem.hpp.
#pragma once

#include <eulervop/certify/interval.hpp>
#include <eulervop/model/euler_problem.hpp>

namespace eulervop {

// Eq. 5 (or Eq. 1) with a constant torque, in intervals.
using exact_problem = euler_problem<interval>;

}  // namespace eulervop
