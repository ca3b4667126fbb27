// `eulervop reference --certify` on the general path (docs/certified.md, "The general path"):
// every row's radii against independent oracles, the rows themselves those of the plain run, the
// same bytes on any number of threads, mpfr:256, breakpoints at irrational times, and the scenes
// it still refuses.
//
// Truth: tests/data/general_oracles/ (tools/oracles/coupled_taylor.py, Taylor series in mpmath at
// 45 and 70 digits, and tools/oracles/b5_closed_form.py, Jacobi's functions in mpmath at 90
// digits, each file's header giving its command and the agreement of its runs, 1e-42 relative or
// better) and tests/data/coupled_oracles/pd_law.csv. Errors are measured in MPFR at 256 bits, far
// below the quad rows' rounding (about 1e-34 relative).
//
// What must hold: each row's true error lies inside its radius (radius_omega in rad/s or radius of
// y, and radius_q of the quaternion), and the largest radius is at most 1e-29 times
// max(1, |y|) and at most 30 times the largest true error, or within 1000 ulps (quad) of the
// printed values where the true error is smaller still.
#include "cli_test_support.hpp"

#include <eulervop/core/scalar.hpp>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace {

using namespace eulervop::cli_test;
using eulervop::mpfr_real;

// A CSV file as written by `reference` or by an oracle: '#' lines, a header, rows of cells.
struct table {
  std::vector<std::string> meta, header;
  std::vector<std::vector<std::string>> rows;

  std::optional<std::size_t> column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) return std::nullopt;
    return static_cast<std::size_t>(it - header.begin());
  }
  std::string meta_value(const std::string& key) const {
    for (const std::string& l : meta)
      if (l.starts_with("# " + key + ": ")) return l.substr(key.size() + 4);
    return "";
  }
};

table read_table(const fs::path& path) {
  table t;
  for (const std::string& l : lines_of(read_file(path))) {
    if (l.empty()) continue;
    if (l[0] == '#') t.meta.push_back(l);
    else if (t.header.empty()) t.header = cells_of(l);
    else t.rows.push_back(cells_of(l));
  }
  return t;
}

mpfr_real number(const std::string& text) { return *eulervop::from_text<mpfr_real>(text); }

struct oracle_case {
  const char* label;
  const char* scene;   // under the source directory
  std::vector<std::string> args;
  const char* oracle;  // under tests/data
  bool coefficient;    // the state is y (radius), not omega (radius_omega)
};

// The worst true error and the largest radius of one group of columns, with every row checked.
struct group_result {
  mpfr_real error = 0, radius = 0, size = 0;
  std::size_t rows = 0;
};

group_result check_group(const table& ref, const table& oracle, const std::vector<std::string>& names,
                         const std::string& radius_name, const std::string& label) {
  group_result g;
  const std::size_t rc = *ref.column(radius_name);
  std::map<std::string, const std::vector<std::string>*> by_time;
  for (const auto& row : oracle.rows) by_time[row[0]] = &row;
  const std::size_t time = 0;
  for (const auto& row : ref.rows) {
    const mpfr_real t = number(row[time]);
    const std::vector<std::string>* truth = nullptr;
    for (const auto& [text, r] : by_time)
      if (number(text) == t) truth = r;
    if (!truth) continue;
    mpfr_real e2 = 0;
    for (const std::string& n : names) {
      const mpfr_real d = number(row[*ref.column(n)]) - number((*truth)[*oracle.column(n)]);
      e2 += d * d;
      g.size = std::max(g.size, mpfr_real(abs(number(row[*ref.column(n)]))));
    }
    const mpfr_real error = sqrt(e2), radius = number(row[rc]);
    EXPECT_LE(error, radius) << label << ": " << radius_name << " at t = " << row[time] << " misses the truth";
    g.error = std::max(g.error, error);
    g.radius = std::max(g.radius, radius);
    ++g.rows;
  }
  return g;
}

