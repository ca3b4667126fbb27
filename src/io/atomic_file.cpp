#include "io/atomic_file.hpp"

#include "compute/scene_library.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace eulervop::app {

namespace {

// A Ctrl-C during a long reference run must not leave "x.csv.tmp.XXXXXX" behind. The signal
// handler may only call async-signal-safe functions, so it unlinks a path prepared in advance.
// One output file at a time is all the program needs.
char pending_temp[4096];
std::atomic<bool> pending_temp_set{false};

extern "C" void remove_temp_and_reraise(int sig) {
  if (pending_temp_set.load()) ::unlink(pending_temp);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void guard_temp(const std::string& path) {
  if (path.size() >= sizeof pending_temp) return;
  std::memcpy(pending_temp, path.c_str(), path.size() + 1);
  pending_temp_set.store(true);
  std::signal(SIGINT, remove_temp_and_reraise);
  std::signal(SIGTERM, remove_temp_and_reraise);
  std::signal(SIGHUP, remove_temp_and_reraise);
}

void unguard_temp() { pending_temp_set.store(false); }

// This machine's name, for the temporaries' names: on a file system shared by several machines
// (a cluster), a process id means something only on the machine that made the file.
std::string host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "localhost";
  std::string host(name);
  std::replace(host.begin(), host.end(), '/', '_');
  return host;
}

// The temporaries of `target` are "<target>.tmp.<host>.<pid>.XXXXXX". A SIGKILL (or a power
// cut) leaves one behind, which no signal handler can remove. Those made on this machine by a
// process that no longer exists are removed here, before a new one is made; others (another
// machine's, a live process's, or names of any other form) are left alone.
void remove_stale_temporaries(const std::filesystem::path& target, const std::string& prefix) {
  std::error_code ec;
  const std::filesystem::path dir = target.parent_path().empty() ? "." : target.parent_path();
  const std::string name_prefix = std::filesystem::path(prefix).filename().string();
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with(name_prefix)) continue;
    const std::string rest = name.substr(name_prefix.size());  // "<pid>.XXXXXX"
    const std::size_t dot = rest.find('.');
    if (dot == 0 || dot == std::string::npos || rest.size() - dot - 1 != 6) continue;
    const std::string pid_text = rest.substr(0, dot);
    if (!std::all_of(pid_text.begin(), pid_text.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
        pid_text.size() > 9)
      continue;
    const pid_t pid = static_cast<pid_t>(std::stol(pid_text));
    if (pid <= 0 || ::kill(pid, 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to judge
    std::filesystem::remove(entry.path(), ec);
  }
}

[[noreturn]] void fail(const std::filesystem::path& target, std::string_view what, int err) {
  throw input_error(fmt::format("--out {}: {}: {}", target.string(), what, std::strerror(err)));
}

}  // namespace

atomic_file::atomic_file(std::filesystem::path target) : target_(std::move(target)) {
  std::error_code ec;
  if (target_.empty()) throw input_error("--out: empty path");
  if (std::filesystem::is_directory(target_, ec))
    throw input_error(fmt::format("--out {}: is a directory", target_.string()));
  // A device or pipe (/dev/null, /dev/stdout, a fifo) cannot be replaced by rename and needs
  // no atomicity: write to it directly.
  if (std::filesystem::exists(target_, ec) && !std::filesystem::is_regular_file(target_, ec)) {
    fd_ = ::open(target_.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd_ < 0) fail(target_, "cannot open", errno);
    return;
  }
  const std::string prefix = temporary_prefix(target_);
  remove_stale_temporaries(target_, prefix);
  std::string pattern = prefix + std::to_string(::getpid()) + ".XXXXXX";
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  fd_ = ::mkstemp(name.data());
  if (fd_ < 0) fail(target_, "cannot create a file in its directory", errno);
  temp_ = name.data();
  guard_temp(temp_);
}

std::string atomic_file::temporary_prefix(const std::filesystem::path& target) {
  return target.string() + ".tmp." + host_name() + ".";
}

atomic_file::~atomic_file() {
  if (!committed_) discard();
}

void atomic_file::discard() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!temp_.empty()) ::unlink(temp_.c_str());
  unguard_temp();
}

void atomic_file::write(std::string_view data) {
  while (!data.empty()) {
    const ssize_t n = ::write(fd_, data.data(), data.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      discard();
      fail(target_, "cannot write", err);
    }
    data.remove_prefix(static_cast<std::size_t>(n));
  }
}

void atomic_file::commit() {
  // mkstemp creates the file 0600; an output file should get the usual 0666 & ~umask.
  if (!temp_.empty()) {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::fchmod(fd_, 0666 & ~mask);
  }
  int err = 0;
  if (::fsync(fd_) != 0 && errno != EINVAL) err = errno;  // EINVAL: a device that cannot sync
  if (::close(fd_) != 0 && err == 0) err = errno;
  fd_ = -1;
  if (err != 0) {
    discard();
    fail(target_, "cannot write", err);
  }
  if (temp_.empty()) {  // a device or pipe, written in place
    committed_ = true;
    return;
  }
  if (::rename(temp_.c_str(), target_.c_str()) != 0) {
    const int err = errno;
    discard();
    fail(target_, "cannot replace", err);
  }
  committed_ = true;
  unguard_temp();
}

}  // namespace eulervop::app
