// `eulervop check` as a user meets it: a physical scene under the gravity gradient and a rate
// damping, and a trajectory made from the scene's own reference (reordered or perturbed here, so
// no outside integrator is needed). Each test holds one thing the output must say: a first row
// that is not the scene's initial state (a quaternion written scalar last), the --columns flag for
// a header in the user's names, no figure that means nothing for the scene (Eq. 7 under a
// torque), scd with what it measures, one number format, and the unit of every figure.
#include "cli_test_support.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace eulervop::cli_test;
using nlohmann::json;

// A body under the gravity gradient of a slow orbit and a damping of its rates: they fall from a
// few hundredths of rad/s to about 1e-5 rad/s over the span (the damping's time constant is
// I / 0.5 = 160 to 240 s). q has four different components, so that any reordering of them is
// another attitude.
const std::string damped_scene = R"(name = "gg-damped"
[body]
inertia = [120.0, 80.0, 100.0]
[torque]
M = ["-0.5*omega1", "-0.5*omega2", "-0.5*omega3"]
[torque.gravity_gradient]
mean_motion = 0.0001
[initial]
omega = [0.02, -0.015, 0.01]
q = [0.5, 0.5, 0.1, 0.7]
[span]
t_end = 1200.0
samples = 61
[reference]
precision = "quad"
)";

// dir/gg.toml and its reference dir/ref.csv (t, omega1..3, q0..q3 in columns 0..7); returns the
// reference's rows.
std::vector<std::vector<std::string>> write_reference(const fs::path& dir, const std::vector<std::string>& flags = {}) {
  write_file(dir / "gg.toml", damped_scene);
  std::vector<std::string> args = {"reference", "gg.toml", "--out", "ref.csv"};
  args.insert(args.end(), flags.begin(), flags.end());
  const run_result ref = run(dir, args);
  EXPECT_EQ(ref.exit_code, 0) << ref.err;
  std::vector<std::string> header;
  auto rows = table_rows(read_file(dir / "ref.csv"), &header);
  EXPECT_EQ(header, (std::vector<std::string>{"t", "omega1", "omega2", "omega3", "q0", "q1", "q2", "q3", "tau",
                                              "Omega1", "Omega2", "Omega3"}));
  EXPECT_EQ(rows.size(), 61u);
  return rows;
}

// A trajectory of the reference's rows: `header`, then for each row the cells `pick` returns.
template <class F>
std::string trajectory_of(const std::vector<std::vector<std::string>>& rows, const std::string& header, F pick) {
  std::string out = header + "\n";
  for (std::size_t i = 0; i < rows.size(); ++i) out += pick(i, rows[i]) + "\n";
  return out;
}

std::string join(const std::vector<std::string>& cells) {
  std::string out;
  for (std::size_t k = 0; k < cells.size(); ++k) out += (k ? "," : "") + cells[k];
  return out;
}

// The table's line that starts with `prefix`, or "".
std::string line_starting(const std::string& table, const std::string& prefix) {
  for (const std::string& l : lines_of(table))
    if (l.starts_with(prefix)) return l;
  return "";
}

