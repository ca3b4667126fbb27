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
    // Where the output goes and whether progress is shown change nothing in it.
    if (a.starts_with("--out=") || a == "--progress" || a == "--quiet") continue;
    text += " " + shell_word(a);
  }
  return text;
}

}  // namespace eulervop::app
