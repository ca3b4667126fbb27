// `eulervop reference --certify`: the radius column and its metadata, the one-line errors for what
// cannot be certified (exit 2), and a certificate that does not close (exit 3, no file).
#include "cli_test_support.hpp"

#include <eulervop/core/scalar.hpp>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <string>
#include <vector>

namespace {

using namespace eulervop::cli_test;

// The data rows of a reference CSV in `dir` (no metadata, no header), as cells.
std::vector<std::vector<std::string>> data_rows(const fs::path& dir, const std::string& file) {
  std::vector<std::vector<std::string>> rows;
  for (const std::string& l : lines_of(read_file(dir / file)))
    if (!l.empty() && l[0] != '#' && !l.starts_with("tau,") && !l.starts_with("t,")) rows.push_back(cells_of(l));
  return rows;
}

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
  const std::vector<std::vector<std::string>> plain_rows = data_rows(dir.path(), "p.csv");
  ASSERT_EQ(plain_rows.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    EXPECT_EQ(std::vector<std::string>(rows[i].begin(), rows[i].begin() + 4), plain_rows[i]);
}

// In MPFR too the rows are those of the plain run: the certificate's threads write them, and the
// times must be formatted at the run's precision, not at a thread's default.
TEST(Certify, MpfrRowsAreThoseOfThePlainRun) {
  temp_dir dir;
  const std::vector<std::string> common = {"--precision", "mpfr:256", "--tau-end", "2", "--samples", "7"};
  std::vector<std::string> certified = {"reference", "--certify", "--out", "c.csv"}, plain = {"reference", "--out", "p.csv"};
  certified.insert(certified.end(), common.begin(), common.end());
  plain.insert(plain.end(), common.begin(), common.end());
  ASSERT_EQ(run(dir.path(), certified).exit_code, 0);
  ASSERT_EQ(run(dir.path(), plain).exit_code, 0);
  const auto c = data_rows(dir.path(), "c.csv"), p = data_rows(dir.path(), "p.csv");
  ASSERT_EQ(c.size(), 7u);
  ASSERT_EQ(p.size(), 7u);
  for (std::size_t i = 0; i < c.size(); ++i) {
    ASSERT_EQ(c[i].size(), 5u);
    EXPECT_EQ(std::vector<std::string>(c[i].begin(), c[i].begin() + 4), p[i]) << "row " << i;
  }
}

TEST(Certify, UnsupportedCombinationsAreOneLineErrors) {
  temp_dir dir;
  expect_one_line_error(run(dir.path(), {"reference", "--certify", "--precision", "double", "--out", "x.csv"}),
                        "precision double is not certified");
  EXPECT_FALSE(fs::exists(dir.path() / "x.csv"));
}

// In mpfr:1024 the radii go below a double's range (the first row's, the printed digits' own
// rounding, near 1e-320): the run certifies, and the header holds the largest radius, compared in
// MPFR (a comparison in double once stopped the run with an internal error).
TEST(Certify, RadiiBelowTheRangeOfADoubleKeepTheirMaximum) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"reference", "--certify", "--precision", "mpfr:1024", "--degree", "60",
                                        "--tau-end", "0.001", "--samples", "3", "--out", "c.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string max_text;
  for (const std::string& l : lines_of(read_file(dir.path() / "c.csv")))
    if (l.starts_with("# certified_max_error: ")) max_text = l.substr(23);
  const auto rows = data_rows(dir.path(), "c.csv");
  ASSERT_EQ(rows.size(), 3u);
  eulervop::mpfr_precision_scope scope(64);
  eulervop::mpfr_real largest = 0;
  for (const auto& row : rows) largest = max(largest, eulervop::mpfr_real(row.at(4)));
  EXPECT_LT(eulervop::mpfr_real(rows[0].at(4)), eulervop::mpfr_real("1e-308")) << "below a double's normal range";
  EXPECT_EQ(eulervop::mpfr_real(max_text), largest);
}

