#include "io/text_table.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace eulervop::app {

std::string aligned_table(const std::vector<std::vector<std::string>>& rows, std::size_t text_columns) {
  std::vector<std::size_t> width;
  for (const auto& row : rows) {
    if (width.size() < row.size()) width.resize(row.size(), 0);
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  }
  std::string out;
  for (const auto& row : rows) {
    std::string line;
    for (std::size_t c = 0; c < row.size(); ++c) {
      const bool last = c + 1 == row.size() && c + 1 == width.size();
      const std::string cell = c < text_columns || last ? fmt::format("{:<{}}", row[c], last ? 0 : width[c])
                                                        : fmt::format("{:>{}}", row[c], width[c]);
      line += (c ? "  " : "") + cell;
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line + "\n";
  }
  return out;
}

}  // namespace eulervop::app
