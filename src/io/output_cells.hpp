// Optional numbers in the outputs: a JSON null or an empty CSV cell when there is no value.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace eulervop::app {

nlohmann::ordered_json number_or_null(const std::optional<double>& x);
// A CSV cell: the shortest round-trip text of x, or empty.
std::string csv_number(const std::optional<double>& x);

}  // namespace eulervop::app
