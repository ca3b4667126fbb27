// eulervop: the command-line program.
//
// Exit codes: 0 success; 2 bad input (scene or flags), with exactly one
// line "eulervop: error: <message>" on stderr and no output file; 3 numerical failure, with
// the tau where it happened and why. 1 is left for what should never happen (a bug), except in
// `check`, where 1 means "the trajectory is outside the tolerance".
// `batch` runs every scene and then exits 2 if any scene had bad input, else 3 if any had a
// numerical failure (batch_command.hpp).
#include "commands/batch_command.hpp"
#include "commands/check_command.hpp"
#include "cli/exit_codes.hpp"
#include "commands/map_command.hpp"
#include "commands/reference_command.hpp"
#include "commands/report_command.hpp"
#include "compute/scene_library.hpp"
#include "commands/sweep_command.hpp"

#include <eulervop/reference/integrate.hpp>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <functional>
#include <iostream>
#include <string_view>
#include <utility>
#include <vector>

namespace {

using eulervop::app::exit_bad_input;
using eulervop::app::exit_internal_error;
using eulervop::app::exit_numerical_failure;
using eulervop::app::exit_success;

int report(int code, const std::string& prefix, const std::string& message) {
  fmt::print(stderr, "eulervop: {}{}\n", prefix, eulervop::app::input_error::one_line(message));
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"eulervop: Euler's equations by variation of parameters, and their high-precision reference"};
  app.set_version_flag("--version", EULERVOP_VERSION);
  app.require_subcommand(1);

  namespace ev = eulervop::app;
  ev::reference_options reference;
  ev::report_options report_opts;
  ev::sweep_options sweep_opts;
  ev::check_options check_opts;
  ev::batch_options batch_opts;
  ev::map_options map_opts;
  // Each subcommand with what runs it (reference, report, sweep and map exit 0 unless they throw).
  const std::vector<std::pair<CLI::App*, std::function<int()>>> subcommands = {
      {ev::add_reference_command(app, reference), [&] { return ev::run_reference(reference, std::cout), 0; }},
      {ev::add_report_command(app, report_opts), [&] { return ev::run_report(report_opts, std::cout), 0; }},
      {ev::add_sweep_command(app, sweep_opts), [&] { return ev::run_sweep(sweep_opts, std::cout), 0; }},
      {ev::add_check_command(app, check_opts), [&] { return ev::run_check(check_opts, std::cout); }},
      {ev::add_batch_command(app, batch_opts), [&] { return ev::run_batch(batch_opts, std::cout); }},
      {ev::add_map_command(app, map_opts), [&] { return ev::run_map(map_opts, std::cout), 0; }},
  };

  // CLI11 would report a mistyped command as "A subcommand is required"; name it instead.
  std::string commands;
  bool known = false;
  for (const auto& [c, run] : subcommands) {
    commands += (commands.empty() ? "" : ", ") + c->get_name();
    known = known || (argc >= 2 && std::string_view(argv[1]) == c->get_name());
  }
  if (argc >= 2 && argv[1][0] != '-' && !known)
    return report(exit_bad_input, "error: ", fmt::format("unknown command `{}` (expected: {})", argv[1], commands));

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion&) {
    fmt::print("eulervop {}\n", EULERVOP_VERSION);  // CLI11 2.1 prints it without a newline
    return exit_success;
  } catch (const CLI::ParseError& e) {
    std::string message = e.what();
    if (message == "A subcommand is required") message += fmt::format(" (expected: {}; see eulervop --help)", commands);
    return report(exit_bad_input, "error: ", message);
  }

  try {
    reference.command = eulervop::app::command_text(argc, argv);
    for (const auto& [c, run] : subcommands)
      if (c->parsed()) return run();
    return exit_success;
  } catch (const eulervop::app::input_error& e) {
    return report(exit_bad_input, "error: ", e.what());
  } catch (const eulervop::numerical_failure& e) {
    return report(exit_numerical_failure, "", e.what());  // "numerical failure at tau=X: why"
  } catch (const std::exception& e) {
    return report(exit_internal_error, "internal error: ", e.what());
  }
}
