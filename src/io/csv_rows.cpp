#include "io/csv_rows.hpp"

#include "compute/scene_library.hpp"

#include <fmt/format.h>

#include <filesystem>

namespace eulervop::app {

std::string trimmed(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return std::string(s);
}

std::vector<std::string> split_csv_cells(std::string_view l) {
  std::vector<std::string> cells;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = l.find(',', begin);
    cells.push_back(trimmed(l.substr(begin, comma == std::string_view::npos ? std::string_view::npos : comma - begin)));
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  return cells;
}

std::ifstream open_input_file(std::string_view what, const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw input_error(fmt::format("{} {}: is a directory", what, path));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw input_error(fmt::format("{} {}: cannot read the file", what, path));
  return in;
}

std::optional<std::string> metadata_value(std::string_view line, std::string_view key) {
  const std::string prefix = fmt::format("# {}:", key);
  if (!line.starts_with(prefix)) return std::nullopt;
  return trimmed(line.substr(prefix.size()));
}

csv_rows::csv_rows(std::istream& in, std::string where) : in_(in), where_(std::move(where)) {
  for (std::string l; read_line(l);) {
    if (l.starts_with("#")) {
      comments_.push_back(l);
      continue;
    }
    if (trimmed(l).empty()) continue;
    header_ = split_csv_cells(l);
    for (std::size_t c = 0; c < header_.size(); ++c)
      if (header_[c].empty()) throw input_error(fmt::format("{}: line {}: header cell {} is empty", where_, line_, c + 1));
    return;
  }
  throw input_error(fmt::format("{}: no header line (the file is empty or has only '#' lines)", where_));
}

bool csv_rows::read_line(std::string& l) {
  if (!std::getline(in_, l)) {
    if (in_.bad()) throw input_error(fmt::format("{}: read error after line {}", where_, line_));
    return false;
  }
  ++line_;
  if (!l.empty() && l.back() == '\r') l.pop_back();
  return true;
}

namespace {
// The cells of one CSV line into `cells`, trimmed, reusing their storage (a row of a large file
// would allocate every cell anew otherwise).
void split_into(std::string_view l, std::vector<std::string>& cells) {
  std::size_t n = 0, begin = 0;
  while (true) {
    const std::size_t comma = l.find(',', begin);
    std::string_view cell = l.substr(begin, comma == std::string_view::npos ? std::string_view::npos : comma - begin);
    while (!cell.empty() && (cell.front() == ' ' || cell.front() == '\t')) cell.remove_prefix(1);
    while (!cell.empty() && (cell.back() == ' ' || cell.back() == '\t' || cell.back() == '\r')) cell.remove_suffix(1);
    if (n == cells.size()) cells.emplace_back();
    cells[n++].assign(cell.data(), cell.size());
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  cells.resize(n);
}

bool blank(std::string_view l) { return l.find_first_not_of(" \t\r") == std::string_view::npos; }
}  // namespace

bool csv_rows::next() {
  std::string& l = line_text_;
  while (read_line(l)) {
    if (l.starts_with("#")) continue;
    if (blank(l)) throw input_error(fmt::format("{}: line {}: empty row", where_, line_));
    split_into(l, cells_);
    if (cells_.size() < header_.size())
      throw input_error(fmt::format("{}: line {}: {} cells, the header has {}: no column {} (a truncated or malformed "
                                    "row)",
                                    where_, line_, cells_.size(), header_.size(), header_[cells_.size()]));
    if (cells_.size() > header_.size())
      throw input_error(fmt::format("{}: line {}: {} cells, the header has {} (a malformed row)", where_, line_,
                                    cells_.size(), header_.size()));
    return true;
  }
  return false;
}

decimal csv_rows::number(std::size_t c) const {
  const std::string& text = cells_[c];
  const auto parsed = parse_decimal(text);
  if (!parsed.number)
    throw input_error(fmt::format("{}: line {}: column {} = `{}` is {}", where_, line_, header_[c], text,
                                  text.empty() ? "empty"
                                  : parsed.problem == decimal_problem::not_a_number ? "not a number"
                                                                                    : describe(parsed.problem)));
  return *parsed.number;
}

}  // namespace eulervop::app
