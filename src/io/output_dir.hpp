// Where a command writes its files: an output directory checked before any work, and files
// written whole or not at all.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace eulervop::app {

// Creates the output directory (if missing) and checks that files can be created in it (by
// creating and removing a temporary next to `probe_file`), before any computation. If the
// command then fails, a directory it created is removed again (it is still empty: every file
// is written atomically at the end).
class output_dir {
 public:
  output_dir(const std::filesystem::path& dir, const std::string& probe_file);
  ~output_dir();
  output_dir(const output_dir&) = delete;
  output_dir& operator=(const output_dir&) = delete;

  void keep() { kept_ = true; }
  const std::filesystem::path& path() const { return dir_; }

 private:
  void remove_if_created() noexcept;
  std::filesystem::path dir_;
  bool created_ = false;
  bool kept_ = false;
};

// --out-dir: the directory given, or ./eulervop-<command>/ when none is; input_error for an
// empty path.
std::filesystem::path out_dir_of(const std::optional<std::string>& flag, std::string_view command);

void write_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace eulervop::app
