// Plain-text tables for the commands' standard output: columns padded to their widest cell,
// text left-aligned and numbers right-aligned.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace eulervop::app {

// The first `text_columns` columns are left-aligned, the others right-aligned; a last column
// that is wider than the header row (a trailing note) is left-aligned and not padded. Two
// spaces between columns, no trailing spaces, one line per row.
std::string aligned_table(const std::vector<std::vector<std::string>>& rows, std::size_t text_columns);

}  // namespace eulervop::app