// 1. A quaternion written scalar last (x, y, z, w) under the names q0..q3: the first row is named
// as disagreeing with [initial] q, with the convention it looks written in and the --columns that
// reads it; with that flag, it matches. A first row with other rates is named too, and one that is
// the initial state gets no line.
TEST(CheckHints, AScalarLastQuaternionIsNamedAtTheFirstRow) {
  temp_dir dir;
  const auto rows = write_reference(dir.path());
  ASSERT_EQ(rows.size(), 61u);
  const std::string header = "t,omega1,omega2,omega3,q0,q1,q2,q3";
  write_file(dir.path() / "xyzw.csv", trajectory_of(rows, header, [](std::size_t, const auto& c) {
               return join({c[0], c[1], c[2], c[3], c[5], c[6], c[7], c[4]});
             }));
  for (const std::string against : {"gg.toml", "ref.csv"}) {
    const run_result r = run(dir.path(), {"check", against, "xyzw.csv"});
    ASSERT_EQ(r.exit_code, 0) << against << ": " << r.err;
    const std::string line = line_starting(r.out, "initial state:");
    EXPECT_NE(line.find("the first row (t = 0 s, line 2) disagrees with the initial state of scene gg-damped "
                        "([initial] q)"),
              std::string::npos)
        << r.out;
    EXPECT_NE(line.find("the trajectory's q looks scalar-last (x, y, z, w); eulervop's q0..q3 are scalar-first "
                        "(w, x, y, z), Hamilton, body to inertial: give --columns q0=q3,q1=q0,q2=q1,q3=q2"),
              std::string::npos)
        << r.out;
    // The rates are the reference's: no line on them.
    EXPECT_EQ(r.out.find("([initial] omega)"), std::string::npos) << r.out;
    const run_result j = run(dir.path(), {"check", against, "xyzw.csv", "--format", "json"});
    ASSERT_EQ(j.exit_code, 0) << j.err;
    const json doc = json::parse(j.out);
    EXPECT_FALSE(doc.at("first_row_matches_initial_state").get<bool>());
    const json& first = doc.at("first_row_initial_state");
    EXPECT_EQ(first.at("line"), 2);
    EXPECT_TRUE(first.at("rates_match").get<bool>());
    EXPECT_FALSE(first.at("attitude_match").get<bool>());
    EXPECT_GT(first.at("attitude_difference").get<double>(), 0.1);
    EXPECT_NE(first.at("q_convention_hint").get<std::string>().find("scalar-last"), std::string::npos);
    // Read as the hint says, the same file matches, at every row.
    const run_result mapped = run(dir.path(), {"check", against, "xyzw.csv", "--columns", "q0=q3,q1=q0,q2=q1,q3=q2",
                                               "--format", "json"});
    ASSERT_EQ(mapped.exit_code, 0) << mapped.err;
    const json m = json::parse(mapped.out);
    EXPECT_TRUE(m.at("first_row_matches_initial_state").get<bool>());
    EXPECT_LT(m.at("max_attitude_error").get<double>(), 1e-30);
  }
  // The inverse rotation (inertial to body): q1..q3 negated.
  write_file(dir.path() / "inverse.csv", trajectory_of(rows, header, [](std::size_t, const auto& c) {
               const auto neg = [](const std::string& x) { return x.starts_with("-") ? x.substr(1) : "-" + x; };
               return join({c[0], c[1], c[2], c[3], c[4], neg(c[5]), neg(c[6]), neg(c[7])});
             }));
  const run_result inverse = run(dir.path(), {"check", "gg.toml", "inverse.csv"});
  ASSERT_EQ(inverse.exit_code, 0) << inverse.err;
  EXPECT_NE(inverse.out.find("the trajectory's q looks like the inverse rotation (inertial to body); eulervop's q0..q3 "
                             "are scalar-first (w, x, y, z), Hamilton, body to inertial: write the inverse (q1..q3 "
                             "negated)"),
            std::string::npos)
      << inverse.out;
  // Rates off by 1e-3 rad/s on the first row, against a bar of 1e-8 rad/s.
  write_file(dir.path() / "off.csv", trajectory_of(rows, header, [](std::size_t i, const auto& c) {
               const std::string w1 = i == 0 ? fmt::format("{}", std::stod(c[1]) + 1e-3) : c[1];
               return join({c[0], w1, c[2], c[3], c[4], c[5], c[6], c[7]});
             }));
  const run_result off = run(dir.path(), {"check", "gg.toml", "off.csv", "--tol", "1e-8", "--attitude-tol", "1e-8"});
  EXPECT_EQ(off.exit_code, 1) << off.err;
  EXPECT_NE(off.out.find("initial state: the first row (t = 0 s, line 2) disagrees with the initial state of scene "
                         "gg-damped ([initial] omega): off by 1.000e-03 rad/s, above 1.000e-08 rad/s (the bar)"),
            std::string::npos)
      << off.out;
  // The reference's own rows: no line, and true in the JSON.
  write_file(dir.path() / "same.csv", trajectory_of(rows, header, [](std::size_t, const auto& c) {
               return join({c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]});
             }));
  const run_result same = run(dir.path(), {"check", "gg.toml", "same.csv"});
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(same.out.find("initial state:"), std::string::npos) << same.out;
  const json s = json::parse(run(dir.path(), {"check", "gg.toml", "same.csv", "--format", "json"}).out);
  EXPECT_TRUE(s.at("first_row_matches_initial_state").get<bool>());
  // A trajectory that starts later is not held to the initial state: null.
  std::string later = read_file(dir.path() / "xyzw.csv");
  later.erase(later.find('\n') + 1, later.find('\n', later.find('\n') + 1) - later.find('\n'));
  write_file(dir.path() / "later.csv", later);
  const json l = json::parse(run(dir.path(), {"check", "gg.toml", "later.csv", "--format", "json"}).out);
  EXPECT_EQ(l.at("first_time").get<double>(), 20.0);
  EXPECT_TRUE(l.at("first_row_matches_initial_state").is_null());
  EXPECT_TRUE(l.at("first_row_initial_state").is_null());
}

