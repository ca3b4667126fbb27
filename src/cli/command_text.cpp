#include "cli/command_text.hpp"

#include "io/shell_word.hpp"

namespace eulervop::app {

std::string command_text(int argc, const char* const* argv) {
  std::string text = "eulervop";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out") {
      ++i;  // and its value
      continue;
    }
    if (a.starts_with("--out=")) continue;
    text += " " + shell_word(a);
  }
  return text;
}

}  // namespace eulervop::app
