// Text for a POSIX shell command line: the program's own command lines (`# command:` in a
// reference file) and the plot script it runs.
#pragma once

#include <string>

namespace eulervop::app {

// 'a' in single quotes, each ' written as '\'' : one word for sh, whatever a contains.
std::string shell_quoted(const std::string& a);

// a as it is when it is one plain word for sh (letters, digits and -_./:=,+@%), else quoted.
std::string shell_word(const std::string& a);

}  // namespace eulervop::app
