// An output file that appears complete or not at all.
//
// Bad input or a failure leaves no output file behind (docs/design.md section 5.3), and an
// existing file is never half-overwritten. The content goes to a temporary file in the target's
// directory (so the final rename(2) is atomic on the same file system), is fsync'ed, and is
// renamed over the target only on commit(). The temporary is created in the constructor, so an
// unwritable path is reported before any computation starts.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace eulervop::app {

class atomic_file {
 public:
  // Creates "<target>.tmp.<host>.<pid>.XXXXXX" next to the target, after removing the ones of
  // this host whose process no longer exists (left by a SIGKILL); input_error (naming the path)
  // if the directory is missing or not writable, or the target is a directory.
  explicit atomic_file(std::filesystem::path target);
  // Removes the temporary unless commit() succeeded; the target is then untouched.
  ~atomic_file();
  atomic_file(const atomic_file&) = delete;
  atomic_file& operator=(const atomic_file&) = delete;

  void write(std::string_view data);
  // fsync, close, and rename over the target. input_error on any failure (temporary removed).
  void commit();

  const std::filesystem::path& target() const { return target_; }

  // "<target>.tmp.<host>.": what the temporaries of `target` made on this machine start with
  // (the process id and six random characters follow).
  static std::string temporary_prefix(const std::filesystem::path& target);
  // False for a device or pipe, which is written in place.
  bool replaces_target() const { return !temp_.empty(); }

 private:
  void discard() noexcept;

  std::filesystem::path target_;
  std::string temp_;
  int fd_ = -1;
  bool committed_ = false;
};

}  // namespace eulervop::app
