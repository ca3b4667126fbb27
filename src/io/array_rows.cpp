#include "io/array_rows.hpp"

#include <fmt/format.h>

namespace eulervop::app {

decimal array_rows::number(std::size_t c) const {
  const std::size_t i = row_ - 1;
  const double x = c == 0 ? time_[i] : values_[i * width_ + (c - 1)];
  if (!std::isfinite(x))
    throw input_error(fmt::format("{}: line {}: column {} = {} is not finite", where_, line(), header_[c], x));
  return binary_number(x, c == 0);
}

}  // namespace eulervop::app
