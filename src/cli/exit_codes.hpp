// The exit codes of every subcommand (documented in the README, "Command line").
#pragma once

namespace eulervop::app {

inline constexpr int exit_success = 0;
inline constexpr int exit_internal_error = 1;     // a bug: the message says "internal error"
inline constexpr int exit_bad_input = 2;          // a bad flag, scene or file: one line naming it
inline constexpr int exit_numerical_failure = 3;  // the computation failed: where (tau) and why
// `check` only: every row within the bar (exit_success), or some row outside it.
inline constexpr int exit_check_outside = 1;

}  // namespace eulervop::app
