// eulervop: the command-line program.
//
// Exit codes: 0 success; 2 bad input (scene or flags), with exactly one
// line "eulervop: error: <message>" on stderr and no output file; 3 numerical failure, with
// the tau where it happened and why. 1 is left for what should never happen (a bug), except in
// `check`, where 1 means "the trajectory is outside the tolerance".
// `batch` runs every scene and then exits 2 if any scene had bad input, else 3 if any had a
// numerical failure (batch_command.hpp).
#include "program/command_registry.hpp"
#include "cli/command_text.hpp"
#include "cli/exit_codes.hpp"
#include "compute/scene_library.hpp"
#include "io/progress_line.hpp"

#include <eulervop/core/numerical_failure.hpp>

#include <CLI/CLI.hpp>
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
  fmt::print(stderr, "eulervop: {}{}\n", prefix, ev::input_error::one_line(message));
  return code;
}

// Parses the command line; an exit code when the program ends here (help, version, bad flags).
std::optional<int> parse(CLI::App& app, int argc, char** argv, const std::string& commands) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion&) {
    fmt::print("eulervop {}\n", EULERVOP_VERSION);  // CLI11 2.1 prints it without a newline
    return ev::exit_success;
  } catch (const CLI::ParseError& e) {
    std::string message = e.what();
    if (message == "A subcommand is required") message += fmt::format(" (expected: {}; see eulervop --help)", commands);
    return report(ev::exit_bad_input, "error: ", message);
  }
  return std::nullopt;
}

// Runs the command given, mapping what it throws to an exit code and one line on stderr.
int run(const ev::command& c, const std::string& command_line) {
  try {
    return c.run(std::cout, command_line);
  } catch (const ev::input_error& e) {
    return report(ev::exit_bad_input, "error: ", e.what());
  } catch (const eulervop::numerical_failure& e) {
    return report(ev::exit_numerical_failure, "", e.what());  // "numerical failure at tau=X: why"
  } catch (const std::exception& e) {
    return report(ev::exit_internal_error, "internal error: ", e.what());
  }
}

// --progress and --quiet, which every command takes.
void add_progress_flags(CLI::App& sub, ev::progress_mode& mode) {
  CLI::Option* on = sub.add_flag_callback(
      "--progress", [&mode] { mode = ev::progress_mode::on; },
      "Show progress on stderr (t or tau reached, segments, time left) even when it is not a terminal or the run is "
      "short (default: on a terminal, after a second)");
  CLI::Option* off =
      sub.add_flag_callback("--quiet", [&mode] { mode = ev::progress_mode::off; }, "Show no progress on stderr");
  on->excludes(off);
}

}  // namespace

int main(int argc, char** argv) {
  // compute/ reports its progress through compute/progress.hpp; on a terminal it is this line
  // (--progress: everywhere; --quiet: nowhere).
  ev::progress_mode mode = ev::progress_mode::automatic;
  ev::set_progress_display([&mode](const std::string& label, double total, const ev::progress_unit& unit) {
    return std::make_unique<ev::progress_line>(label, total, unit, mode);
  });
  CLI::App app{"eulervop: Euler's equations by variation of parameters, and their high-precision reference"};
  app.set_version_flag("--version", EULERVOP_VERSION);
  app.footer(ev::help_footer("") + "\nEach command's --help lists its flags with their defaults.");
  app.require_subcommand(1);

  const std::vector<ev::command> commands = ev::all_commands();
  std::vector<CLI::App*> subcommands;
  std::string names;
  bool known = false;
  for (const ev::command& c : commands) {
    CLI::App* sub = app.add_subcommand(c.name, c.description);
    c.add_flags(*sub);
    if (c.computes) add_progress_flags(*sub, mode);
    sub->footer(ev::help_footer(c.name));
    subcommands.push_back(sub);
    names += (names.empty() ? "" : ", ") + c.name;
    known = known || (argc >= 2 && std::string_view(argv[1]) == c.name);
  }
  // CLI11 would report a mistyped command as "A subcommand is required"; name it instead.
  if (argc >= 2 && argv[1][0] != '-' && !known)
    return report(ev::exit_bad_input, "error: ", fmt::format("unknown command `{}` (expected: {})", argv[1], names));

  if (const std::optional<int> code = parse(app, argc, argv, names)) return *code;
  for (std::size_t i = 0; i < commands.size(); ++i)
    if (subcommands[i]->parsed()) return run(commands[i], ev::command_text(argc, argv));
  return ev::exit_success;
}
