#include "io/scratch_file.hpp"

#include "compute/scene_library.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <system_error>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

namespace eulervop::app {

namespace {

constexpr std::size_t copy_chunk = 1 << 16;

}  // namespace

std::filesystem::path scratch_directory_for(const atomic_file* output) {
  if (output && output->replaces_target()) {
    const std::filesystem::path dir = output->target().parent_path();
    return dir.empty() ? std::filesystem::path(".") : dir;
  }
  std::error_code ec;
  std::filesystem::path tmp = std::filesystem::temp_directory_path(ec);
  if (ec) {
    const char* value = std::getenv("TMPDIR");
    throw input_error(fmt::format("TMPDIR {}: not a usable directory for the rows of standard output: {}",
                                  value ? value : "(unset)", ec.message()));
  }
  return tmp;
}

scratch_file::scratch_file(const std::filesystem::path& directory) : directory_(directory) {
  std::string pattern = (directory_ / ".eulervop-scratch.XXXXXX").string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  fd_ = ::mkstemp(name.data());
  if (fd_ < 0) fail("cannot create a scratch file", errno);
  // Unlinked at once: from here on nothing can leave it behind (the name existed for the
  // time of one system call).
  ::unlink(name.data());
}

scratch_file::~scratch_file() {
  if (fd_ >= 0) ::close(fd_);
}

void scratch_file::fail(std::string_view what, int err) const {
  throw input_error(fmt::format("{}: {}: {}", directory_.string(), what, std::strerror(err)));
}

void scratch_file::write(std::string_view data) {
  while (!data.empty()) {
    const ssize_t n = ::write(fd_, data.data(), data.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("cannot write a scratch file", errno);
    }
    data.remove_prefix(static_cast<std::size_t>(n));
    size_ += static_cast<std::uint64_t>(n);
  }
}

void scratch_file::copy_to(const std::function<void(std::string_view)>& out) const {
  std::vector<char> chunk(copy_chunk);
  for (std::uint64_t at = 0; at < size_;) {
    const ssize_t n = ::pread(fd_, chunk.data(), chunk.size(), static_cast<off_t>(at));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("cannot read back a scratch file", n < 0 ? errno : EIO);
    out(std::string_view(chunk.data(), static_cast<std::size_t>(n)));
    at += static_cast<std::uint64_t>(n);
  }
}

}  // namespace eulervop::app
