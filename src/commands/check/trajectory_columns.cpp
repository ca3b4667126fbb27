#include "commands/check/trajectory_columns.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <vector>

namespace eulervop::app {

namespace {

// The file's name for a canonical column. (q0..q3 are canonical names only once --columns knows
// them; until then they are looked up as they are.)
std::string file_name(const check_job& job, const std::string& canonical) {
  const auto it = job.columns.file.find(canonical);
  return it == job.columns.file.end() ? canonical : it->second;
}

bool renamed(const check_job& job, const std::string& canonical) {
  const auto it = job.columns.renamed.find(canonical);
  return it != job.columns.renamed.end() && it->second;
}

std::string column_label(const check_job& job, const std::string& canonical) {
  return renamed(job, canonical) ? fmt::format("`{}` (for {} by --columns)", file_name(job, canonical), canonical)
                                 : fmt::format("`{}`", canonical);
}

// q0..q3: all four, or none (and none renamed by --columns).
std::optional<std::array<std::size_t, 4>> find_attitude(const check_job& job, const table_rows& rows,
                                                        const std::string& where) {
  std::array<std::optional<std::size_t>, 4> found;
  std::optional<int> present;  // the first of q0..q3 the header has
  bool asked = false;          // some renamed by --columns
  for (int k = 0; k < 4; ++k) {
    const std::string canonical = fmt::format("q{}", k);
    found[k] = rows.column(file_name(job, canonical));
    if (found[k] && !present) present = k;
    asked = asked || renamed(job, canonical);
  }
  if (!present && !asked) return std::nullopt;
  std::array<std::size_t, 4> q{};
  for (int k = 0; k < 4; ++k) {
    if (!found[k]) {
      const std::string missing = column_label(job, fmt::format("q{}", k));
      if (!present) throw input_error(fmt::format("{}: the header has no column {}", where, missing));
      throw input_error(fmt::format("{}: the header has no column {} (column {} is there: an attitude needs q0..q3)",
                                    where, missing, column_label(job, fmt::format("q{}", *present))));
    }
    q[k] = *found[k];
  }
  return q;
}

// A header without the names it needs: what it has, and the --columns that maps its first
// columns (the time, if `time` is not given, then the state) to the names of `expected` (the
// state `state`, whose time is then `time`). A user's file with its own names ("time,w1,w2,w3")
// is told the flag, not only the name that is missing.
std::string columns_hint(const table_rows& rows, const expected_names& expected, std::optional<std::size_t> time,
                         const std::string& state) {
  const std::vector<std::string>& header = rows.header();
  constexpr std::size_t shown = 8;
  std::string names;
  for (std::size_t k = 0; k < header.size() && k < shown; ++k) names += (k ? ", " : "") + header[k];
  if (header.size() > shown) names += ", ...";
  std::vector<std::string> wanted;  // the names missing, in order: the time (if missing), then the state
  if (!time) wanted.push_back(expected.time);
  for (int k = 1; k <= 3; ++k) wanted.push_back(fmt::format("{}{}", state, k));
  std::vector<std::size_t> free;  // the columns other than the time
  for (std::size_t k = 0; k < header.size(); ++k)
    if (!time || k != *time) free.push_back(k);
  std::vector<std::string> mapping;
  for (std::size_t k = 0; k < wanted.size(); ++k)
    if (free.size() < wanted.size())
      mapping.push_back(wanted[k] + "=NAME");
    else if (header[free[k]] != wanted[k])
      mapping.push_back(fmt::format("{}={}", wanted[k], header[free[k]]));
  return fmt::format("; the header has {}: map them with --columns {}{}", names, fmt::join(mapping, ","),
                     free.size() < wanted.size() ? "" : " (for example)");
}

bool any_renamed(const check_job& job) {
  for (const auto& [canonical, renamed] : job.columns.renamed)
    if (renamed) return true;
  return false;
}

}  // namespace

trajectory_columns find_columns(const check_job& job, const table_rows& rows, const expected_names& expected) {
  trajectory_columns c;
  const std::string where = fmt::format("{}: line {}", rows.where(), rows.line());
  // With --columns given, the message names what it mapped; without, it names the flag.
  const bool hint = !any_renamed(job);
  if (auto tau = rows.column(job.columns.file.at("tau"))) {
    c.time = *tau;
  } else if (auto t = rows.column(job.columns.file.at("t"))) {
    c.physical = true;
    c.time = *t;
  } else {
    throw input_error(fmt::format("{}: the header has no column {} (nor {} for a physical or coefficient-form scene){}",
                                  where, column_label(job, "tau"), column_label(job, "t"),
                                  hint ? columns_hint(rows, expected, std::nullopt, expected.state) : ""));
  }
  c.time_name = rows.header()[c.time];
  if (c.physical)
    c.state = !rows.column(job.columns.file.at("omega1")) && rows.column(job.columns.file.at("y1")) ? "y" : "omega";
  for (int k = 0; k < 3; ++k) {
    const std::string canonical = fmt::format("{}{}", c.state, k + 1);
    const auto col = rows.column(job.columns.file.at(canonical));
    if (!col) {
      // The state the reference expects, unless the time says otherwise (tau has Omega only).
      const std::string state = c.physical == (expected.time == "t") ? expected.state : c.state;
      throw input_error(fmt::format("{}: the header has no column {}{}", where, column_label(job, canonical),
                                    hint ? columns_hint(rows, expected, c.time, state) : ""));
    }
    c.value[k] = *col;
  }
  c.q = find_attitude(job, rows, where);
  return c;
}

void require_attitude_match(const check_job& job, const trajectory_columns& cols, const table_rows& rows,
                            bool reference_has_attitude, const std::string& reference, const std::string& why) {
  if (cols.q && !reference_has_attitude)
    throw input_error(fmt::format("{}: line {}: columns q0..q3: {} has no attitude ({})", rows.where(), rows.line(),
                                  reference, why));
  if (!cols.q && job.attitude_tol)
    throw input_error(fmt::format("--attitude-tol {}: {} has no columns q0..q3 (no attitude to check)",
                                  *job.attitude_tol, rows.where()));
  if (!cols.q && job.ignore_attitude)
    throw input_error(fmt::format("--ignore-attitude: {} has no columns q0..q3 (no attitude to ignore)", rows.where()));
  // No silent pass: a verdict on the rates alone would pass a trajectory whose attitude is wrong.
  if (cols.q && (job.tol || job.rel_tol) && !job.attitude_tol && !job.ignore_attitude)
    throw input_error(fmt::format("--attitude-tol: required, since {} has columns q0..q3 (give --attitude-tol RAD, "
                                  "or --ignore-attitude to judge the rates alone)",
                                  rows.where()));
}

compared_terms terms_of(const trajectory_columns& cols, bool physical_scene, bool normalized_apart) {
  compared_terms terms;
  for (int k = 0; k < 3; ++k) terms.components[k] = fmt::format("{}{}", cols.state, k + 1);
  if (cols.physical && physical_scene) {
    terms.time_unit = "s";
    terms.state_unit = "rad/s";
  }
  terms.normalized_apart = normalized_apart;
  return terms;
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

std::array<decimal, 4> row_reader::attitude() const {
  const std::array<std::size_t, 4>& c = *cols.q;
  const std::array<decimal, 4> q = {rows.number(c[0]), rows.number(c[1]), rows.number(c[2]), rows.number(c[3])};
  if (q[0].value == 0 && q[1].value == 0 && q[2].value == 0 && q[3].value == 0)
    throw input_error(fmt::format("{}: line {}: columns {}..{} are all 0, which is no attitude", rows.where(),
                                  rows.line(), rows.header()[c[0]], rows.header()[c[3]]));
  return q;
}

}  // namespace eulervop::app
