// Whether each formulation can start from a scene's state, checked before anything is computed.
#pragma once

#include "compute/scene_library.hpp"

#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <vector>

namespace eulervop::app {

// A formulation that cannot start from this state (the paper's VOP needs k0 < 1) is bad input:
// one step of h with each, on the scene's problem.
void probe_formulations(const std::vector<formulation>& forms, const scene& s, double h);

}  // namespace eulervop::app
