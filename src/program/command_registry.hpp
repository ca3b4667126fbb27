// Every command of the program: its name and description, its flags (bound to the command's own
// options) and what runs it. main() offers them in this order and runs the one given.
#pragma once

#include "cli/cli11_fwd.hpp"

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace eulervop::app {

struct command {
  std::string name;
  std::string description;
  std::function<void(CLI::App& sub)> add_flags;
  // With the flags parsed: runs the command and returns its exit code. `command_line` is the
  // invocation as command_text states it.
  std::function<int(std::ostream& standard_output, const std::string& command_line)> run;
  bool computes = true;  // takes --progress and --quiet
};

// reference, report, sweep, check, batch, map, scene-template.
std::vector<command> all_commands();

// The end of a command's --help: where the scene format and the command's own page are.
std::string help_footer(const std::string& command);

}  // namespace eulervop::app
