// Output files appear complete or not at all, and a run killed with SIGKILL (which no handler can
// catch) leaves its temporary "<out>.tmp.<host>.<pid>.XXXXXX" behind: the next run that writes
// beside it removes it, when it was made on this machine by a process that no longer exists.
#include "io/atomic_file.hpp"
#include "cli_test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
namespace cli_test = eulervop::cli_test;
using cli_test::temp_dir;
using cli_test::write_file;

// The id of a process that has exited and been reaped.
pid_t dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

bool exists(const fs::path& p) { return fs::exists(p); }

TEST(AtomicOutput, ARunRemovesStaleTemporariesOfThisHostOnly) {
  temp_dir dir;
  using eulervop::app::atomic_file;
  const std::string ours = atomic_file::temporary_prefix("ref.csv");  // "ref.csv.tmp.<host>."
  const fs::path stale = dir.path() / (ours + std::to_string(dead_pid()) + ".AbCdEf");
  const fs::path live = dir.path() / (ours + std::to_string(::getpid()) + ".AbCdEf");
  const fs::path other_host = dir.path() / (ours.substr(0, ours.size() - 1) + "-elsewhere.12345.AbCdEf");
  const fs::path other_name = dir.path() / "ref.csv.tmp.AbCdEf";  // not of this form: not judged
  const fs::path other_output =
      dir.path() / (atomic_file::temporary_prefix("other.csv") + std::to_string(dead_pid()) + ".AbCdEf");
  for (const fs::path& p : {stale, live, other_host, other_name, other_output}) write_file(p, "");

  const cli_test::run_result r =
      cli_test::run(dir.path(), {"reference", "--tau-end", "1", "--samples", "3", "--out", "ref.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir.path() / "ref.csv"));
  EXPECT_FALSE(fs::exists(stale)) << "a dead process's temporary on this host must go";
  EXPECT_TRUE(fs::exists(live)) << "a live process's temporary must stay";
  EXPECT_TRUE(fs::exists(other_host)) << "another host's process id means nothing here";
  EXPECT_TRUE(fs::exists(other_name));
  EXPECT_TRUE(fs::exists(other_output)) << "only the temporaries of the file being written are judged";
}

// A run killed with SIGKILL leaves exactly its own temporary; the rerun removes it and writes
// the output.
TEST(AtomicOutput, RerunAfterSigkillLeavesOnlyTheOutput) {
  temp_dir dir;
  const pid_t child = ::fork();
  if (child == 0) {
    ::chdir(dir.path().c_str());
    ::execl(cli_test::binary.c_str(), cli_test::binary.c_str(), "reference", "--tau-end", "1e6", "--samples", "3",
            "--out", "ref.csv", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Wait until the temporary exists (it is made before the integration starts), then kill.
  bool made = false;
  for (int i = 0; i < 500 && !made; ++i) {
    ::usleep(10000);
    for (const auto& e : fs::directory_iterator(dir.path()))
      if (e.path().filename().string().starts_with("ref.csv.tmp.")) made = true;
  }
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(made) << "no temporary appeared";
  ASSERT_TRUE(WIFSIGNALED(status));

  const cli_test::run_result r =
      cli_test::run(dir.path(), {"reference", "--tau-end", "1", "--samples", "3", "--out", "ref.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.path())) names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"ref.csv"});
}

}  // namespace
