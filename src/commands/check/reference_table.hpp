// The rows of a reference a trajectory is checked against, in time order: a reference file of
// `eulervop reference` read as it streams, or a reference held in memory (held_reference.hpp, the
// Python module's). Columns by the file's names, numbers in T, the metadata of its '#' lines.
#pragma once

#include "compute/scene_library.hpp"
#include "io/reference_csv.hpp"
#include "io/table_rows.hpp"

#include <fmt/format.h>

#include <eulervop/core/scalar_traits.hpp>
#include <eulervop/core/vec3.hpp>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace eulervop::app {

template <scalar T>
class reference_table {
 public:
  virtual ~reference_table() = default;
  virtual const std::vector<std::string>& header() const = 0;
  virtual const reference_metadata& metadata() const = 0;
  // How messages name it: "reference ref.csv", "the Reference".
  virtual const std::string& where() const = 0;
  // Advances to the next row; false after the last.
  virtual bool next() = 0;
  virtual std::size_t line() const = 0;
  // A time or radius cell as its text and binary64 value (exact when the times are binary64).
  virtual decimal number(std::size_t c) const = 0;
  // A cell in T.
  virtual T value(std::size_t c) const = 0;

  std::optional<std::size_t> column(std::string_view name) const { return column_in(header(), name); }
  // The column named `name`; input_error ("the header has no column `name`{why}") if absent.
  std::size_t required(const std::string& name, std::string_view why = "") const;
  vec3<T> values(const std::array<std::size_t, 3>& c) const { return {value(c[0]), value(c[1]), value(c[2])}; }
  // The sample times are binary64 numbers (# times): a trajectory's time must equal one exactly.
  bool binary_times() const { return !metadata().times.empty(); }
};

template <scalar T>
std::size_t reference_table<T>::required(const std::string& name, std::string_view why) const {
  const auto c = column(name);
  if (!c) throw input_error(fmt::format("{}: line {}: the header has no column `{}`{}", where(), line(), name, why));
  return *c;
}

}  // namespace eulervop::app
