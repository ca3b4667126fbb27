// A file on disk that holds output until it can be placed, so a long run's memory does not grow
// with its output.
//
// `reference` states its segment count and wall time in the metadata block at the top of the
// CSV, known only when the run ends; its rows wait here meanwhile and are copied after the
// header. The file is unlinked as soon as it is created, so it vanishes when closed, however
// the program ends (an exception, a signal, even SIGKILL): a failed run leaves nothing behind
// (docs/design.md section 5.3).
#pragma once

#include "io/atomic_file.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string_view>

namespace eulervop::app {

// Where the rows of `output` wait: beside the output file (its file system holds them in the end
// anyway); for standard output (none) or a device, in the temporary directory (TMPDIR).
// input_error when TMPDIR is not usable.
std::filesystem::path scratch_directory_for(const atomic_file* output);

class scratch_file {
 public:
  // An unnamed file in `directory`; input_error (naming the directory) if it cannot be made.
  explicit scratch_file(const std::filesystem::path& directory);
  ~scratch_file();
  scratch_file(const scratch_file&) = delete;
  scratch_file& operator=(const scratch_file&) = delete;

  void write(std::string_view data);
  // Hands everything written so far to `out`, in order, in chunks of a fixed size.
  void copy_to(const std::function<void(std::string_view)>& out) const;
  std::uint64_t size() const { return size_; }

 private:
  [[noreturn]] void fail(std::string_view what, int err) const;

  std::filesystem::path directory_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

}  // namespace eulervop::app
