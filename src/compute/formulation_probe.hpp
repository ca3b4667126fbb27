// Which formulations a scene takes, and whether each can start from its state, checked before
// anything is computed.
#pragma once

#include "compute/scene_library.hpp"

#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <string>
#include <vector>

namespace eulervop::app {

// Why the paper's VOP does not apply to scene `s` (the coefficient form, or a body integrated in
// the direct form of Eq. 1), so that only euler runs on it; empty where every formulation applies.
std::string euler_only_reason(const scene& s);

// The formulations scene `s` takes: `preferred` (a command's default), or euler alone where the
// paper's VOP does not apply (euler_only_reason).
std::vector<formulation> formulations_for(const scene& s, std::vector<formulation> preferred);

// input_error if `forms`, given by `where` ("--formulations vop"), lists one that scene `s` does
// not take (euler_only_reason), naming it and why.
void require_formulations_apply(const std::vector<formulation>& forms, const scene& s, const std::string& where);

// A formulation that cannot start from this state (the paper's VOP needs k0 < 1) is bad input:
// one step of h with each, on the scene's problem.
void probe_formulations(const std::vector<formulation>& forms, const scene& s, double h);

}  // namespace eulervop::app
