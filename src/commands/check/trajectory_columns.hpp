// The trajectory `check` reads: its columns, found by name (tau and Omega1..3, t and omega1..3,
// or t and y1..3 for the coefficient form; --columns renames), and its rows, each checked as it
// is read.
#pragma once

#include "commands/check/check_job.hpp"
#include "compute/scene_library.hpp"
#include "io/csv_rows.hpp"

#include <array>
#include <cstddef>
#include <optional>
#include <string>

namespace eulervop::app {

struct trajectory_columns {
  bool physical = false;        // the time is t (omega1..3, or y1..3)
  std::string state = "Omega";  // the state's name: Omega, omega or y
  std::size_t time = 0;
  std::array<std::size_t, 3> value{};
  std::string time_name;  // as in the file
};

// The columns of the header of `rows`; input_error naming the missing one otherwise.
trajectory_columns find_columns(const check_job& job, const csv_rows& rows);

// A trajectory row: its time and state, checked (numbers, time >= 0 and increasing).
struct row_reader {
  csv_rows& rows;
  const trajectory_columns& cols;
  std::optional<decimal> previous;
  std::size_t previous_line = 0;

  decimal time();
  std::array<decimal, 3> values() const;
};

}  // namespace eulervop::app
