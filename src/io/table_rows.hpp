// Rows of numbers under named columns: what `check` reads a trajectory from. A CSV file
// (csv_rows.hpp) is one; arrays held in memory (array_rows.hpp, the Python module's NumPy arrays)
// are another, whose rows are numbered as the lines of the CSV the arrays would make.
#pragma once

#include "compute/scene_library.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eulervop::app {

// The index of the column named `name` in `header` (the first one, if repeated).
inline std::optional<std::size_t> column_in(const std::vector<std::string>& header, std::string_view name) {
  for (std::size_t c = 0; c < header.size(); ++c)
    if (header[c] == name) return c;
  return std::nullopt;
}

class table_rows {
 public:
  virtual ~table_rows() = default;
  virtual const std::vector<std::string>& header() const = 0;
  // The index of the column named `name` (the first one, if repeated).
  std::optional<std::size_t> column(std::string_view name) const { return column_in(header(), name); }
  // Advances to the next row; false after the last one.
  virtual bool next() = 0;
  // The current row's line (1-based; the header is line 1 of a file without '#' lines).
  virtual std::size_t line() const = 0;
  // The current row's cell in column c as a number; input_error naming where() and the line if
  // it is not one.
  virtual decimal number(std::size_t c) const = 0;
  // How messages name the rows: "trajectory run.csv".
  virtual const std::string& where() const = 0;
};

}  // namespace eulervop::app
