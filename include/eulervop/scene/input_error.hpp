// The one exception type for bad input (scene files and command-line flags).
//
// Bad input exits with code 2 and a one-line message that names the field or flag and the
// offending value (docs/design.md section 5.3). Everything that validates user input throws
// this type, so main() can map it to that exit code without guessing.
#pragma once

#include <stdexcept>
#include <string>

namespace eulervop::scene {

class input_error : public std::runtime_error {
 public:
  // The message is made single-line here, so no caller can break the one-line contract.
  explicit input_error(const std::string& message) : std::runtime_error(one_line(message)) {}

  static std::string one_line(std::string text) {
    for (char& c : text)
      if (c == '\n' || c == '\r') c = ' ';
    return text;
  }
};

}  // namespace eulervop::scene
