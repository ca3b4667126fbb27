// The values of the command-line flags, parsed and validated in one place: numbers and whole
// numbers, the precision and the tolerance, lists and ladders (--tols, --steps, --max-step,
// --levels, --torque-scales, --times), the names of formulations and methods, --format, --shard
// and --columns.
//
// The flags are kept as the user's text until the command applies them, so every message quotes
// it: each problem is an input_error (exit 2, one line) naming the flag and its value.
#pragma once

#include "compute/ladders.hpp"
#include "compute/scene_library.hpp"
#include "compute/step_rule.hpp"

#include <eulervop/core/precision.hpp>
#include <eulervop/rk/tableaux.hpp>
#include <eulervop/runs/formulation.hpp>
#include <eulervop/runs/run_result.hpp>
#include <eulervop/runs/settings.hpp>

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eulervop::app {

// ---- numbers and choices ---------------------------------------------------------------------

decimal flag_number(std::string_view flag, const std::string& text);
decimal positive_flag_number(std::string_view flag, const std::string& text);
// A bar such as --tol: a number >= 0, or none when the flag is not given.
std::optional<double> non_negative_flag(std::string_view flag, const std::optional<std::string>& text);
std::int64_t flag_integer(std::string_view flag, const std::string& text, std::int64_t lo, std::int64_t hi);
// --precision: double | quad | mpfr:BITS.
eulervop::precision flag_precision(const std::string& text);
// --tolerance of the reference integrator: relative, so in (0, 1).
double flag_tolerance(const std::string& text);
// --format table (the default) or json: true for json.
bool flag_json_format(const std::optional<std::string>& text);

// ---- lists and ladders -------------------------------------------------------------------------

// "a,b,c": the items, none empty.
std::vector<std::string> flag_list(std::string_view flag, const std::string& text);
// "1e-4,1e-6,1e-8": positive finite numbers, strictly increasing or strictly decreasing (a
// ladder); the message names the offending item.
std::vector<decimal> flag_ladder(std::string_view flag, const std::string& text);
// A ladder of tolerances (--tols): each also below 1.
std::vector<ladder_tol> tol_ladder(const std::string& flag, const std::string& text);
// A ladder of error levels (--levels of `map`): each also below 1.
std::vector<double> level_ladder(const std::string& text);
// --times t1,t2,...: strictly increasing, in [0, span_end] (`span_name` = "tau_end" or "t_end").
std::vector<decimal> flag_times(const std::string& text, const decimal& span_end, std::string_view span_name);

// ---- formulations and methods ----------------------------------------------------------------------

// --formulations, else the scene's [run] formulations, else `fallback`: an unknown or repeated
// name is an input_error naming the list.
std::vector<formulation> chosen_formulations(const std::optional<std::string>& flag,
                                             const std::vector<std::string>& scene_list,
                                             std::vector<formulation> fallback);
// --methods, else the scene's [run] methods, else `fallback`. Each listed method must run on one
// of the ladders present: a fixed-step method on the `steps`, an adaptive one on the `tols`.
std::vector<rk::method> chosen_methods(const std::optional<std::string>& flag,
                                       const std::vector<std::string>& scene_list, std::vector<rk::method> fallback,
                                       bool steps, bool tols);

// ---- steps ---------------------------------------------------------------------------------------

// "K/N" (whole N >= 1) or a positive number; input_error "FLAG TEXT: why".
step_spec flag_step(const std::string& flag, const std::string& text);
// The fixed step of `report`: --step, else the scene's [run] step, else K/default_K_divisor,
// resolved for `s`.
fixed_step_choice fixed_step_of(const scene& s, const std::optional<std::string>& flag, std::int64_t default_K_divisor);
// The fixed steps "K/N" or plain numbers of a ladder (`flag` names the source in messages; with
// `from_default` the texts are the default ladder's), each resolved for `s`, none listed twice,
// with about `samples` error samples each.
std::vector<ladder_step> step_ladder(const scene& s, const std::vector<std::string>& texts, const std::string& flag,
                                     bool from_default, std::size_t samples);
// The adaptive runs' largest step: --max-step "K/N" or a number in the scene's time variable;
// without it K/2, or the span where K is undefined at the initial state (Omega = 0 or k0 = 1).
max_step_choice max_step_of(const scene& s, const std::optional<std::string>& flag);

// ---- batch and check -------------------------------------------------------------------------------

// --shard I/N of `batch`: share I of N, 1 <= I <= N.
struct shard_spec {
  std::int64_t index = 1, count = 1;
};
shard_spec flag_shard(const std::string& text);

// --columns tau=time,Omega1=w1,... of `check`: the trajectory's column for each canonical name
// (tau, Omega1..3, t, omega1..3, y1..3, q0..3), and whether --columns renamed it.
struct column_names {
  std::map<std::string, std::string> file;  // canonical -> the file's column name
  std::map<std::string, bool> renamed;
};
column_names flag_columns(const std::optional<std::string>& text);

}  // namespace eulervop::app