// 2. A header in the user's own names: one line, exit 2, naming the --columns that maps them; that
// flag then reads the file.
TEST(CheckHints, UnknownColumnNamesAreToldTheColumnsFlag) {
  temp_dir dir;
  const auto rows = write_reference(dir.path());
  ASSERT_EQ(rows.size(), 61u);
  write_file(dir.path() / "mine.csv", trajectory_of(rows, "time,w1,w2,w3", [](std::size_t, const auto& c) {
               return join({c[0], c[1], c[2], c[3]});
             }));
  for (const std::string against : {"gg.toml", "ref.csv"}) {
    expect_one_line_error(run(dir.path(), {"check", against, "mine.csv"}),
                          "trajectory mine.csv: line 1: the header has no column `tau` (nor `t` for a physical or "
                          "coefficient-form scene); the header has time, w1, w2, w3: map them with --columns "
                          "t=time,omega1=w1,omega2=w2,omega3=w3 (for example)");
    const run_result mapped =
        run(dir.path(), {"check", against, "mine.csv", "--columns", "t=time,omega1=w1,omega2=w2,omega3=w3"});
    EXPECT_EQ(mapped.exit_code, 0) << mapped.err;
  }
  // The time found, the rates not.
  write_file(dir.path() / "rates.csv", trajectory_of(rows, "t,w1,w2,w3", [](std::size_t, const auto& c) {
               return join({c[0], c[1], c[2], c[3]});
             }));
  expect_one_line_error(run(dir.path(), {"check", "gg.toml", "rates.csv"}),
                        "line 1: the header has no column `omega1`; the header has t, w1, w2, w3: map them with "
                        "--columns omega1=w1,omega2=w2,omega3=w3 (for example)");
}