// Initial elements with u != 0 (Eq. 12): Omega(0) = (c1 cn u, c1 sn u, c2 dn u) enters the proof
// as the enclosure of Jacobi's functions of the decimals, with a constant torque and with a
// torque of tau. Truth: the mpfr:256 run of the same scene (Boost's
// jacobi_elliptic at 256 bits, the Picard integration at 1e-60), at the same tau (dyadic, exact in
// both precisions).
TEST(Certify, InitialElementsWithUAreEnclosed) {
  temp_dir dir;
  const std::string torques[] = {"G = [0.01, 0.02, 0.0]", "G = [\"0.01*sin(tau)\", 0.0, \"0.02*cos(2*tau)\"]"};
  for (const std::string& torque : torques) {
    write_file(dir.path() / "u.toml", "name = \"u\"\n[torque]\n" + torque +
                                          "\n[initial]\nc1 = 0.5\nc2 = 1.0\nu = 0.3\n[span]\ntau_end = 8.0\n"
                                          "samples = 33\n");
    const run_result q = run(dir.path(), {"reference", "u.toml", "--certify", "--out", "q.csv"});
    ASSERT_EQ(q.exit_code, 0) << q.err;
    ASSERT_EQ(run(dir.path(), {"reference", "u.toml", "--precision", "mpfr:256", "--out", "m.csv"}).exit_code, 0);
    const auto qr = data_rows(dir.path(), "q.csv"), mr = data_rows(dir.path(), "m.csv");
    ASSERT_EQ(qr.size(), 33u);
    ASSERT_EQ(mr.size(), qr.size());
    eulervop::mpfr_precision_scope scope(256);
    double worst = 0;
    for (std::size_t i = 0; i < qr.size(); ++i) {
      ASSERT_EQ(qr[i].size(), 5u);
      EXPECT_EQ(eulervop::mpfr_real(qr[i][0]), eulervop::mpfr_real(mr[i][0])) << "the same tau";
      eulervop::mpfr_real s = 0;
      for (int c = 1; c < 4; ++c) {
        const eulervop::mpfr_real d = eulervop::mpfr_real(qr[i][c]) - eulervop::mpfr_real(mr[i][c]);
        s += d * d;
      }
      EXPECT_LE(sqrt(s), eulervop::mpfr_real(qr[i][4])) << torque << " tau = " << qr[i][0];
      worst = std::max(worst, std::strtod(qr[i][4].c_str(), nullptr));
    }
    EXPECT_LT(worst, 1e-30) << torque;
  }
}

// The certificate is a module the program loads only for --certify (run_certificate.hpp): the
// program copied alone runs a reference, and --certify then fails with one line naming the module
// and the places searched, and writes no file.
TEST(Certify, TheProgramAloneRunsAndNamesTheMissingModule) {
  temp_dir dir;
  const fs::path alone = dir.path() / "bin" / "eulervop";
  fs::create_directories(alone.parent_path());
  fs::copy_file(binary, alone);
  const run_result plain = run(dir.path(), {"reference", "--tau-end", "1", "--samples", "3", "--out", "p.csv"}, alone);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const run_result r = run(dir.path(), {"reference", "--certify", "--tau-end", "1", "--samples", "3", "--out", "c.csv"},
                           alone);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("cannot load the certificate module eulervop_certificate.so: not found at "), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find((alone.parent_path() / "lib" / "eulervop" / "eulervop_certificate.so").string()), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir.path() / "c.csv"));
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

// check against a certified reference: the error of each row is an interval (error +- radius);
// only a row certainly beyond the bar fails, and the JSON lists the rows left undecided.
TEST(Certify, CheckTreatsEachErrorAsAnInterval) {
  temp_dir dir;
  ASSERT_EQ(run(dir.path(), {"reference", "--certify", "--tau-end", "5", "--samples", "11", "--out", "ref.csv"}).exit_code, 0);
  // Trajectories: the reference's own rows (error 0), and the same with Omega1 moved by 1e-15.
  std::string same = "tau,Omega1,Omega2,Omega3\n", moved = same;
  for (const std::string& l : lines_of(read_file(dir.path() / "ref.csv"))) {
    if (l.empty() || l[0] == '#' || l.starts_with("tau,")) continue;
    const auto c = cells_of(l);
    same += fmt::format("{},{},{},{}\n", c[0], c[1], c[2], c[3]);
    moved += fmt::format("{},{:.17e},{},{}\n", c[0], std::strtod(c[1].c_str(), nullptr) + 1e-15, c[2], c[3]);
  }
  write_file(dir.path() / "same.csv", same);
  write_file(dir.path() / "moved.csv", moved);
  auto json_of = [&](const std::vector<std::string>& args) {
    const run_result r = run(dir.path(), args);
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;
    return nlohmann::json::parse(r.out);
  };
  // A bar of 0: error 0 +- radius straddles it on every row, so no row fails and none is certain.
  auto j = json_of({"check", "ref.csv", "same.csv", "--tol", "0", "--format", "json"});
  EXPECT_EQ(j["certified_reference"], true);
  EXPECT_EQ(j["pass"], true);
  EXPECT_EQ(j["uncertain_rows"], 11);
  EXPECT_EQ(j["uncertain_lines"].size(), 11u);
  EXPECT_EQ(j["all_rows_certain"], false);
  EXPECT_GT(j["max_reference_radius"].get<double>(), 0.0);
  // A bar far above the radii: every row certainly passes.
  j = json_of({"check", "ref.csv", "same.csv", "--tol", "1e-20", "--format", "json"});
  EXPECT_EQ(j["uncertain_rows"], 0);
  EXPECT_EQ(j["all_rows_certain"], true);
  // Moved by ~1e-15 against a bar of 1e-20: every row certainly fails.
  j = json_of({"check", "ref.csv", "moved.csv", "--tol", "1e-20", "--format", "json"});
  EXPECT_EQ(j["pass"], false);
  EXPECT_EQ(j["exceeding_rows"], 11);
  EXPECT_EQ(j["uncertain_rows"], 0);
}

