// The formulations and methods a user may choose from, by name (the lists of the help and of
// the messages); flags.hpp turns a list of names into values.
#pragma once

#include <string>
#include <vector>

namespace eulervop::app {

// "a, b, c".
std::string joined(const std::vector<std::string>& names);
std::vector<std::string> available_formulations();
std::vector<std::string> available_methods();

}  // namespace eulervop::app