// 3a. Under a torque, c1^2 and c2^2 of Eq. 7 drift in any correct trajectory: no line in the
// table, null with the reason in the JSON; the normalized Eq. 20 figure is left out of the table
// (kept in the JSON, labelled). A torque-free body keeps both.
TEST(CheckHints, FiguresThatMeanNothingUnderATorqueAreLeftOut) {
  temp_dir dir;
  const auto rows = write_reference(dir.path());
  ASSERT_EQ(rows.size(), 61u);
  write_file(dir.path() / "rates.csv", trajectory_of(rows, "t,omega1,omega2,omega3", [](std::size_t, const auto& c) {
               return join({c[0], c[1], c[2], fmt::format("{:.12e}", std::stod(c[3]))});
             }));
  for (const std::string against : {"gg.toml", "ref.csv"}) {
    const run_result r = run(dir.path(), {"check", against, "rates.csv"});
    ASSERT_EQ(r.exit_code, 0) << against << ": " << r.err;
    EXPECT_EQ(r.out.find("invariant drift"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("c1^2"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("normalized (Eq. 20"), std::string::npos) << r.out;
    const json j = json::parse(run(dir.path(), {"check", against, "rates.csv", "--format", "json"}).out);
    EXPECT_TRUE(j.at("c1_squared_drift").is_null());
    EXPECT_TRUE(j.at("c2_squared_drift").is_null());
    EXPECT_NE(j.at("invariant_drift_note").get<std::string>().find("torque"), std::string::npos);
    EXPECT_GT(j.at("normalized_max_error").get<double>(), 0);
    EXPECT_EQ(j.at("normalized_error_unit"), "normalized Omega (Eq. 20, no unit)");
  }
  // The same body without a torque: the drift and the normalized figure are there.
  std::string free = damped_scene;
  free.replace(free.find("[torque]"), free.find("[initial]") - free.find("[torque]"), "");
  write_file(dir.path() / "free.toml", free);
  ASSERT_EQ(run(dir.path(), {"reference", "free.toml", "--out", "free.csv"}).exit_code, 0);
  const auto free_rows = table_rows(read_file(dir.path() / "free.csv"));
  write_file(dir.path() / "free_rates.csv",
             trajectory_of(free_rows, "t,omega1,omega2,omega3", [](std::size_t, const auto& c) {
               return join({c[0], c[1], c[2], fmt::format("{:.12e}", std::stod(c[3]))});
             }));
  const run_result r = run(dir.path(), {"check", "free.toml", "free_rates.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("invariant drift (Eq. 7"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("normalized (Eq. 20 in tau, Omega of Eq. 4; dimensionless, not rad/s): max error "),
            std::string::npos)
      << r.out;
}

// 3b. Rates that decay to about 1e-5 rad/s, checked with an error of 1e-11 rad/s on each: scd is
// low for a passing trajectory, and the table says what it measures and where the ratio is
// largest, with the reference's small value there.
TEST(CheckHints, ScdSaysWhatItMeasures) {
  temp_dir dir;
  const auto rows = write_reference(dir.path());
  ASSERT_EQ(rows.size(), 61u);
  double smallest = 1;
  for (const auto& c : rows) smallest = std::min(smallest, std::abs(std::stod(c[2])));
  ASSERT_LT(smallest, 1e-4);  // the damping brings the rates down
  write_file(dir.path() / "rates.csv", trajectory_of(rows, "t,omega1,omega2,omega3", [](std::size_t, const auto& c) {
               return join({c[0], fmt::format("{:.17e}", std::stod(c[1]) + 1e-11),
                            fmt::format("{:.17e}", std::stod(c[2]) + 1e-11),
                            fmt::format("{:.17e}", std::stod(c[3]) + 1e-11)});
             }));
  const run_result r = run(dir.path(), {"check", "gg.toml", "rates.csv", "--tol", "1e-10"});
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("result: PASS"), std::string::npos) << r.out;
  const std::string scd = line_starting(r.out, "scd: ");
  EXPECT_NE(scd.find("(significant correct digits: -log10 of the largest |error|/|ref| of a component; it is at "),
            std::string::npos)
      << r.out;
  EXPECT_TRUE(std::regex_search(scd, std::regex(R"(where \|omega[123]_ref\| = \d\.\d{3}e-\d\d rad/s\)$)"))) << scd;
  const std::string mescd = line_starting(r.out, "mescd: ");
  EXPECT_NE(mescd.find("atol 1.000e-12, rtol 1.000e-12"), std::string::npos) << mescd;
  const json j = json::parse(run(dir.path(), {"check", "gg.toml", "rates.csv", "--format", "json"}).out);
  EXPECT_LT(j.at("scd").get<double>(), 7);
  EXPECT_LT(j.at("scd_worst").at("reference_value").get<double>(), 1e-4);
  EXPECT_EQ(j.at("scd_worst").at("component").get<std::string>().substr(0, 5), "omega");
}

// 3c. One number format: every error and bar in the table with four significant digits, every
// time with at most six; no number anywhere with the 17 digits the error had before.
TEST(CheckHints, OneNumberFormatInTheTable) {
  temp_dir dir;
  const auto rows = write_reference(dir.path());
  ASSERT_EQ(rows.size(), 61u);
  // Times written with many digits, rates off by a little, q rotated off slightly.
  write_file(dir.path() / "traj.csv", trajectory_of(rows, "t,omega1,omega2,omega3,q0,q1,q2,q3",
                                                    [](std::size_t i, const auto& c) {
                                                      const double w3 = std::stod(c[3]) * (1 + 3e-9 * (i % 7));
                                                      const double q0 = std::stod(c[4]) * (1 + 1e-9 * (i % 5));
                                                      return join({c[0], c[1], c[2], fmt::format("{:.17e}", w3),
                                                                   fmt::format("{:.17e}", q0), c[5], c[6], c[7]});
                                                    }));
  const run_result r =
      run(dir.path(), {"check", "gg.toml", "traj.csv", "--tol", "1e-12", "--attitude-tol", "2.5e-9"});
  ASSERT_EQ(r.exit_code, 1) << r.err << r.out;
  // A run of 8 or more digits, but in the trajectory's file name: none.
  EXPECT_FALSE(std::regex_search(r.out, std::regex(R"(\d{8})"))) << r.out;
  const std::regex four(R"(\d\.\d{3}e[+-]\d\d)");
  for (const std::string prefix : {"max error: ", "rms error: ", "per component: ", "max attitude error: ",
                                   "rms attitude error: ", "tolerance: ", "attitude tolerance: "}) {
    const std::string line = line_starting(r.out, prefix);
    EXPECT_TRUE(std::regex_search(line, four)) << prefix << " in:\n" << r.out;
  }
  EXPECT_TRUE(std::regex_search(line_starting(r.out, "max error: "),
                                std::regex(R"(^max error: \d\.\d{3}e-\d\d rad/s at t = \d+ s \(line \d+\)$)")))
      << r.out;
  EXPECT_NE(r.out.find("tolerance: error <= 1.000e-12 rad/s"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("attitude tolerance: attitude error <= 2.500e-09 rad"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("computed to t = 1200 s"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("trajectory: traj.csv (61 rows, t from 0 s to 1200 s)"), std::string::npos) << r.out;
}

// 4. The reference's estimated error (--verify) is the normalized Eq. 20 figure for a physical
// scene: labelled so in the table and the JSON, and its rad/s figure (# estimated_max_error_omega)
// beside it, in the table where the errors are in rad/s.
TEST(CheckHints, TheReferencesEstimatedErrorCarriesItsUnit) {
  temp_dir dir;
  const auto rows = write_reference(dir.path(), {"--verify"});
  ASSERT_EQ(rows.size(), 61u);
  const std::string file = read_file(dir.path() / "ref.csv");
  ASSERT_NE(file.find("# estimated_max_error: "), std::string::npos);
  const std::size_t at = file.find("# estimated_max_error_omega: ");
  ASSERT_NE(at, std::string::npos) << file;
  const double omega_estimate = std::stod(file.substr(at + 29));
  write_file(dir.path() / "rates.csv", trajectory_of(rows, "t,omega1,omega2,omega3", [](std::size_t, const auto& c) {
               return join({c[0], c[1], c[2], c[3]});
             }));
  const run_result r = run(dir.path(), {"check", "ref.csv", "rates.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::regex_search(
      line_starting(r.out, "reference: "),
      std::regex(R"(estimated max error \d\.\d{3}e-\d\d \(normalized, Eq\. 20\), \d\.\d{3}e-\d\d rad/s\)$)")))
      << r.out;
  const json j = json::parse(run(dir.path(), {"check", "ref.csv", "rates.csv", "--format", "json"}).out);
  EXPECT_EQ(j.at("error_unit"), "rad/s");
  EXPECT_GT(j.at("reference").at("estimated_max_error").get<double>(), 0);
  // The words of the reference's own `# error_units:` line.
  EXPECT_EQ(j.at("reference").at("estimated_max_error_unit"), "normalized Omega (Eq. 20, no unit)");
  EXPECT_NE(file.find("estimated_max_error = normalized Omega (Eq. 20, no unit)"), std::string::npos);
  EXPECT_NE(file.find("estimated_max_error_omega = rad/s"), std::string::npos);
  EXPECT_EQ(j.at("reference").at("estimated_max_error_omega").get<double>(), omega_estimate);
  EXPECT_EQ(j.at("reference").at("estimated_max_error_omega_unit"), "rad/s");
  // Compared in tau and Omega: the table keeps the normalized figure alone.
  write_file(dir.path() / "normalized.csv",
             trajectory_of(rows, "tau,Omega1,Omega2,Omega3",
                           [](std::size_t, const auto& c) { return join({c[8], c[9], c[10], c[11]}); }));
  const run_result n = run(dir.path(), {"check", "ref.csv", "normalized.csv"});
  ASSERT_EQ(n.exit_code, 0) << n.err;
  EXPECT_TRUE(line_starting(n.out, "reference: ").ends_with("(normalized, Eq. 20))")) << n.out;
  // Without --verify: no figure, and no unit.
  ASSERT_EQ(run(dir.path(), {"reference", "gg.toml", "--out", "plain.csv"}).exit_code, 0);
  const json p = json::parse(run(dir.path(), {"check", "plain.csv", "rates.csv", "--format", "json"}).out);
  for (const char* key : {"estimated_max_error", "estimated_max_error_unit", "estimated_max_error_omega",
                          "estimated_max_error_omega_unit"})
    EXPECT_TRUE(p.at("reference").at(key).is_null()) << key;
}

}  // namespace
