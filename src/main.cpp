// eulervop: the command-line program.
//
// Exit codes (issue 2, section 6): 0 success; 2 bad input (scene or flags), with exactly one
// line "eulervop: error: <message>" on stderr and no output file; 3 numerical failure, with
// the tau where it happened and why. 1 is left for what should never happen (a bug), except in
// `check`, where 1 means "the trajectory is outside the tolerance" (issue 6, section 1).
// `batch` runs every scene and then exits 2 if any scene had bad input, else 3 if any had a
// numerical failure (batch_command.hpp).
#include "batch_command.hpp"
#include "check_command.hpp"
#include "input_error.hpp"
#include "map_command.hpp"
#include "reference_command.hpp"
#include "report_command.hpp"
#include "sweep_command.hpp"

#include <eulervop/chebyshev_picard.hpp>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <iostream>
#include <string_view>

namespace {

constexpr int exit_bad_input = 2;
constexpr int exit_numerical_failure = 3;
constexpr int exit_internal_error = 1;

int report(int code, const std::string& prefix, const std::string& message) {
  fmt::print(stderr, "eulervop: {}{}\n", prefix, eulervop::app::input_error::one_line(message));
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"eulervop: Euler's equations by variation of parameters, and their high-precision reference"};
  app.set_version_flag("--version", EULERVOP_VERSION);
  app.require_subcommand(1);

  eulervop::app::reference_options reference;
  CLI::App* reference_command = eulervop::app::add_reference_command(app, reference);
  eulervop::app::report_options report_opts;
  CLI::App* report_command = eulervop::app::add_report_command(app, report_opts);
  eulervop::app::sweep_options sweep_opts;
  CLI::App* sweep_command = eulervop::app::add_sweep_command(app, sweep_opts);
  eulervop::app::check_options check_opts;
  CLI::App* check_command = eulervop::app::add_check_command(app, check_opts);
  eulervop::app::batch_options batch_opts;
  CLI::App* batch_command = eulervop::app::add_batch_command(app, batch_opts);
  eulervop::app::map_options map_opts;
  CLI::App* map_command = eulervop::app::add_map_command(app, map_opts);

  // CLI11 would report a mistyped command as "A subcommand is required"; name it instead.
  std::string commands;
  bool known = false;
  for (const CLI::App* c : {reference_command, report_command, sweep_command, check_command, batch_command, map_command}) {
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
    return 0;
  } catch (const CLI::ParseError& e) {
    std::string message = e.what();
    if (message == "A subcommand is required") message += fmt::format(" (expected: {}; see eulervop --help)", commands);
    return report(exit_bad_input, "error: ", message);
  }

  try {
    reference.command = eulervop::app::command_text(argc, argv);
    if (reference_command->parsed()) eulervop::app::run_reference(reference, std::cout);
    if (report_command->parsed()) eulervop::app::run_report(report_opts, std::cout);
    if (sweep_command->parsed()) eulervop::app::run_sweep(sweep_opts, std::cout);
    if (check_command->parsed()) return eulervop::app::run_check(check_opts, std::cout);
    if (batch_command->parsed()) return eulervop::app::run_batch(batch_opts, std::cout);
    if (map_command->parsed()) eulervop::app::run_map(map_opts, std::cout);
    return 0;
  } catch (const eulervop::app::input_error& e) {
    return report(exit_bad_input, "error: ", e.what());
  } catch (const eulervop::numerical_failure& e) {
    return report(exit_numerical_failure, "", e.what());  // "numerical failure at tau=X: why"
  } catch (const std::exception& e) {
    return report(exit_internal_error, "internal error: ", e.what());
  }
}
