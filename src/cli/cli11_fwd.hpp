// The two CLI11 classes that the commands' flag declarations name, declared without CLI11's
// header (about 6 s of compile time in every unit that includes it): only the units that call
// CLI11 include <CLI/CLI.hpp>.
#pragma once

namespace CLI {
class App;
class Option;
}  // namespace CLI
