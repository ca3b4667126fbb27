#include "io/text_buffer.hpp"

#include <iterator>

namespace eulervop::app {

void append_formatted(fmt::memory_buffer& out, fmt::string_view format, fmt::format_args args) {
  fmt::vformat_to(std::back_inserter(out), format, args);
}

}  // namespace eulervop::app
