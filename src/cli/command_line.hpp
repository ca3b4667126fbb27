// The program's command line: its commands, each with its flags, parsed from argv (main.cpp). The
// parsing is in command_flags.cpp, the one unit that includes CLI11's header (its parsing and code
// generation cost about 8 s of compile time in every unit that includes it).
#pragma once

#include "cli/cli11_fwd.hpp"
#include "io/progress_line.hpp"

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace eulervop::app {

struct subcommand_def {
  std::string name;
  std::string description;
  std::string footer;  // the end of its --help
  std::function<void(CLI::App& sub)> add_flags;
  bool progress_flags = true;  // --progress and --quiet, which set the progress_mode
};

struct program_def {
  std::string description;
  std::string version;  // --version prints "eulervop <version>"
  std::string footer;
  std::vector<subcommand_def> subcommands;  // exactly one is required
};

// Where parsing the command line ended: the index of the subcommand given (its flags parsed), or
// an exit code: help or the version shown (exit_success), or bad flags, with CLI11's message in
// `error` for the caller to report (exit_bad_input).
struct parsed_command_line {
  std::optional<std::size_t> subcommand;
  int exit_code = 0;
  std::string error;
};

parsed_command_line parse_command_line(const program_def& program, progress_mode& mode, int argc, char** argv);

}  // namespace eulervop::app
