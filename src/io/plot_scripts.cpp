#include "io/plot_scripts.hpp"

#include <system_error>
#include <vector>

// The install layout's path from the program's directory to the scripts (set by CMakeLists.txt).
#ifndef EULERVOP_SCRIPTS_FROM_BINDIR
#define EULERVOP_SCRIPTS_FROM_BINDIR "../share/eulervop"
#endif

namespace eulervop::app {

namespace fs = std::filesystem;

plot_script find_plot_script(const std::string& name) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec || exe.empty()) return {{}, name + " next to the program (its own path is unknown)"};
  const fs::path exe_dir = exe.parent_path();
  const std::vector<fs::path> candidates = {
      (exe_dir / EULERVOP_SCRIPTS_FROM_BINDIR / name).lexically_normal(),
      (exe_dir / "share" / "eulervop" / name).lexically_normal(),
  };
  plot_script missing;
  for (const fs::path& p : candidates) {
    if (fs::is_regular_file(p, ec)) return {p, {}};
    missing.searched += (missing.searched.empty() ? "" : " or ") + p.string();
  }
  return missing;
}

}  // namespace eulervop::app
