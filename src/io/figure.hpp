// The figures of `report`, `sweep` and `map`, drawn by the plot scripts (matplotlib).
#pragma once

#include <filesystem>
#include <string>

namespace eulervop::app {

// Runs the plot script (tools/<script>, found by find_plot_script in share/eulervop next to the
// program) with DIR (python3 on PATH, then /usr/bin/python3). Never fails the command: a missing
// script, python3 or matplotlib (the script exits with 4) is one line on stderr saying how to get
// the figure.
void draw_figure(const std::filesystem::path& dir, const std::string& script);

}  // namespace eulervop::app
