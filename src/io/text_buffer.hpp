// Text composed of formatted pieces: the tables, CSV files and reports the commands print.
#pragma once

#include <fmt/format.h>

#include <iterator>
#include <string>
#include <utility>

namespace eulervop::app {

class text_buffer {
 public:
  template <class... Args>
  void put(fmt::format_string<Args...> format, Args&&... args) {
    fmt::format_to(std::back_inserter(buffer_), format, std::forward<Args>(args)...);
  }
  std::string text() const { return fmt::to_string(buffer_); }

 private:
  fmt::memory_buffer buffer_;
};

}  // namespace eulervop::app
