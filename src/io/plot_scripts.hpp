// Where the program finds its plot scripts (plot_fig1.py and the others, with plot_common.py):
// relative to its own executable, never in the source tree, so an installed program keeps its
// figures when the checkout it was built from is moved or deleted.
#pragma once

#include <filesystem>
#include <string>

namespace eulervop::app {

struct plot_script {
  std::filesystem::path path;  // the script; empty if it was not found
  std::string searched;        // when not found: the paths tried, joined by " or "
};

// Looks for the script `name` in, in order:
//   <exe dir>/../share/eulervop  (an installed program: bin/ and share/eulervop/ under one prefix;
//                                 the relative part follows CMAKE_INSTALL_BINDIR and _DATADIR)
//   <exe dir>/share/eulervop     (the build tree, where the build copies the scripts)
// where <exe dir> is the directory of the running executable (/proc/self/exe, links resolved).
plot_script find_plot_script(const std::string& name);

}  // namespace eulervop::app
