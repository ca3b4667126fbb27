#include "io/figure.hpp"

#include "io/plot_scripts.hpp"
#include "compute/scene_library.hpp"
#include "io/shell_word.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <sstream>

#include <sys/wait.h>

namespace eulervop::app {

namespace fs = std::filesystem;

void draw_figure(const fs::path& dir, const std::string& script_name) {
  const plot_script found = find_plot_script(script_name);
  const fs::path& script = found.path;
  const std::string how =
      fmt::format("apt-get install python3-matplotlib, then tools/{} {}", script_name, dir.string());
  std::error_code ec;
  if (script.empty()) {
    fmt::print(stderr, "figure skipped: {} not found ({})\n", found.searched, how);
    return;
  }
  // The python3 on PATH first; then Debian's own, which is where python3-matplotlib installs
  // (a pyenv or venv python3 on PATH does not see it).
  int code = -1;
  std::string output;
  for (const char* python : {"python3", "/usr/bin/python3"}) {
    if (python[0] == '/' && !fs::exists(python, ec)) continue;
    const std::string cmd = fmt::format("{} {} {} 2>&1 < /dev/null", python, shell_quoted(script.string()),
                                        shell_quoted(dir.string()));
    std::fflush(stdout);
    FILE* pipe = ::popen(cmd.c_str(), "r");
    if (!pipe) continue;
    output.clear();
    char buf[512];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) output.append(buf, n);
    const int status = ::pclose(pipe);
    code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code != 4 && code != 127) break;  // drawn, or failed for another reason
  }
  if (code == 0) return;
  if (code == 4) {
    fmt::print(stderr, "figure skipped: matplotlib not found ({})\n", how);
  } else if (code == 127) {
    fmt::print(stderr, "figure skipped: python3 not found ({})\n", how);
  } else {
    std::string last;  // the last line of the script's output says why (a traceback ends with it)
    std::istringstream in(output);
    for (std::string l; std::getline(in, l);)
      if (!l.empty()) last = l;
    fmt::print(stderr, "figure failed: {} exited with code {}: {}\n", script_name, code, input_error::one_line(last));
  }
}

}  // namespace eulervop::app
