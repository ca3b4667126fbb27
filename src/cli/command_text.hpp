// The "# command:" line of a reference file: the command line that made it.
#pragma once

#include <string>

namespace eulervop::app {

// "eulervop" and the arguments after the program name, each shell-quoted when needed, with
// `--out FILE` left out (where the CSV went is not what made it).
std::string command_text(int argc, const char* const* argv);

}  // namespace eulervop::app
