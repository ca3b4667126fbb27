#include "io/output_cells.hpp"

#include <fmt/format.h>

namespace eulervop::app {

nlohmann::ordered_json number_or_null(const std::optional<double>& x) {
  return x ? nlohmann::ordered_json(*x) : nlohmann::ordered_json(nullptr);
}

std::string csv_number(const std::optional<double>& x) { return x ? fmt::format("{}", *x) : std::string(); }

}  // namespace eulervop::app