// The tightness the general path promises (see the header).
void expect_tight(const group_result& g, const std::string& what) {
  std::printf("%s: largest radius %.3g, largest true error %.3g, ratio %.3g, over %zu rows\n", what.c_str(),
              static_cast<double>(g.radius), static_cast<double>(g.error), static_cast<double>(g.radius / g.error),
              g.rows);
  const mpfr_real one = 1;
  EXPECT_LE(g.radius, mpfr_real("1e-29") * std::max(one, g.size)) << what;
  const mpfr_real ulps = 1000 * mpfr_real(std::ldexp(1.0, -112)) * std::max(one, g.size);
  EXPECT_TRUE(g.radius <= 30 * g.error || g.radius <= ulps)
      << what << ": radius " << g.radius << " against a true error of " << g.error;
}

class GeneralOracle : public ::testing::TestWithParam<oracle_case> {};

TEST_P(GeneralOracle, EveryRowInsideItsRadiiAndTheRadiiTight) {
  const eulervop::mpfr_precision_scope scope(256);
  const oracle_case& c = GetParam();
  temp_dir dir;
  std::vector<std::string> args = {"reference", source_dir + "/" + c.scene, "--certify", "--out", "c.csv"};
  args.insert(args.end(), c.args.begin(), c.args.end());
  const run_result r = run(dir.path(), args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const table ref = read_table(dir.path() / "c.csv");
  const table oracle = read_table(source_dir + "/tests/data/" + c.oracle);
  const std::vector<std::string> state = c.coefficient ? std::vector<std::string>{"y1", "y2", "y3"}
                                                       : std::vector<std::string>{"omega1", "omega2", "omega3"};
  const group_result rates = check_group(ref, oracle, state, c.coefficient ? "radius" : "radius_omega", c.label);
  EXPECT_GE(rates.rows, 4u) << c.label << ": the rows checked";
  expect_tight(rates, std::string(c.label) + " rates");
  if (ref.column("radius_q")) {
    const group_result q = check_group(ref, oracle, {"q0", "q1", "q2", "q3"}, "radius_q", c.label);
    expect_tight(q, std::string(c.label) + " q");
    EXPECT_EQ(number(ref.meta_value("certified_max_error_q")), q.radius) << c.label;
  }
  EXPECT_NE(ref.meta_value("certify_method").find("ball Chebyshev models"), std::string::npos) << c.label;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, GeneralOracle,
    ::testing::Values(
        oracle_case{"b5", "data/scenes/problems/enright-pryce-b5.toml", {"--samples", "11"}, "general_oracles/b5.csv",
                    true},
        oracle_case{"damped_ordered", "tests/scenes/general/damped_ordered.toml", {},
                    "general_oracles/damped_ordered.csv", false},
        oracle_case{"damped_unordered", "tests/scenes/general/damped_unordered.toml", {},
                    "general_oracles/damped_unordered.csv", false},
        oracle_case{"axisymmetric", "data/scenes/axisymmetric.toml", {"--samples", "7"},
                    "general_oracles/axisymmetric_attitude.csv", false},
        oracle_case{"near_symmetric", "data/scenes/hard/near-symmetric.toml", {"--samples", "7"},
                    "general_oracles/near_symmetric.csv", false},
        oracle_case{"free_attitude", "tests/scenes/general/free_attitude.toml", {},
                    "general_oracles/free_attitude.csv", false},
        oracle_case{"constant_attitude", "data/scenes/spacecraft-attitude.toml", {"--samples", "7"},
                    "general_oracles/constant_attitude.csv", false},
        oracle_case{"axisymmetric_attitude", "tests/scenes/general/axisymmetric_attitude.toml", {},
                    "general_oracles/axisymmetric_attitude.csv", false},
        oracle_case{"unordered_attitude", "tests/scenes/general/unordered_attitude.toml", {},
                    "general_oracles/unordered_attitude.csv", false},
        oracle_case{"pd_law", "tests/scenes/general/pd_law.toml", {}, "coupled_oracles/pd_law.csv", false},
        // Forcings that are not polynomials (tools/oracles/forced_taylor.py) and the gravity
        // gradient (tools/oracles/coupled_taylor.py).
        oracle_case{"eulr", "data/scenes/problems/hnw-eulr.toml", {"--samples", "11"}, "general_oracles/eulr.csv",
                    false},
        oracle_case{"sciml_10", "data/scenes/problems/sciml-rigid-body.toml", {"--samples", "11"},
                    "general_oracles/sciml_10.csv", true},
        oracle_case{"sciml_100", "data/scenes/problems/sciml-rigid-body-100.toml", {"--samples", "11"},
                    "general_oracles/sciml_100.csv", true},
        oracle_case{"gg_alone", "tests/scenes/general/gg-alone.toml", {}, "coupled_oracles/gg_alone.csv", false},
        oracle_case{"gg_unordered", "tests/scenes/general/gg-unordered.toml", {}, "coupled_oracles/gg_unordered.csv",
                    false},
        oracle_case{"gg_damped", "tests/scenes/general/gg-damped.toml", {}, "coupled_oracles/gg_damped.csv", false}),
    [](const auto& info) { return std::string(info.param.label); });

// The rows of a certified run are those of the plain run, cell for cell: the certificate only
// appends radii.
TEST(GeneralCertify, RowsAreThoseOfThePlainRun) {
  temp_dir dir;
  for (const char* scene : {"data/scenes/problems/enright-pryce-b5.toml", "data/scenes/attitude/pd-slew.toml",
                            "data/scenes/hard/near-symmetric.toml"}) {
    const std::string path = source_dir + "/" + scene;
    ASSERT_EQ(run(dir.path(), {"reference", path, "--certify", "--samples", "13", "--out", "c.csv"}).exit_code, 0);
    ASSERT_EQ(run(dir.path(), {"reference", path, "--samples", "13", "--out", "p.csv"}).exit_code, 0);
    const table c = read_table(dir.path() / "c.csv"), p = read_table(dir.path() / "p.csv");
    ASSERT_EQ(c.rows.size(), 13u) << scene;
    ASSERT_EQ(p.rows.size(), c.rows.size()) << scene;
    for (std::size_t i = 0; i < c.rows.size(); ++i) {
      ASSERT_GT(c.rows[i].size(), p.rows[i].size()) << scene;
      EXPECT_EQ(std::vector<std::string>(c.rows[i].begin(), c.rows[i].begin() + p.rows[i].size()), p.rows[i])
          << scene << " row " << i;
    }
    // The header names the radii after the plain run's columns.
    EXPECT_TRUE(std::equal(p.header.begin(), p.header.end(), c.header.begin())) << scene;
  }
}

// The radii are the same bytes whatever the number of threads: on one core (no worker: all in the
// integration's thread) and on the machine's.
TEST(GeneralCertify, RadiiAreTheSameOnOneThreadAndOnSeveral) {
  if (std::system("command -v taskset > /dev/null 2>&1") != 0) GTEST_SKIP() << "no taskset";
  temp_dir dir;
  const std::string scene = source_dir + "/data/scenes/attitude/pd-slew.toml";
  ASSERT_EQ(run(dir.path(), {"reference", scene, "--certify", "--samples", "61", "--out", "a.csv"}).exit_code, 0);
  const std::string one = "cd " + shell_quote(dir.path().string()) + " && taskset -c 0 " + shell_quote(binary) +
                          " reference " + shell_quote(scene) + " --certify --samples 61 --out b.csv";
  ASSERT_EQ(std::system(one.c_str()), 0);
  const table a = read_table(dir.path() / "a.csv"), b = read_table(dir.path() / "b.csv");
  EXPECT_EQ(a.rows, b.rows);
  for (const char* key : {"certified_max_error", "certified_max_error_omega", "certified_max_error_q"})
    EXPECT_EQ(a.meta_value(key), b.meta_value(key)) << key;
}

// mpfr:256 takes the same scenes, and its radii follow the precision.
TEST(GeneralCertify, Mpfr256CertifiesFarBelowQuad) {
  temp_dir dir;
  for (const char* scene : {"data/scenes/problems/enright-pryce-b5.toml", "data/scenes/attitude/pd-slew.toml"}) {
    const run_result r = run(dir.path(), {"reference", source_dir + "/" + scene, "--certify", "--precision",
                                          "mpfr:256", "--t-end", "5", "--samples", "6", "--out", "m.csv"});
    ASSERT_EQ(r.exit_code, 0) << scene << ": " << r.err;
    const table t = read_table(dir.path() / "m.csv");
    EXPECT_LT(std::strtod(t.meta_value("certified_max_error").c_str(), nullptr), 1e-70) << scene;
    if (t.column("radius_q")) EXPECT_LT(std::strtod(t.meta_value("certified_max_error_q").c_str(), nullptr), 1e-70);
  }
}

// SciML's rigid body to t = 10 in mpfr:256: every row within its radius of the 95-digit oracle, and
// the radius at most 1e-70.
TEST(GeneralCertify, SciMLInMpfr256IsCertifiedBelow1e70) {
  const eulervop::mpfr_precision_scope scope(400);
  temp_dir dir;
  const run_result r = run(dir.path(), {"reference", source_dir + "/data/scenes/problems/sciml-rigid-body.toml",
                                        "--certify", "--precision", "mpfr:256", "--samples", "11", "--out", "m.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const table ref = read_table(dir.path() / "m.csv");
  const group_result g = check_group(ref, read_table(source_dir + "/tests/data/general_oracles/sciml_10.csv"),
                                     {"y1", "y2", "y3"}, "radius", "sciml mpfr:256");
  EXPECT_EQ(g.rows, 11u);
  EXPECT_LE(g.radius, mpfr_real("1e-70"));
  std::printf("sciml mpfr:256: largest radius %.3g, largest true error %.3g\n", static_cast<double>(g.radius),
              static_cast<double>(g.error));
}

// A physical scene with polynomial pieces at decimal times: in tau = t dtau/dt each breakpoint is
// irrational, so the reference's breakpoint (a quad number) and the exact one differ. The radius
// covers the distance to an mpfr:256 run of the same scene (whose breakpoints are 2^-256 close to
// the exact ones), and to the truth through it.
TEST(GeneralCertify, PiecesAtIrrationalBreakpointsAreCrossed) {
  const eulervop::mpfr_precision_scope scope(256);
  temp_dir dir;
  write_file(dir.path() / "s.toml", R"(name = "thrusts"
[body]
inertia = [100.0, 150.0, 200.0]
[torque]
M = [0.01, -0.02, "0.005 - 0.2*omega3"]
[[torque.piece]]
from = 100.1
to = 300.7
M = ["0.05 + 0.001*t", 0.0, "-0.3*omega3"]
[initial]
omega = [0.02, 0.1, 0.05]
q = [1.0, 0.0, 0.0, 0.0]
[span]
t_end = 600.0
samples = 13
)");
  const run_result c = run(dir.path(), {"reference", "s.toml", "--certify", "--out", "c.csv"});
  ASSERT_EQ(c.exit_code, 0) << c.err;
  ASSERT_EQ(run(dir.path(), {"reference", "s.toml", "--precision", "mpfr:256", "--out", "m.csv"}).exit_code, 0);
  const table ref = read_table(dir.path() / "c.csv"), wide = read_table(dir.path() / "m.csv");
  // The mpfr:256 run is about 1e-70 from the truth, far inside any radius here.
  const group_result w = check_group(ref, wide, {"omega1", "omega2", "omega3"}, "radius_omega", "pieces");
  const group_result q = check_group(ref, wide, {"q0", "q1", "q2", "q3"}, "radius_q", "pieces");
  EXPECT_EQ(w.rows, 13u);
  expect_tight(w, "pieces: rates");
  expect_tight(q, "pieces: q");
}

// A formula undefined where its argument may lie on a segment (a division by a value that may be
// 0, the log or the square root of one that may not be positive) stops the certificate with exit
// 3: the time, the formula, why, and its piece; no file. The plain runs of these scenes pass: their
// values stay defined (0 log(Omega1^2) is 0 wherever Omega1 is not exactly 0).
TEST(GeneralCertify, AnUndefinedFormulaStopsAtItsPlace) {
  temp_dir dir;
  const auto scene = [](const std::string& base, const std::string& piece) {
    return "name = \"u\"\n[torque]\nG = [" + base + ", 0.0, 0.0]\n[[torque.piece]]\nfrom = 1.0\nto = 30.0\nG = [" +
           piece + ", 0.0, 0.0]\n[initial]\nc1 = 0.5\nc2 = 1.0\nu = 0.0\n[span]\ntau_end = 20.0\nsamples = 5\n";
  };
  struct fault {
    std::string base, piece, formula, why, where;
  };
  for (const fault& f : {fault{"\"0.001*Omega1/Omega1\"", "0.0", "G1 = `0.001*Omega1/Omega1`",
                               "a division by a value that may be 0", "numerical failure at tau="},
                         fault{"0.0", "\"0*log(Omega1^2)\"", "G1 = `0*log(Omega1^2)`",
                               "the log of a value that is not certainly positive in the piece [1.0, 30.0)",
                               "numerical failure at tau=1:"},
                         fault{"0.0", "\"0*sqrt(Omega1^2)\"", "G1 = `0*sqrt(Omega1^2)`",
                               "the square root of a value that is not certainly positive in the piece [1.0, 30.0)",
                               "numerical failure at tau=1:"}}) {
    write_file(dir.path() / "s.toml", scene(f.base, f.piece));
    ASSERT_EQ(run(dir.path(), {"reference", "s.toml", "--out", "plain.csv"}).exit_code, 0) << f.formula;
    const run_result r = run(dir.path(), {"reference", "s.toml", "--certify", "--out", "x.csv"});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(f.where), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(f.formula + ": " + f.why), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("higher precision"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir.path() / "x.csv"));
  }
}

// Saturations and hyperbolic functions (tanh, atan, sinh, cosh) of the state and of the time, in
// the coefficient form with a = 0, where each equation stands alone and has a closed form:
//   y1' = -tanh y1:        sinh y1 = sinh(y1(0)) e^-t, so y1 = asinh(sinh(1.5) e^-t);
//   y2' = -0.2 cosh y2:    gd(y2) = gd(y2(0)) - 0.2 t with gd(y) = atan(sinh y) (d gd / dy =
//                          1 / cosh y), so y2 = asinh(tan(atan(sinh 1) - 0.2 t)) while
//                          |atan(sinh 1) - 0.2 t| < pi/2 (to t = 10: -1.13);
//   y3' = 0.1 tanh(t - 5) + atan(t/2 - 1) + sinh(t/5):
//       y3 = -0.5 + 0.1 log(cosh(t - 5) / cosh 5) + 2 [u atan u - log(1 + u^2) / 2] from u = -1 to
//       t/2 - 1, + 5 (cosh(t/5) - 1).
// Every row lies within its radius of the closed form (MPFR at 256 bits), and the radii are tight.
TEST(GeneralCertify, SaturationsHoldTheirClosedForms) {
  const eulervop::mpfr_precision_scope scope(256);
  temp_dir dir;
  write_file(dir.path() / "s.toml", R"toml(name = "saturations"
[equations]
a = [0.0, 0.0, 0.0]
[torque]
f = ["-tanh(y1)", "-0.2*cosh(y2)", "0.1*tanh(t - 5) + atan(t/2 - 1) + sinh(t/5)"]
[initial]
y = [1.5, 1.0, -0.5]
[span]
t_end = 10.0
samples = 21
)toml");
  const run_result r = run(dir.path(), {"reference", "s.toml", "--certify", "--out", "c.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const table t = read_table(dir.path() / "c.csv");
  ASSERT_EQ(t.rows.size(), 21u);
  const auto antiderivative = [](const mpfr_real& u) { return u * atan(u) - log(1 + u * u) / 2; };
  group_result g;
  for (const auto& row : t.rows) {
    const mpfr_real time = number(row[0]);
    const std::array<mpfr_real, 3> y = {
        asinh(sinh(mpfr_real("1.5")) * exp(-time)), asinh(tan(atan(sinh(mpfr_real(1))) - mpfr_real("0.2") * time)),
        mpfr_real("-0.5") + mpfr_real("0.1") * log(cosh(time - 5) / cosh(mpfr_real(5))) +
            2 * (antiderivative(time / 2 - 1) - antiderivative(mpfr_real(-1))) + 5 * (cosh(time / 5) - 1)};
    mpfr_real e2 = 0;
    for (int i = 0; i < 3; ++i) {
      const mpfr_real v = number(row[*t.column("y" + std::to_string(i + 1))]);
      e2 += (v - y[i]) * (v - y[i]);
      g.size = std::max(g.size, mpfr_real(abs(v)));
    }
    const mpfr_real radius = number(row[*t.column("radius")]);
    EXPECT_LE(sqrt(e2), radius) << "at t = " << row[0];
    g.radius = std::max(g.radius, radius);
    g.error = std::max(g.error, mpfr_real(sqrt(e2)));
    ++g.rows;
  }
  EXPECT_GT(g.error, 0);  // the rows are quad numbers: the closed form is not among them
  expect_tight(g, "saturations");
}

// A body's rate damping saturated by tanh (M_i = -0.5 tanh(omega_i / 0.05), the torque's bound
// 0.5 N m reached for |omega_i| >> 0.05 rad/s and linear below), with an atan disturbance, and its
// attitude: every row within its radii of an mpfr:256 run of the same scene (about 1e-70 from the
// truth, far inside any radius here), and the radii tight.
TEST(GeneralCertify, SaturatedRateDampingIsCovered) {
  const eulervop::mpfr_precision_scope scope(256);
  temp_dir dir;
  write_file(dir.path() / "s.toml", R"toml(name = "saturated damping"
[body]
inertia = [100.0, 150.0, 200.0]
[torque]
M = ["-0.5*tanh(omega1/0.05)", "-0.5*tanh(omega2/0.05) + 0.01*atan(t - 20)", "-0.5*tanh(omega3/0.05)"]
[initial]
omega = [0.3, -0.2, 0.1]
q = [1.0, 0.0, 0.0, 0.0]
[span]
t_end = 60.0
samples = 13
)toml");
  const run_result c = run(dir.path(), {"reference", "s.toml", "--certify", "--out", "c.csv"});
  ASSERT_EQ(c.exit_code, 0) << c.err;
  ASSERT_EQ(run(dir.path(), {"reference", "s.toml", "--precision", "mpfr:256", "--out", "m.csv"}).exit_code, 0);
  const table ref = read_table(dir.path() / "c.csv"), wide = read_table(dir.path() / "m.csv");
  const group_result w = check_group(ref, wide, {"omega1", "omega2", "omega3"}, "radius_omega", "saturated");
  const group_result q = check_group(ref, wide, {"q0", "q1", "q2", "q3"}, "radius_q", "saturated");
  EXPECT_EQ(w.rows, 13u);
  expect_tight(w, "saturated: rates");
  expect_tight(q, "saturated: q");
}

// check against a certified file of a body in the direct form reads its radius_omega.
TEST(GeneralCertify, CheckReadsTheDirectFormsRadius) {
  temp_dir dir;
  const std::string scene = source_dir + "/data/scenes/axisymmetric.toml";
  ASSERT_EQ(run(dir.path(), {"reference", scene, "--certify", "--samples", "7", "--out", "ref.csv"}).exit_code, 0);
  const table ref = read_table(dir.path() / "ref.csv");
  EXPECT_EQ(ref.header, (std::vector<std::string>{"t", "omega1", "omega2", "omega3", "radius_omega"}));
  std::string traj = "t,omega1,omega2,omega3\n";
  for (const auto& row : ref.rows) traj += fmt::format("{},{},{},{}\n", row[0], row[1], row[2], row[3]);
  write_file(dir.path() / "traj.csv", traj);
  const run_result r = run(dir.path(), {"check", "ref.csv", "traj.csv", "--tol", "1e-20", "--format", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"certified_reference\": true"), std::string::npos) << r.out;
}

// Closed forms: with a = 0 the solution is y0 + int f, a polynomial here (the coefficient form);
// an axisymmetric body without torque keeps omega3 and turns (omega1, omega2) at the rate
// lambda = (I3 - I1) omega3 / I1 (Eq. 1 with I1 = I2: omega1' = -lambda omega2,
// omega2' = lambda omega1; the direct form). Each row lies within its radius of the exact value,
// and the radii are within 1000 ulps of the printed digits (the true errors are the reference's
// rounding).
TEST(GeneralCertify, ClosedForms) {
  const eulervop::mpfr_precision_scope scope(256);
  temp_dir dir;
  write_file(dir.path() / "poly.toml", R"(name = "poly"
[equations]
a = [0.0, 0.0, 0.0]
[torque]
f = ["1 + t", "t^2 - 0.5", "-t^3/3"]
[initial]
y = [0.25, -1.0, 2.0]
[span]
t_end = 3.0
samples = 7
)");
  write_file(dir.path() / "axi.toml", R"(name = "axi"
[body]
inertia = [2.0, 2.0, 3.0]
[initial]
omega = [0.3, -0.2, 1.1]
[span]
t_end = 40.0
samples = 9
)");
  ASSERT_EQ(run(dir.path(), {"reference", "poly.toml", "--certify", "--out", "p.csv"}).exit_code, 0);
  ASSERT_EQ(run(dir.path(), {"reference", "axi.toml", "--certify", "--out", "a.csv"}).exit_code, 0);
  const auto check = [&](const char* file, const char* state, const char* radius,
                         const std::function<std::array<mpfr_real, 3>(const mpfr_real&)>& exact) {
    const table t = read_table(dir.path() / file);
    group_result g;
    for (const auto& row : t.rows) {
      const std::array<mpfr_real, 3> y = exact(number(row[0]));
      mpfr_real e2 = 0;
      for (int i = 0; i < 3; ++i) {
        const mpfr_real v = number(row[*t.column(std::string(state) + std::to_string(i + 1))]);
        e2 += (v - y[i]) * (v - y[i]);
        g.size = std::max(g.size, mpfr_real(abs(v)));
      }
      const mpfr_real r = number(row[*t.column(radius)]);
      EXPECT_LE(sqrt(e2), r) << file << " at t = " << row[0];
      g.radius = std::max(g.radius, r);
      g.error = std::max(g.error, mpfr_real(sqrt(e2)));
    }
    EXPECT_LE(g.radius, 1000 * mpfr_real(std::ldexp(1.0, -112)) * std::max(mpfr_real(1), g.size)) << file;
  };
  check("p.csv", "y", "radius", [](const mpfr_real& t) {
    return std::array<mpfr_real, 3>{mpfr_real("0.25") + t + t * t / 2, -1 + t * t * t / 3 - t / 2,
                                    2 - t * t * t * t / 12};
  });
  check("a.csv", "omega", "radius_omega", [](const mpfr_real& t) {
    const mpfr_real w3("1.1"), lambda = (mpfr_real(3) - 2) * w3 / 2, A("0.3"), B("-0.2");
    return std::array<mpfr_real, 3>{A * cos(lambda * t) - B * sin(lambda * t), A * sin(lambda * t) + B * cos(lambda * t),
                                    w3};
  });
}

}  // namespace
