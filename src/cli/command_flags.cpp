#include "cli/command_flags.hpp"

#include "cli/command_line.hpp"
#include "cli/exit_codes.hpp"
#include "compute/ladders.hpp"
#include "compute/run_names.hpp"
#include "io/shell_word.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

namespace eulervop::app {

CLI::Option* add_text_flag(CLI::App& sub, const flag_def& flag, std::optional<std::string>& text) {
  CLI::Option* option =
      sub.add_option_function<std::string>(flag.name, [&text](const std::string& v) { text = v; }, flag.help);
  return option->type_name(flag.value_name);
}

CLI::Option* add_switch(CLI::App& sub, const flag_def& flag, bool& on) {
  return sub.add_flag(flag.name, on, flag.help);
}

void add_required_text_flag(CLI::App& sub, const flag_def& flag, std::optional<std::string>& text) {
  add_text_flag(sub, flag, text)->required();
}

void add_required_positional(CLI::App& sub, const flag_def& arg, std::string& value) {
  sub.add_option(arg.name, value, arg.help)->required()->type_name(arg.value_name);
}

void add_positional_list(CLI::App& sub, const flag_def& arg, std::vector<std::string>& values) {
  sub.add_option(arg.name, values, arg.help)->type_name(arg.value_name);
}

std::string command_line_text(const flag_def& flag, const std::optional<std::string>& text) {
  return text ? fmt::format(" {} {}", flag.name, shell_word(*text)) : "";
}

std::string command_line_text(const flag_def& flag, bool on) { return on ? " " + flag.name : ""; }

void add_output_flags(CLI::App& sub, std::optional<std::string>& out_dir, bool& no_plot, std::string_view command,
                      std::string_view figure) {
  add_text_flag(
      sub, {"--out-dir", "DIR", fmt::format("Output directory (default: ./eulervop-{}/, created if missing)", command)},
      out_dir);
  add_switch(sub, {"--no-plot", "", fmt::format("Do not draw {0}.png/{0}.svg", figure)}, no_plot);
}

// ---- the scene overrides --------------------------------------------------------------------------

namespace override_flags {
const flag_def precision{"--precision", "P", "double | quad | mpfr:BITS (default: the scene's [reference] precision, else quad)"};
const flag_def tau_end{"--tau-end", "T", "End of the span in tau, normalized scenes (default: the scene's tau_end)"};
const flag_def t_end{"--t-end", "T", "End of the span in t: s for physical scenes, t of the coefficient form (default: the scene's t_end)"};
const flag_def times{"--times", "LIST", "Exact sample times t1,t2,... in the scene's time, tau or t (default: the scene's samples or times)"};
const flag_def degree{"--degree", "N", "Chebyshev degree (default: from the precision)"};
const flag_def tolerance{
    "--tolerance", "X",
    "Relative tolerance; each segment's truncation is held to a sixteenth of it (default: from the precision)"};
const flag_def samples{"--samples", "N", ""};
}  // namespace override_flags

void add_scene_override_flags(CLI::App& sub, scene_override_flags& o, scene_override_set which,
                              const std::string& samples_help) {
  if (which.reference) add_text_flag(sub, override_flags::precision, o.precision);
  if (which.span) {
    add_text_flag(sub, override_flags::tau_end, o.tau_end);
    add_text_flag(sub, override_flags::t_end, o.t_end);
  }
  if (which.samples) add_text_flag(sub, override_flags::samples.described(samples_help), o.samples);
  if (which.times) add_text_flag(sub, override_flags::times, o.times);
  if (which.reference) {
    add_text_flag(sub, override_flags::degree, o.degree);
    add_text_flag(sub, override_flags::tolerance, o.tolerance);
  }
}

// ---- the work-precision grid ------------------------------------------------------------------------

void add_grid_flags(CLI::App& sub, grid_flags& f, const grid_flag_defaults& d) {
  add_text_flag(
      sub,
      {"--steps", "LIST",
       fmt::format("Comma-separated fixed steps: K/N (K of the initial modulus) or h (default: {})", d.steps)},
      f.steps);
  add_text_flag(sub,
                {"--tols", "LIST",
                 fmt::format("Comma-separated tolerances of the adaptive runs, atol = rtol (default: {}; with --steps "
                             "alone: none)",
                             default_tol_ladder)},
                f.tols);
  add_text_flag(sub,
                {"--max-step", "S",
                 fmt::format("Largest step of the adaptive runs: K/N or h (default: {})", default_max_step)},
                f.max_step);
  add_text_flag(sub,
                {"--methods", "LIST",
                 "Comma-separated: rk4,rkf45,dp45,rk8 at the fixed steps, rkf45,dp45,dop853 at the tolerances "
                 "(default: all)"},
                f.methods);
  add_text_flag(sub,
                {"--formulations", "LIST", "Comma-separated: " + joined(available_formulations()) + " (default: all)"},
                f.formulations);
  add_text_flag(sub,
                {"--repeat", "N", fmt::format("Timed runs per case; the minimum time is kept (default: {})", d.repeat)},
                f.repeat);
  add_text_flag(sub, {"--jobs", "N", "Cases run in parallel (default: 1; above 1 the timings are less pure)"}, f.jobs);
}

// ---- the program's command line ---------------------------------------------------------------------

namespace {

void add_progress_flags(CLI::App& sub, progress_mode& mode) {
  CLI::Option* on = sub.add_flag_callback(
      "--progress", [&mode] { mode = progress_mode::on; },
      "Show progress on stderr (t or tau reached, segments, time left) even when it is not a terminal or the run is "
      "short (default: on a terminal, after a second)");
  CLI::Option* off = sub.add_flag_callback("--quiet", [&mode] { mode = progress_mode::off; }, "Show no progress on stderr");
  on->excludes(off);
}

// Runs CLI11's parser; the outcome when the program ends here (help, version, bad flags).
std::optional<parsed_command_line> parse(CLI::App& app, const std::string& version, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return parsed_command_line{std::nullopt, app.exit(e), ""};
  } catch (const CLI::CallForAllHelp& e) {
    return parsed_command_line{std::nullopt, app.exit(e), ""};
  } catch (const CLI::CallForVersion&) {
    fmt::print("eulervop {}\n", version);  // CLI11 2.1 prints it without a newline
    return parsed_command_line{std::nullopt, exit_success, ""};
  } catch (const CLI::ParseError& e) {
    return parsed_command_line{std::nullopt, exit_bad_input, e.what()};
  }
  return std::nullopt;
}

}  // namespace

parsed_command_line parse_command_line(const program_def& program, progress_mode& mode, int argc, char** argv) {
  CLI::App app{program.description};
  app.set_version_flag("--version", program.version);
  app.footer(program.footer);
  app.require_subcommand(1);
  std::vector<CLI::App*> subcommands;
  for (const subcommand_def& c : program.subcommands) {
    CLI::App* sub = app.add_subcommand(c.name, c.description);
    c.add_flags(*sub);
    if (c.progress_flags) add_progress_flags(*sub, mode);
    sub->footer(c.footer);
    subcommands.push_back(sub);
  }
  if (std::optional<parsed_command_line> ended = parse(app, program.version, argc, argv)) return *ended;
  for (std::size_t i = 0; i < subcommands.size(); ++i)
    if (subcommands[i]->parsed()) return {i, exit_success, ""};
  return {};
}

}  // namespace eulervop::app
