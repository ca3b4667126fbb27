// --errors-out of `check`: each row's error streamed into an atomic file (which appears only when
// complete): line, time, error, bar (and radius against a certified reference).
#pragma once

#include "compute/scene_library.hpp"
#include "io/atomic_file.hpp"

#include <cstddef>
#include <memory>
#include <optional>
#include <string>

namespace eulervop::app {

class errors_writer {
 public:
  // No path: writes nothing. The file is created here, so an unwritable path fails at once.
  explicit errors_writer(const std::optional<std::string>& path);
  // With a certified reference, a last column `radius`.
  void header(const std::string& time_name, bool certified);
  void row(std::size_t line, const std::string& time, double error, std::optional<double> bar,
           const std::optional<decimal>& radius);
  void commit();

 private:
  void flush();
  std::unique_ptr<atomic_file> file_;
  std::string buffer_;
};

}  // namespace eulervop::app
