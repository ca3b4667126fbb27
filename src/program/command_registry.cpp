#include "program/command_registry.hpp"

#include "commands/batch/batch_command.hpp"
#include "commands/check/check_command.hpp"
#include "commands/map/map_command.hpp"
#include "commands/reference/reference_command.hpp"
#include "commands/report/report_command.hpp"
#include "commands/scene_template/scene_template_command.hpp"
#include "commands/sweep/sweep_command.hpp"

#include <map>
#include <memory>
#include <string>

namespace eulervop::app {

namespace {

// A command whose options live as long as the command: its flags are bound to them, and
// run(options, standard_output, command_line) reads them.
template <class Options, class Run>
command command_of(std::string name, std::string description, void (*add_flags)(CLI::App&, Options&), Run run) {
  const auto options = std::make_shared<Options>();
  return {
      std::move(name), std::move(description), [options, add_flags](CLI::App& sub) { add_flags(sub, *options); },
      [options, run](std::ostream& out, const std::string& command_line) { return run(*options, out, command_line); }};
}

// The run of a command that has no use for its command line.
template <class Options>
auto without_command_line(int (*run)(const Options&, std::ostream&)) {
  return [run](Options& o, std::ostream& out, const std::string&) { return run(o, out); };
}

// `reference` writes its command line into the file ("# command:").
int run_reference_of(reference_options& o, std::ostream& out, const std::string& command_line) {
  o.command = command_line;
  return run_reference(o, out);
}

}  // namespace

std::vector<command> all_commands() {
  std::vector<command> commands = {
      command_of<reference_options>("reference", "Compute the high-precision reference solution as CSV",
                                    add_reference_flags, run_reference_of),
      command_of<report_options>(
          "report",
          "Run Euler and VOP in double at a fixed step or under error control; Eq. 20 errors, summary and Fig. 1",
          add_report_flags, without_command_line(run_report)),
      command_of<sweep_options>("sweep",
                                "Work against precision: every formulation x method x fixed step and tolerance, timed "
                                "and measured against one reference",
                                add_sweep_flags, without_command_line(run_sweep)),
      command_of<check_options>(
          "check", "Check another tool's trajectory (CSV) against the reference: Eq. 20 errors, pass/fail by tolerance",
          add_check_flags, without_command_line(run_check)),
      command_of<batch_options>("batch", "Run `reference` (and optionally `report`) for many scenes", add_batch_flags,
                                without_command_line(run_batch)),
      command_of<map_options>("map",
                              "Where VOP pays: the scene's torque scaled, every formulation x method x step and "
                              "tolerance, the cheapest per error level and VOP's speed-up over Euler",
                              add_map_flags, without_command_line(run_map)),
  };
  command scene_template = command_of<scene_template_options>(
      "scene-template", "Print an annotated scene (normalized, physical or coefficient form) to start one from",
      add_scene_template_flags, without_command_line(run_scene_template));
  scene_template.computes = false;
  commands.push_back(std::move(scene_template));
  return commands;
}

std::string help_footer(const std::string& command) {
  static const std::map<std::string, std::string> pages = {
      {"reference", "docs/reference.md"}, {"report", "docs/command-line.md"}, {"sweep", "docs/sweep.md"},
      {"check", "docs/check.md"},         {"batch", "docs/batch.md"},         {"map", "docs/regime-map.md"},
      {"scene-template", "docs/scenes.md"}};
  const auto page = pages.find(command);
  return "\nScenes are TOML files: `eulervop scene-template physical` (or normalized, coefficient) prints one with "
         "every key explained, pieces, formulas and the attitude q with its convention included; the format is "
         "docs/scenes.md." +
         (page == pages.end() ? std::string() : " This command: " + page->second + ".") +
         "\nExit codes: 0 success, 2 bad input (one line on stderr), 3 numerical failure" +
         (command == "check" ? ", 1 outside the tolerance." : ".");
}

}  // namespace eulervop::app