// A physical scene: omega in rad/s at each row's t must lie within radius_omega of the exact
// solution, here an mpfr:256 reference of the same scene at the same t (exact in both precisions;
// its own error is below 1e-70, beyond the 1e-31 radii tested). Returns the largest radius of
// Omega.
double worst_radius_against_mpfr256(const std::string& scene, const std::string& samples) {
  temp_dir dir;
  const run_result q = run(dir.path(), {"reference", scene, "--certify", "--samples", samples, "--out", "q.csv"});
  EXPECT_EQ(q.exit_code, 0) << q.err;
  const run_result m =
      run(dir.path(), {"reference", scene, "--precision", "mpfr:256", "--samples", samples, "--out", "m.csv"});
  EXPECT_EQ(m.exit_code, 0) << m.err;
  const auto qr = data_rows(dir.path(), "q.csv"), mr = data_rows(dir.path(), "m.csv");
  EXPECT_EQ(qr.size(), static_cast<std::size_t>(std::stoi(samples)));
  EXPECT_EQ(mr.size(), qr.size());
  eulervop::mpfr_precision_scope scope(256);
  double worst_radius = 0;
  for (std::size_t i = 0; i < std::min(qr.size(), mr.size()); ++i) {
    EXPECT_EQ(qr[i].size(), 10u);
    EXPECT_EQ(eulervop::mpfr_real(qr[i][0]), eulervop::mpfr_real(mr[i][0])) << "the same t";
    eulervop::mpfr_real s = 0;
    for (int c = 1; c < 4; ++c) {  // t,omega1..3 lead; then tau,Omega1..3, radius, radius_omega
      const eulervop::mpfr_real d = eulervop::mpfr_real(qr[i][c]) - eulervop::mpfr_real(mr[i][c]);
      s += d * d;
    }
    EXPECT_LE(sqrt(s), eulervop::mpfr_real(qr[i][9])) << "t = " << qr[i][0];
    worst_radius = std::max(worst_radius, std::strtod(qr[i][8].c_str(), nullptr));
  }
  return worst_radius;
}

TEST(Certify, PhysicalSceneOmegaWithinRadiusOmega) {
  const double worst = worst_radius_against_mpfr256(source_dir + "/data/scenes/spacecraft-physical.toml", "61");
  EXPECT_LT(worst, 1e-28) << "Omega's radius on the spacecraft scene";
}

// Numbers written as formulas enter as enclosures of their exact values: Hairer, Lubich and
// Wanner's free rigid body (moments 2, 1, "2/3"; omega(0) = ("cos(1.1)/2", 0, "1.5*sin(1.1)")) is
// certified, and its rows lie within their radii of the mpfr:256 run, which evaluates the same
// formulas at 256 bits.
TEST(Certify, NumbersWrittenAsFormulasAreEnclosed) {
  const double worst = worst_radius_against_mpfr256(source_dir + "/data/scenes/problems/hlw-free-rigid-body.toml", "101");
  EXPECT_LT(worst, 1e-29) << "Omega's radius on the HLW free rigid body";
}

}  // namespace
