// eulervop: the command-line program.
//
// Exit codes: 0 success; 2 bad input (scene or flags), with exactly one
// line "eulervop: error: <message>" on stderr and no output file; 3 numerical failure, with
// the tau where it happened and why. 1 is left for what should never happen (a bug), except in
// `check`, where 1 means "the trajectory is outside the tolerance".
// `batch` runs every scene and then exits 2 if any scene had bad input, else 3 if any had a
// numerical failure (batch_command.hpp).
#include "program/command_registry.hpp"
#include "cli/command_line.hpp"
#include "cli/command_text.hpp"
#include "cli/exit_codes.hpp"
#include "io/progress_line.hpp"

#include <eulervop/core/numerical_failure.hpp>
#include <eulervop/scene/input_error.hpp>

#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <memory>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace {

namespace ev = eulervop::app;

int report(int code, const std::string& prefix, const std::string& message) {
  fmt::print(stderr, "eulervop: {}{}\n", prefix, eulervop::scene::input_error::one_line(message));
  return code;
}

// Runs the command given, mapping what it throws to an exit code and one line on stderr.
int run(const ev::command& c, const std::string& command_line) {
  try {
    return c.run(std::cout, command_line);
  } catch (const eulervop::scene::input_error& e) {
    return report(ev::exit_bad_input, "error: ", e.what());
  } catch (const eulervop::numerical_failure& e) {
    return report(ev::exit_numerical_failure, "", e.what());  // "numerical failure at tau=X: why"
  } catch (const std::exception& e) {
    return report(ev::exit_internal_error, "internal error: ", e.what());
  }
}

// The program's command line: every command, with --progress and --quiet for those that compute.
ev::program_def program_of(const std::vector<ev::command>& commands) {
  ev::program_def program{"eulervop: Euler's equations by variation of parameters, and their high-precision reference",
                          EULERVOP_VERSION,
                          ev::help_footer("") + "\nEach command's --help lists its flags with their defaults.",
                          {}};
  for (const ev::command& c : commands)
    program.subcommands.push_back({c.name, c.description, ev::help_footer(c.name), c.add_flags, c.computes});
  return program;
}

}  // namespace

int main(int argc, char** argv) {
  // compute/ reports its progress through compute/progress.hpp; on a terminal it is this line
  // (--progress: everywhere; --quiet: nowhere).
  ev::progress_mode mode = ev::progress_mode::automatic;
  ev::set_progress_display([&mode](const std::string& label, double total, const ev::progress_unit& unit) {
    return std::make_unique<ev::progress_line>(label, total, unit, mode);
  });
  const std::vector<ev::command> commands = ev::all_commands();
  std::string names;
  bool known = false;
  for (const ev::command& c : commands) {
    names += (names.empty() ? "" : ", ") + c.name;
    known = known || (argc >= 2 && std::string_view(argv[1]) == c.name);
  }
  // CLI11 would report a mistyped command as "A subcommand is required"; name it instead.
  if (argc >= 2 && argv[1][0] != '-' && !known)
    return report(ev::exit_bad_input, "error: ", fmt::format("unknown command `{}` (expected: {})", argv[1], names));

  const ev::parsed_command_line parsed = ev::parse_command_line(program_of(commands), mode, argc, argv);
  if (!parsed.error.empty()) {
    std::string message = parsed.error;
    if (message == "A subcommand is required") message += fmt::format(" (expected: {}; see eulervop --help)", names);
    return report(parsed.exit_code, "error: ", message);
  }
  if (!parsed.subcommand) return parsed.exit_code;
  return run(commands[*parsed.subcommand], ev::command_text(argc, argv));
}
