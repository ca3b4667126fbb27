#include "commands/check/trajectory_columns.hpp"

#include <fmt/format.h>

namespace eulervop::app {

namespace {

std::string column_label(const check_job& job, const std::string& canonical) {
  return job.columns.renamed.at(canonical)
             ? fmt::format("`{}` (for {} by --columns)", job.columns.file.at(canonical), canonical)
             : fmt::format("`{}`", canonical);
}

}  // namespace

trajectory_columns find_columns(const check_job& job, const csv_rows& rows) {
  trajectory_columns c;
  const std::string where = fmt::format("{}: line {}", rows.where(), rows.line());
  if (auto tau = rows.column(job.columns.file.at("tau"))) {
    c.time = *tau;
  } else if (auto t = rows.column(job.columns.file.at("t"))) {
    c.physical = true;
    c.time = *t;
  } else {
    throw input_error(fmt::format("{}: the header has no column {} (nor {} for a physical or coefficient-form scene)", where,
                                  column_label(job, "tau"), column_label(job, "t")));
  }
  c.time_name = rows.header()[c.time];
  if (c.physical)
    c.state = !rows.column(job.columns.file.at("omega1")) && rows.column(job.columns.file.at("y1")) ? "y" : "omega";
  for (int k = 0; k < 3; ++k) {
    const std::string canonical = fmt::format("{}{}", c.state, k + 1);
    const auto col = rows.column(job.columns.file.at(canonical));
    if (!col) throw input_error(fmt::format("{}: the header has no column {}", where, column_label(job, canonical)));
    c.value[k] = *col;
  }
  return c;
}

decimal row_reader::time() {
  const decimal x = rows.number(cols.time);
  if (x.value < 0)
    throw input_error(fmt::format("{}: line {}: column {} = {} is negative (the reference starts at 0)", rows.where(),
                                  rows.line(), cols.time_name, x.text));
  if (previous && !(x.value > previous->value))
    throw input_error(fmt::format("{}: line {}: column {} = {} does not increase (line {} has {})", rows.where(),
                                  rows.line(), cols.time_name, x.text, previous_line, previous->text));
  previous = x;
  previous_line = rows.line();
  return x;
}

std::array<decimal, 3> row_reader::values() const {
  return {rows.number(cols.value[0]), rows.number(cols.value[1]), rows.number(cols.value[2])};
}

}  // namespace eulervop::app
