// The formulations and methods a command runs, by name: the lists a user may choose from, and
// the parsing of a list ("--formulations euler,vop", "[run] methods") into values.
#pragma once

#include <eulervop/runs/comparison_run.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/rk/explicit_rk.hpp>

#include <string>
#include <vector>

namespace eulervop::app {

std::string joined(const std::vector<std::string>& names);
std::vector<std::string> available_formulations();
std::vector<std::string> available_methods();

// Names -> values; input_error naming `where` ("--formulations euler,foo", "[run] formulations")
// for an unknown or repeated name, followed by `hint`.
std::vector<formulation> formulations_of(const std::vector<std::string>& names, const std::string& where,
                                         const std::string& hint);
std::vector<rk::method> methods_of(const std::vector<std::string>& names, const std::string& where,
                                   const std::string& hint);

// A formulation that cannot start from this state (the paper's VOP needs k0 < 1) is bad input:
// one step of each, before anything is computed.
void probe_formulations(const std::vector<formulation>& forms, const euler_problem<double>& problem, double h);

}  // namespace eulervop::app
