// Rows of binary64 numbers held in memory: a time column and a row-major block of values, as the
// Python module receives NumPy arrays t (n,) and y (n, m). Each number is judged as the binary
// value it is (decimal::binary), never through a decimal text; the time also shows as its
// shortest round-trip text in outputs. Row i counts as line i + 2, the line it would have in the
// CSV file of the same numbers under a header line.
#pragma once

#include "io/table_rows.hpp"

#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace eulervop::app {

class array_rows final : public table_rows {
 public:
  // `header`: the time's name, then one name per column of `values` (rows x (header.size() - 1)).
  // The arrays must outlive the rows.
  array_rows(std::vector<std::string> header, const double* time, const double* values, std::size_t rows,
             std::string where)
      : header_(std::move(header)), time_(time), values_(values), rows_(rows), width_(header_.size() - 1),
        where_(std::move(where)) {}

  const std::vector<std::string>& header() const override { return header_; }
  bool next() override { return ++row_ <= rows_; }
  std::size_t line() const override { return row_ + 1; }
  decimal number(std::size_t c) const override;
  const std::string& where() const override { return where_; }

 private:
  std::vector<std::string> header_;
  const double* time_;
  const double* values_;
  std::size_t rows_, width_;
  std::string where_;
  std::size_t row_ = 0;  // 1-based: the current row is row_ - 1
};

}  // namespace eulervop::app
