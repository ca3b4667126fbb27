// `eulervop reference --certify`: the radius column and its metadata, the one-line errors for what
// cannot be certified (exit 2), and a certificate that does not close (exit 3, no file).
#include "cli_test_support.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace {

using namespace eulervop::cli_test;

TEST(Certify, RowsCarryARadiusAndTheHeaderItsMaximum) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"reference", "--certify", "--tau-end", "5", "--samples", "11", "--out", "c.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = lines_of(read_file(dir.path() / "c.csv"));
  std::string max_line, header;
  std::vector<std::vector<std::string>> rows;
  for (const std::string& l : lines) {
    if (l.starts_with("# certified_max_error: ")) max_line = l;
    else if (l.starts_with("tau,")) header = l;
    else if (!l.empty() && l[0] != '#') rows.push_back(cells_of(l));
  }
  EXPECT_EQ(header, "tau,Omega1,Omega2,Omega3,radius");
  ASSERT_EQ(rows.size(), 11u);
  double worst = 0;
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 5u);
    const double radius = std::strtod(row[4].c_str(), nullptr);
    EXPECT_GT(radius, 0);
    EXPECT_LT(radius, 1e-28) << "the paper scene to tau = 5 certifies far below 1e-28 in quad";
    worst = std::max(worst, radius);
  }
  ASSERT_FALSE(max_line.empty());
  EXPECT_EQ(std::strtod(max_line.substr(23).c_str(), nullptr), worst);
  // The rows themselves are those of the run without --certify.
  const run_result plain = run(dir.path(), {"reference", "--tau-end", "5", "--samples", "11", "--out", "p.csv"});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  std::vector<std::vector<std::string>> plain_rows;
  for (const std::string& l : lines_of(read_file(dir.path() / "p.csv")))
    if (!l.empty() && l[0] != '#' && !l.starts_with("tau,")) plain_rows.push_back(cells_of(l));
  ASSERT_EQ(plain_rows.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    EXPECT_EQ(std::vector<std::string>(rows[i].begin(), rows[i].begin() + 4), plain_rows[i]);
}

TEST(Certify, UnsupportedCombinationsAreOneLineErrors) {
  temp_dir dir;
  expect_one_line_error(run(dir.path(), {"reference", "--certify", "--precision", "double", "--out", "x.csv"}),
                        "precision double is not certified");
  expect_one_line_error(
      run(dir.path(), {"reference", source_dir + "/data/scenes/spacecraft-physical.toml", "--certify", "--out", "x.csv"}),
      "is physical");
  write_file(dir.path() / "u.toml", R"(name = "u"
[torque]
G = [0.0, 0.0, 0.0]
[initial]
c1 = 0.5
c2 = 1.0
u = 0.3
[span]
tau_end = 1.0
samples = 3
)");
  expect_one_line_error(run(dir.path(), {"reference", "u.toml", "--certify", "--out", "x.csv"}), "u = 0.3");
  EXPECT_FALSE(fs::exists(dir.path() / "x.csv"));
}

TEST(Certify, ABoundThatDoesNotCloseExitsThreeWithTheTauAndNoFile) {
  temp_dir dir;
  // At 32 bits the proven bound passes 2^-20 of the state near the separatrix by tau ~ 14.
  const run_result r = run(dir.path(), {"reference", source_dir + "/data/scenes/hard/near-separatrix-free.toml",
                                        "--certify", "--precision", "mpfr:32", "--out", "x.csv"});
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("numerical failure at tau="), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("certification does not close"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("higher precision"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.path() / "x.csv"));
}

}  // namespace
