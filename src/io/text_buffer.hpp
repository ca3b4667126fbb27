// Text composed of formatted pieces: the tables, CSV files and reports the commands print.
#pragma once

#include <fmt/format.h>

#include <string>
#include <utility>

namespace eulervop::app {

// Appends `format` with `args` to `out`: fmt::format_to's work, compiled once here (text_buffer.cpp)
// rather than in every unit that writes into a buffer, as fmt::format is compiled in libfmt.
void append_formatted(fmt::memory_buffer& out, fmt::string_view format, fmt::format_args args);

// fmt::format_to(std::back_inserter(out), format, args...), with the format checked at compile time.
template <class... Args>
void format_into(fmt::memory_buffer& out, fmt::format_string<Args...> format, Args&&... args) {
  append_formatted(out, format, fmt::make_format_args(args...));
}

class text_buffer {
 public:
  template <class... Args>
  void put(fmt::format_string<Args...> format, Args&&... args) {
    format_into(buffer_, format, std::forward<Args>(args)...);
  }
  std::string text() const { return fmt::to_string(buffer_); }

 private:
  fmt::memory_buffer buffer_;
};

}  // namespace eulervop::app
