// The CSV files eulervop reads (reference files of `eulervop reference`, trajectories for
// `eulervop check`): '#' metadata lines, one header line, then rows of numbers.
//
// csv_rows streams a file row by row (nothing is held but the current row), so a file of any
// size can be read. Every problem is an input_error whose one-line message names the file, the
// line number and, for a cell, the column: a malformed row is never skipped.
#pragma once

#include "compute/scene_library.hpp"
#include "io/table_rows.hpp"

#include <fmt/format.h>

#include <cstddef>
#include <fstream>
#include <istream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eulervop::app {

// The text without leading blanks and trailing blanks or '\r'.
std::string trimmed(std::string_view s);

// The cells of one CSV line, trimmed; empty cells are kept ("1,,2" has three cells).
std::vector<std::string> split_csv_cells(std::string_view line);

// The file opened for reading; input_error "<what> <path>: is a directory" or "...: cannot read the
// file" otherwise.
std::ifstream open_input_file(std::string_view what, const std::string& path);

// "# key: value" -> value (trimmed); nullopt if the line is not that key's metadata.
std::optional<std::string> metadata_value(std::string_view line, std::string_view key);

class csv_rows final : public table_rows {
 public:
  // Reads the '#' lines and blank lines before the header, then the header. `where` names the
  // file in messages ("trajectory run.csv"). input_error if there is no header line.
  csv_rows(std::istream& in, std::string where);

  const std::vector<std::string>& header() const override { return header_; }
  // The '#' lines before the header, verbatim.
  const std::vector<std::string>& comments() const { return comments_; }

  // Advances to the next data row; false at the end of the file. '#' lines are skipped; a
  // blank line or a row with another number of cells than the header is an input_error.
  bool next() override;

  std::size_t line() const override { return line_; }  // 1-based line number of the current row
  const std::string& cell(std::size_t c) const { return cells_[c]; }
  // The cell as a finite decimal; input_error "<where>: line N: column <name> = `text` is not
  // a number" otherwise.
  decimal number(std::size_t c) const override;
  const std::string& where() const override { return where_; }

 private:
  bool read_line(std::string& l);

  std::istream& in_;
  std::string where_;
  std::vector<std::string> header_, comments_, cells_;
  std::string line_text_;
  std::size_t line_ = 0;
};

// A CSV file's rows, with the file they are read from (trajectory files of `check`).
class csv_file_rows final : public table_rows {
 public:
  // input_error "<what> <path>: ..." when the file cannot be read or has no header.
  csv_file_rows(std::string_view what, const std::string& path)
      : in_(open_input_file(what, path)), rows_(in_, fmt::format("{} {}", what, path)) {}
  const std::vector<std::string>& header() const override { return rows_.header(); }
  bool next() override { return rows_.next(); }
  std::size_t line() const override { return rows_.line(); }
  decimal number(std::size_t c) const override { return rows_.number(c); }
  const std::string& where() const override { return rows_.where(); }

 private:
  std::ifstream in_;
  csv_rows rows_;
};

}  // namespace eulervop::app
