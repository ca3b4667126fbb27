// Long certification runs (CTest label "long"; opt in with EULERVOP_LONG_TESTS=1), through the
// program as a user runs it:
//   - the paper scene to tau = 136 in quad: an mpfr:512 reference (verified error far below
//     1e-140) lies within the quad radius at every row, and the largest radius is at most 1e-26;
//   - the long-bounded scene to tau = 1e4 in quad: the largest radius is at most 1e-24;
//   - the paper scene in mpfr:256: the largest radius is at most 1e-60;
//   - hard/spinup-unstable to tau = 360 in quad: the largest radius is at most 1.5 times the
//     `--verify` estimate of the largest error (one precision up), where a box that grew its balls
//     with its parallelepiped's condition gave 7.9 times (docs/certified.md).
// The mpfr:512 run is evaluated at the quad rows' own tau values (`--times` with their decimals,
// which round back to those binary values exactly), so the two are compared at the same times.
#include "cli_test_support.hpp"

#include <eulervop/core/scalar.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace {

using namespace eulervop::cli_test;

std::vector<std::vector<std::string>> data_rows(const fs::path& file) {
  std::vector<std::vector<std::string>> rows;
  for (const std::string& l : lines_of(read_file(file)))
    if (!l.empty() && l[0] != '#' && !l.starts_with("tau,") && !l.starts_with("t,")) rows.push_back(cells_of(l));
  return rows;
}

double header_number(const fs::path& file, const std::string& key) {
  const std::string prefix = "# " + key + ": ";
  for (const std::string& l : lines_of(read_file(file)))
    if (l.starts_with(prefix)) return std::strtod(l.substr(prefix.size()).c_str(), nullptr);
  return -1;
}

double certified_max(const fs::path& file) { return header_number(file, "certified_max_error"); }

TEST(LongCertified, PaperSceneMpfr512WithinTheQuadRadius) {
  temp_dir dir;
  ASSERT_EQ(run(dir.path(), {"reference", "--certify", "--samples", "137", "--out", "q.csv"}).exit_code, 0);
  const auto q = data_rows(dir.path() / "q.csv");
  ASSERT_EQ(q.size(), 137u);
  std::string times;
  for (const auto& r : q) times += (times.empty() ? "" : ",") + r[0];
  const run_result m = run(dir.path(), {"reference", "--precision", "mpfr:512", "--times", times, "--out", "m.csv"});
  ASSERT_EQ(m.exit_code, 0) << m.err;
  const auto mr = data_rows(dir.path() / "m.csv");
  ASSERT_EQ(mr.size(), q.size());
  eulervop::mpfr_precision_scope scope(512);
  for (std::size_t i = 0; i < q.size(); ++i) {
    ASSERT_EQ(eulervop::mpfr_real(q[i][0]), eulervop::mpfr_real(mr[i][0]));
    eulervop::mpfr_real s = 0;
    for (int c = 1; c <= 3; ++c) {
      const eulervop::mpfr_real d = eulervop::mpfr_real(q[i][c]) - eulervop::mpfr_real(mr[i][c]);
      s += d * d;
    }
    EXPECT_LE(sqrt(s), eulervop::mpfr_real(q[i][4])) << "tau " << q[i][0];
  }
  EXPECT_LE(certified_max(dir.path() / "q.csv"), 1e-26);
}

TEST(LongCertified, LongBoundedToTau1e4) {
  temp_dir dir;
  ASSERT_EQ(run(dir.path(), {"reference", source_dir + "/data/scenes/hard/long-bounded.toml", "--certify",
                             "--samples", "101", "--out", "l.csv"})
                .exit_code,
            0);
  const double worst = certified_max(dir.path() / "l.csv");
  EXPECT_GT(worst, 0);
  EXPECT_LE(worst, 1e-24);
}

TEST(LongCertified, PaperSceneMpfr256) {
  temp_dir dir;
  ASSERT_EQ(run(dir.path(), {"reference", "--certify", "--precision", "mpfr:256", "--samples", "137", "--out", "m.csv"})
                .exit_code,
            0);
  const double worst = certified_max(dir.path() / "m.csv");
  EXPECT_GT(worst, 0);
  EXPECT_LE(worst, 1e-60);
}

TEST(LongCertified, SpinUpRadiusWithinItsEstimate) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"reference", source_dir + "/data/scenes/hard/spinup-unstable.toml", "--certify",
                                        "--verify", "--samples", "101", "--out", "s.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double radius = certified_max(dir.path() / "s.csv");
  const double estimate = header_number(dir.path() / "s.csv", "estimated_max_error");
  EXPECT_GT(estimate, 0);
  EXPECT_GE(radius, 0.9 * estimate);  // the estimate is not a bound, but it is near the error
  EXPECT_LE(radius, 1.5 * estimate);
}

}  // namespace
