// --errors-out of `check`: each row's error streamed into an atomic file (which appears only when
// complete): line, time, error, bar (and radius against a certified reference, attitude_error for
// a trajectory with q0..q3).
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
  // With a certified reference, a last column `radius`; with an attitude, `attitude_error`.
  void header(const std::string& time_name, bool certified, bool attitude = false);
  // `attitude_error`: the row's attitude error as text (every digit of its precision).
  void row(std::size_t line, const std::string& time, double error, std::optional<double> bar,
           const std::optional<decimal>& radius, const std::string* attitude_error = nullptr);
  void commit();
  // Whether rows are written (a path was given).
  bool writing() const { return file_ != nullptr; }

 private:
  void flush();
  std::unique_ptr<atomic_file> file_;
  std::string buffer_;
};

}  // namespace eulervop::app
