// `eulervop check`: an outside integrator's trajectory (Boost.Odeint dopri5, made here) checked
// against the paper's scene and against a reference file; the reported max error against one
// computed independently here; the exit code around the tolerance; and bad files, each one line
// naming the line and column, exit 2.
#include "cli_test_support.hpp"

#include <eulervop/reference/integrate.hpp>
#include <eulervop/model/error_measure.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/model/integrals.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/core/quaternion.hpp>
#include <eulervop/core/scalar.hpp>

#include <boost/numeric/odeint.hpp>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace odeint = boost::numeric::odeint;
using namespace eulervop::cli_test;
using eulervop::quad;
using nlohmann::json;
using state = std::array<double, 3>;

constexpr double tau_end = 20;
constexpr int n_times = 200;

// The paper's scene (data/scenes/paper-fig1.toml): G = (1,1,1), c1 = 0.5, c2 = 1, u = 0, so
// Omega(0) = (c1, 0, c2) exactly.
const state G = {1, 1, 1};
const state Omega0 = {0.5, 0, 1};

std::string paper_scene() { return source_dir + "/data/scenes/paper-fig1.toml"; }

// The outside integrator's trajectory: Boost.Odeint dopri5, dense output, tolerance 1e-10,
// at tau_i = 20 i / 199 (i = 0..199). Times are written as their shortest round-trip text and
// states with 17 digits, as another tool would write them.
struct trajectory {
  std::vector<std::string> tau_text;
  std::vector<state> Omega;
  std::string csv(const std::string& header = "tau,Omega1,Omega2,Omega3") const {
    std::string out = header + "\n";
    for (std::size_t i = 0; i < Omega.size(); ++i)
      out += fmt::format("{},{:.17g},{:.17g},{:.17g}\n", tau_text[i], Omega[i][0], Omega[i][1], Omega[i][2]);
    return out;
  }
};

const trajectory& odeint_trajectory() {
  static const trajectory traj = [] {
    std::vector<double> times;
    for (int i = 0; i < n_times; ++i) times.push_back(tau_end * i / (n_times - 1));
    auto rhs = [](const state& x, state& dxdt, double) {
      dxdt[0] = G[0] - x[1] * x[2];
      dxdt[1] = G[1] + x[0] * x[2];
      dxdt[2] = G[2] - x[0] * x[1];
    };
    trajectory t;
    state x = Omega0;
    odeint::integrate_times(odeint::make_dense_output(1e-10, 1e-10, odeint::runge_kutta_dopri5<state>()), rhs, x,
                            times.begin(), times.end(), 1e-3, [&](const state& s, double tau) {
                              t.tau_text.push_back(fmt::format("{}", tau));
                              t.Omega.push_back(s);
                            });
    return t;
  }();
  return traj;
}

// The max Eq. 20 error computed here, independently of the program: a quad reference of the same
// problem and the error at each row's time as written (its decimal text read in quad).
struct independent_error {
  double max = -1;
  std::size_t row = 0;
};

const independent_error& odeint_error() {
  static const independent_error e = [] {
    eulervop::euler_problem<quad> p;
    p.torque.G = {quad(1), quad(1), quad(1)};
    p.Omega0 = {quad("0.5"), quad(0), quad(1)};
    const eulervop::dense_trajectory<quad> ref = eulervop::integrate_reference<quad>(p, quad(tau_end));
    const trajectory& t = odeint_trajectory();
    independent_error out;
    for (std::size_t i = 0; i < t.Omega.size(); ++i) {
      eulervop::vec3<quad> Om;  // the 17-digit text, as the program reads it
      for (int k = 0; k < 3; ++k) Om[k] = quad(fmt::format("{:.17g}", t.Omega[i][k]));
      const double err = static_cast<double>(eulervop::eq20_error(ref(quad(t.tau_text[i])), Om));
      if (err > out.max) {
        out.max = err;
        out.row = i;
      }
    }
    return out;
  }();
  return e;
}

int count_lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

TEST(Check, OdeintTrajectoryAgainstTheSceneMatchesAnIndependentError) {
  temp_dir dir;
  write_file(dir.path() / "traj.csv", odeint_trajectory().csv());
  const run_result r = run(dir.path(), {"check", paper_scene(), "traj.csv", "--format", "json", "--errors-out", "e.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  const independent_error& mine = odeint_error();
  // dopri5 at 1e-10 over tau = 20: an error well above the quad reference's, well below 1e-6.
  EXPECT_GT(mine.max, 1e-12);
  EXPECT_LT(mine.max, 1e-6);
  const double reported = j.at("max_error").get<double>();
  EXPECT_NEAR(reported, mine.max, 1e-6 * mine.max) << r.out;
  std::printf("max Eq. 20 error: reported %.17g, independent %.17g (relative difference %.2e), line %zu\n", reported,
              mine.max, std::abs(reported - mine.max) / mine.max, mine.row + 2);
  EXPECT_EQ(j.at("max_error_line").get<std::size_t>(), mine.row + 2);  // header is line 1
  EXPECT_EQ(j.at("rows").get<int>(), n_times);
  EXPECT_EQ(j.at("reference").at("precision"), "quad");
  EXPECT_TRUE(j.at("tol").is_null());
  EXPECT_TRUE(j.at("pass").is_null());  // no bar, no verdict
  EXPECT_GT(j.at("rms_error").get<double>(), 0);
  EXPECT_LE(j.at("rms_error").get<double>(), reported);
  // The per-row file: a header and one line per row, the max among them.
  const std::vector<std::string> lines = lines_of(read_file(dir.path() / "e.csv"));
  ASSERT_EQ(lines.size(), static_cast<std::size_t>(n_times + 1));
  EXPECT_EQ(lines[0], "line,tau,error,bar");
  EXPECT_EQ(lines[1].substr(0, 4), "2,0,");
}

TEST(Check, ExitCodeFlipsAroundTheMaxError) {
  temp_dir dir;
  write_file(dir.path() / "traj.csv", odeint_trajectory().csv());
  const run_result first = run(dir.path(), {"check", paper_scene(), "traj.csv", "--format", "json"});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const double max = json::parse(first.out).at("max_error").get<double>();  // the reported max
  const run_result above =
      run(dir.path(), {"check", paper_scene(), "traj.csv", "--tol", fmt::format("{}", max * (1 + 1e-9))});
  EXPECT_EQ(above.exit_code, 0) << above.out << above.err;
  EXPECT_NE(above.out.find("PASS"), std::string::npos) << above.out;
  const run_result below = run(dir.path(), {"check", paper_scene(), "traj.csv", "--tol",
                                            fmt::format("{}", max * (1 - 1e-9)), "--format", "json"});
  EXPECT_EQ(below.exit_code, 1) << below.out << below.err;
  const json j = json::parse(below.out);
  EXPECT_FALSE(j.at("pass").get<bool>());
  EXPECT_EQ(j.at("exceeding_rows").get<int>(), 1);
  EXPECT_EQ(j.at("first_exceeding_line"), j.at("max_error_line"));
  // --rel-tol: |Omega_ref| stays above 1/4 here, so R = 4 max gives a bar above max.
  const run_result rel =
      run(dir.path(), {"check", paper_scene(), "traj.csv", "--rel-tol", fmt::format("{}", 4 * max)});
  EXPECT_EQ(rel.exit_code, 0) << rel.out << rel.err;
}

TEST(Check, AgainstAReferenceFileAndRenamedColumns) {
  temp_dir dir;
  // The reference at the same times (20 i / 199: --samples 200), and the trajectory with other
  // column names.
  const run_result ref = run(dir.path(), {"reference", paper_scene(), "--tau-end", "20", "--samples", "200", "--out", "ref.csv"});
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  std::string csv = "time,w1,w2,w3\n" + odeint_trajectory().csv().substr(odeint_trajectory().csv().find('\n') + 1);
  write_file(dir.path() / "traj.csv", csv);
  const run_result r = run(dir.path(), {"check", "ref.csv", "traj.csv", "--columns", "tau=time,Omega1=w1,Omega2=w2,Omega3=w3",
                                        "--format", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j.at("reference").at("source"), "file");
  EXPECT_EQ(j.at("time_column"), "time");
  EXPECT_NEAR(j.at("max_error").get<double>(), odeint_error().max, 1e-6 * odeint_error().max);

  // A time that is not one of the reference's samples: exit 2, naming it and its neighbours.
  std::vector<std::string> lines = lines_of(csv);
  lines.insert(lines.begin() + 3, "0.15,0.5,0,1");  // between 20/199 and 40/199
  std::string with_extra;
  for (const auto& l : lines) with_extra += l + "\n";
  write_file(dir.path() / "extra.csv", with_extra);
  const run_result missing = run(dir.path(), {"check", "ref.csv", "extra.csv", "--columns", "tau=time,Omega1=w1,Omega2=w2,Omega3=w3"});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(count_lines(missing.err), 1) << missing.err;
  EXPECT_NE(missing.err.find("line 4: time = 0.15 is not a sample time"), std::string::npos) << missing.err;

  // --columns naming a column the file does not have.
  const run_result unmapped = run(dir.path(), {"check", "ref.csv", "traj.csv", "--columns", "tau=time,Omega1=x1"});
  EXPECT_EQ(unmapped.exit_code, 2);
  EXPECT_NE(unmapped.err.find("no column `x1` (for Omega1 by --columns)"), std::string::npos) << unmapped.err;
}

// ref.csv in `dir`: a physical scene's reference in double to t = 600 s, 61 samples.
void write_double_reference(const fs::path& dir, const std::string& scene) {
  const run_result ref =
      run(dir, {"reference", scene, "--t-end", "600", "--samples", "61", "--precision", "double", "--out", "ref.csv"});
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
}

TEST(Check, PhysicalTrajectoryInTAndOmega) {
  temp_dir dir;
  const std::string scene = source_dir + "/data/scenes/spacecraft-physical.toml";
  ASSERT_NO_FATAL_FAILURE(write_double_reference(dir.path(), scene));
  // The reference's own t, omega columns as a trajectory: errors at double rounding.
  std::string traj = "t,omega1,omega2,omega3\n";
  bool header_seen = false;
  for (const std::string& l : lines_of(read_file(dir.path() / "ref.csv"))) {
    if (l.starts_with("#")) continue;
    if (!header_seen) {
      header_seen = true;
      continue;
    }
    std::vector<std::string> cells;
    std::size_t b = 0;
    for (std::size_t c; (c = l.find(',', b)) != std::string::npos; b = c + 1) cells.push_back(l.substr(b, c - b));
    cells.push_back(l.substr(b));
    traj += fmt::format("{},{},{},{}\n", cells[0], cells[1], cells[2], cells[3]);
  }
  write_file(dir.path() / "traj.csv", traj);
  for (const std::string& against : {scene, std::string("ref.csv")}) {
    const run_result r = run(dir.path(), {"check", against, "traj.csv", "--rel-tol", "1e-12", "--format", "json"});
    ASSERT_EQ(r.exit_code, 0) << against << ": " << r.err << r.out;
    const json j = json::parse(r.out);
    EXPECT_EQ(j.at("time_column"), "t");
    EXPECT_EQ(j.at("rows").get<int>(), 61);
    EXPECT_LT(j.at("max_error").get<double>(), 1e-12) << against;
  }
  // A physical trajectory against a normalized scene is bad input.
  const run_result wrong = run(dir.path(), {"check", paper_scene(), "traj.csv"});
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.err.find("normalized"), std::string::npos) << wrong.err;
}

// An axisymmetric body is integrated in the direct form: its reference has t and omega only, and
// check takes a t, omega trajectory against the scene or that file, with no Eq. 7 drift (it
// does not apply) and the split along the motion of Eq. 1's own right-hand side.
TEST(Check, AxisymmetricBodyInTheDirectForm) {
  temp_dir dir;
  const std::string scene = source_dir + "/data/scenes/axisymmetric.toml";
  ASSERT_NO_FATAL_FAILURE(write_double_reference(dir.path(), scene));
  std::string traj;
  for (const std::string& l : lines_of(read_file(dir.path() / "ref.csv")))
    if (!l.starts_with("#")) traj += l + "\n";
  ASSERT_TRUE(traj.starts_with("t,omega1,omega2,omega3\n")) << traj.substr(0, 80);
  write_file(dir.path() / "traj.csv", traj);
  for (const std::string& against : {scene, std::string("ref.csv")}) {
    const run_result r = run(dir.path(), {"check", against, "traj.csv", "--rel-tol", "1e-12", "--format", "json"});
    ASSERT_EQ(r.exit_code, 0) << against << ": " << r.err << r.out;
    const json j = json::parse(r.out);
    EXPECT_EQ(j.at("rows").get<int>(), 61);
    EXPECT_LT(j.at("max_error").get<double>(), 1e-12) << against;  // double rounding of a quad-free run
    EXPECT_TRUE(j.at("c1_squared_drift").is_null()) << against;
    EXPECT_TRUE(j.at("max_error_along_motion").is_number()) << against;
  }
  // tau and Omega do not exist for this body.
  write_file(dir.path() / "norm.csv", "tau,Omega1,Omega2,Omega3\n0,0.02,0.01,0.05\n");
  const run_result wrong = run(dir.path(), {"check", scene, "norm.csv"});
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.err.find("direct form"), std::string::npos) << wrong.err;
  EXPECT_EQ(std::count(wrong.err.begin(), wrong.err.end(), '\n'), 1) << wrong.err;
}

// ---- bad files: one line naming the line and the column, exit 2, no errors file -----------------

struct bad_file {
  std::string name;
  std::string (*make)(const std::string& good);
  std::string expected;  // a part of the message
};

std::string replace_line(const std::string& text, std::size_t index, const std::string& with) {
  std::vector<std::string> lines = lines_of(text);
  lines[index] = with;
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

// Line `index` (0-based) with its cell `cell` replaced by `with`.
std::string replace_cell(const std::string& text, std::size_t index, std::size_t cell, const std::string& with) {
  std::vector<std::string> lines = lines_of(text);
  std::string& l = lines[index];
  std::size_t begin = 0;
  for (std::size_t c = 0; c < cell; ++c) begin = l.find(',', begin) + 1;
  const std::size_t end = l.find(',', begin);
  l = l.substr(0, begin) + with + (end == std::string::npos ? "" : l.substr(end));
  std::string out;
  for (const auto& x : lines) out += x + "\n";
  return out;
}

std::vector<bad_file> bad_files() {
  return {
      {"truncated",
       [](const std::string& good) {
         // The last line cut in the middle of its third cell, no final newline.
         std::string t = good.substr(0, good.size() - 1);
         const std::size_t last = t.rfind('\n');
         const std::size_t second_comma = t.find(',', t.find(',', last + 1) + 1);
         return t.substr(0, second_comma + 4);
       },
       "line 201: 3 cells, the header has 4: no column Omega3"},
      {"non_numeric",
       [](const std::string& good) { return replace_cell(good, 50, 2, "abc"); },
       "line 51: column Omega2 = `abc` is not a number"},
      {"missing_column",
       [](const std::string& good) { return replace_line(good, 0, "tau,Omega1,Omega2,Omega4"); },
       "line 1: the header has no column `Omega3`"},
      {"non_monotonic",
       [](const std::string& good) {
         std::vector<std::string> lines = lines_of(good);
         std::swap(lines[100], lines[101]);
         std::string out;
         for (const auto& l : lines) out += l + "\n";
         return out;
       },
       "line 102: column tau = "},
      {"empty_cell",
       [](const std::string& good) { return replace_cell(good, 7, 1, ""); },
       "line 8: column Omega1 = `` is empty"},
  };
}

class BadFile : public ::testing::TestWithParam<bad_file> {};

TEST_P(BadFile, OneLineNamingTheLineAndColumnExitTwo) {
  temp_dir dir;
  const bad_file& b = GetParam();
  write_file(dir.path() / "traj.csv", b.make(odeint_trajectory().csv()));
  const run_result r = run(dir.path(), {"check", paper_scene(), "traj.csv", "--tol", "1", "--errors-out", "e.csv"});
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_TRUE(r.err.starts_with("eulervop: error: trajectory traj.csv: ")) << r.err;
  EXPECT_NE(r.err.find(b.expected), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_FALSE(fs::exists(dir.path() / "e.csv"));
}

INSTANTIATE_TEST_SUITE_P(Table, BadFile, ::testing::ValuesIn(bad_files()),
                         [](const ::testing::TestParamInfo<bad_file>& info) { return info.param.name; });

TEST(Check, BadFlags) {
  temp_dir dir;
  write_file(dir.path() / "traj.csv", odeint_trajectory().csv());
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"check", paper_scene(), "traj.csv", "--tol", "-1"},
           {"check", paper_scene(), "traj.csv", "--format", "yaml"},
           {"check", paper_scene(), "traj.csv", "--columns", "time"},
           {"check", paper_scene(), "missing.csv"},
           {"check", paper_scene()},
           {"check", paper_scene(), "traj.csv", "--scd-atol", "0"},
           {"check", paper_scene(), "traj.csv", "--scd-rtol", "-1e-12"},
       }) {
    const run_result r = run(dir.path(), args);
    EXPECT_EQ(r.exit_code, 2) << args.back() << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
  }
}

// The oracle metrics on a hand-made reference file and trajectory, where each is known in closed
// form. The scene text (G = 0) gives the direction of motion, f(Omega_ref) of Eq. 5. Rows:
//   tau 0:   reference (1, 0, 2),   trajectory equal;
//   tau 0.5: reference (0.5, 1, 2), trajectory Omega2 + 0.001;
//   tau 1:   reference (0, 2, 4),   trajectory Omega1 + 0.01 (reference component 0: not in scd).
TEST(Check, OracleMetricsOnAHandMadeTrajectory) {
  temp_dir dir;
  write_file(dir.path() / "ref.csv",
             "# precision: quad\n"
             "# scene_text: name = \"hand\"\n# scene_text: [torque]\n# scene_text: G = [0.0, 0.0, 0.0]\n"
             "# scene_text: [initial]\n# scene_text: Omega = [1.0, 0.0, 2.0]\n"
             "# scene_text: [span]\n# scene_text: tau_end = 1.0\n# scene_text: samples = 3\n"
             "tau,Omega1,Omega2,Omega3\n0,1,0,2\n0.5,0.5,1,2\n1,0,2,4\n");
  write_file(dir.path() / "traj.csv", "tau,Omega1,Omega2,Omega3\n0,1,0,2\n0.5,0.5,1.001,2\n1,0.01,2,4\n");
  const run_result r = run(dir.path(), {"check", "ref.csv", "traj.csv", "--format", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  const auto near = [](double got, double want) { EXPECT_NEAR(got, want, 1e-14 * std::abs(want) + 1e-300); };
  near(j["scd"], 3);      // max relative error 0.001 / 1 (tau 0.5)
  near(j["mescd"], 2);    // mixed: 0.01 / (1e-12/1e-12 + 0) at tau 1 beats 0.001 / (1 + 1)
  near(j["max_component_errors"][0], 0.01);
  near(j["max_component_errors"][1], 0.001);
  EXPECT_EQ(j["max_component_errors"][2], 0.0);
  // c1^2 = Omega1^2 + Omega2^2: 1.002001 - 1 at tau 0.5, 0.0001 at tau 1.
  near(j["c1_squared_drift"]["max"], 0.002001);
  near(j["c1_squared_drift"]["last"], 0.0001);
  // c2^2 = Omega2^2 + Omega3^2: 0.002001 at tau 0.5, none at tau 1.
  near(j["c2_squared_drift"]["max"], 0.002001);
  EXPECT_EQ(j["c2_squared_drift"]["last"], 0.0);
  // f(0.5, 1, 2) = (-2, 1, -0.5): d = (0, 0.001, 0) splits into 0.001/sqrt(5.25) along and
  // 0.001 sqrt(4.25/5.25) across; f(0, 2, 4) = (-8, 0, 0): d = (0.01, 0, 0) is all along.
  near(j["max_error_along_motion"], 0.01);
  near(j["max_error_across_motion"], 0.001 * std::sqrt(4.25 / 5.25));

  // A larger atol/rtol damps the mixed error: 0.01 / (1 + 0) becomes 0.01 / (10 + 0).
  const run_result r2 =
      run(dir.path(), {"check", "ref.csv", "traj.csv", "--format", "json", "--scd-atol", "1e-11"});
  ASSERT_EQ(r2.exit_code, 0) << r2.err;
  near(json::parse(r2.out)["mescd"], 3);
}

// ---- the attitude: q0..q3 against the reference's q --------------------------------------------

// A small physical scene with an attitude (or without: `q` empty), 61 samples over 600 s.
std::string attitude_scene(const std::string& name, const std::string& q) {
  return fmt::format(R"(name = "{}"
[body]
inertia = [100.0, 150.0, 200.0]
[torque]
M = [0.01, -0.02, 0.005]
[initial]
omega = [0.02, 0.1, 0.05]
{}
[span]
t_end = 600.0
samples = 61
[reference]
precision = "quad"
)",
                     name, q.empty() ? "" : "q = " + q);
}

// The rotation every trajectory row gets: 1e-7 rad about (2, 3, 6) / 7, applied in the body's
// axes (q r, on the right).
const quad small_angle("1e-7");
eulervop::quaternion<quad> small_rotation() {
  const eulervop::vec3<quad> axis = {quad(2) / 7, quad(3) / 7, quad(6) / 7};
  return eulervop::axis_angle(axis, small_angle);
}

// dir/att.toml and its reference dir/ref.csv (t,omega1..3 at columns 0..3, q0..q3 at 4..7),
// and the trajectory dir/traj.csv: t and omega of the reference, and q r for each row's q,
// with the sign of q turned on every third row (-q is the same attitude).
void write_rotated_trajectory(const fs::path& dir) {
  write_file(dir / "att.toml", attitude_scene("attitude-check", "[0.5, 0.5, 0.5, 0.5]"));
  const run_result ref = run(dir, {"reference", "att.toml", "--out", "ref.csv"});
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  std::vector<std::string> header;
  const auto rows = table_rows(read_file(dir / "ref.csv"), &header);
  ASSERT_EQ(header, (std::vector<std::string>{"t", "omega1", "omega2", "omega3", "q0", "q1", "q2", "q3", "tau",
                                              "Omega1", "Omega2", "Omega3"}));
  ASSERT_EQ(rows.size(), 61u);
  const eulervop::quaternion<quad> r = small_rotation();
  std::string traj = "t,omega1,omega2,omega3,q0,q1,q2,q3\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& c = rows[i];
    eulervop::quaternion<quad> q = eulervop::quaternion<quad>{quad(c[4]), quad(c[5]), quad(c[6]), quad(c[7])} * r;
    if (i % 3 == 0) q = {-q.w, -q.x, -q.y, -q.z};
    traj += fmt::format("{},{},{},{},{},{},{},{}\n", c[0], c[1], c[2], c[3], eulervop::to_text(q.w),
                        eulervop::to_text(q.x), eulervop::to_text(q.y), eulervop::to_text(q.z));
  }
  write_file(dir / "traj.csv", traj);
}

// Against the scene (its attitude integrated at the trajectory's times) and against its
// reference file, every row's attitude error is the angle of the rotation put in, 1e-7, to
// 1e-20 relative in the column of --errors-out (written in quad), and the max and the RMS are
// that angle to double rounding. The signs of q do not matter; the rates are untouched.
TEST(CheckAttitude, ARotationByAKnownAngleIsReportedAsThatAngle) {
  temp_dir dir;
  ASSERT_NO_FATAL_FAILURE(write_rotated_trajectory(dir.path()));
  const double angle = static_cast<double>(small_angle);
  for (const std::string against : {"att.toml", "ref.csv"}) {
    const run_result r = run(dir.path(), {"check", against, "traj.csv", "--tol", "1e-30", "--ignore-attitude",
                                          "--format", "json", "--errors-out", "e.csv"});
    ASSERT_EQ(r.exit_code, 0) << against << ": " << r.err << r.out;
    const json j = json::parse(r.out);
    EXPECT_LT(j.at("max_error").get<double>(), 1e-33) << against;
    EXPECT_NEAR(j.at("max_attitude_error").get<double>(), angle, 4e-16 * angle) << against;
    EXPECT_NEAR(j.at("rms_attitude_error").get<double>(), angle, 4e-16 * angle) << against;
    EXPECT_TRUE(j.at("attitude_tol").is_null());
    EXPECT_EQ(j.at("attitude_exceeding_rows").get<int>(), 0);
    EXPECT_TRUE(j.at("first_attitude_exceeding_time").is_null());
    const int line = j.at("max_attitude_error_line").get<int>();
    EXPECT_GE(line, 2);
    EXPECT_LE(line, 62);
    EXPECT_TRUE(j.at("pass").get<bool>());
    const std::vector<std::string> lines = lines_of(read_file(dir.path() / "e.csv"));
    ASSERT_EQ(lines.size(), 62u);
    EXPECT_EQ(lines[0], "line,t,error,bar,attitude_error");
    quad worst = 0;
    for (std::size_t i = 1; i < lines.size(); ++i) {
      const std::vector<std::string> c = cells_of(lines[i]);
      ASSERT_EQ(c.size(), 5u) << lines[i];
      EXPECT_EQ(c[0], std::to_string(i + 1));
      worst = std::max(worst, abs(quad(c[4]) / small_angle - 1));
    }
    EXPECT_LT(worst, quad("1e-20")) << against;
    std::printf("%s: attitude error 1e-7 rad reproduced to %.3g relative (worst row)\n", against.c_str(),
                static_cast<double>(worst));
  }
}

// --attitude-tol: a bar just above the angle passes, just below fails (exit 1) on every row, the
// rates within theirs; the table says which.
TEST(CheckAttitude, AttitudeTolDecidesTheExitCode) {
  temp_dir dir;
  ASSERT_NO_FATAL_FAILURE(write_rotated_trajectory(dir.path()));
  const double angle = static_cast<double>(small_angle);
  const std::string above = fmt::format("{}", angle * (1 + 1e-9)), below = fmt::format("{}", angle * (1 - 1e-9));
  for (const std::string against : {"att.toml", "ref.csv"}) {
    const run_result pass = run(dir.path(), {"check", against, "traj.csv", "--tol", "1e-30", "--attitude-tol", above});
    EXPECT_EQ(pass.exit_code, 0) << against << ": " << pass.err << pass.out;
    EXPECT_NE(pass.out.find("attitude tolerance: attitude error <= " + above + " rad"), std::string::npos) << pass.out;
    EXPECT_NE(pass.out.find("result: PASS"), std::string::npos) << pass.out;
    const run_result fail = run(dir.path(), {"check", against, "traj.csv", "--tol", "1e-30", "--attitude-tol", below});
    EXPECT_EQ(fail.exit_code, 1) << against << ": " << fail.err << fail.out;
    EXPECT_NE(fail.out.find("result: FAIL (attitude: 61 of 61 rows exceed; first at t = "), std::string::npos)
        << fail.out;
    const run_result j =
        run(dir.path(), {"check", against, "traj.csv", "--tol", "1e-30", "--attitude-tol", below, "--format", "json"});
    EXPECT_EQ(j.exit_code, 1) << j.err;
    const json out = json::parse(j.out);
    EXPECT_FALSE(out.at("pass").get<bool>());
    EXPECT_EQ(out.at("exceeding_rows").get<int>(), 0);
    EXPECT_EQ(out.at("attitude_exceeding_rows").get<int>(), 61);
    EXPECT_EQ(out.at("first_attitude_exceeding_line").get<int>(), 2);
    EXPECT_EQ(out.at("first_attitude_exceeding_time").get<double>(), 0.0);
    EXPECT_EQ(out.at("attitude_tol").get<double>(), angle * (1 - 1e-9));
  }
}

// A trajectory without q0..q3 against a reference with an attitude: the rates only, as before,
// and the table says the attitude was not checked.
TEST(CheckAttitude, RatesOnlyTrajectoryAgainstAnAttitudeReference) {
  temp_dir dir;
  ASSERT_NO_FATAL_FAILURE(write_rotated_trajectory(dir.path()));
  std::string rates;
  for (const std::string& l : lines_of(read_file(dir.path() / "traj.csv"))) {
    const std::vector<std::string> c = cells_of(l);
    rates += fmt::format("{},{},{},{}\n", c[0], c[1], c[2], c[3]);
  }
  write_file(dir.path() / "rates.csv", rates);
  for (const std::string against : {"att.toml", "ref.csv"}) {
    const run_result table = run(dir.path(), {"check", against, "rates.csv", "--errors-out", "e.csv"});
    EXPECT_EQ(table.exit_code, 0) << against << ": " << table.err;
    EXPECT_NE(table.out.find("attitude: not checked (the trajectory has no columns q0..q3)"), std::string::npos)
        << table.out;
    EXPECT_EQ(lines_of(read_file(dir.path() / "e.csv"))[0], "line,t,error,bar");
    const run_result r = run(dir.path(), {"check", against, "rates.csv", "--format", "json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json j = json::parse(r.out);
    EXPECT_LT(j.at("max_error").get<double>(), 1e-33);
    for (const char* key : {"max_attitude_error", "max_attitude_error_time", "max_attitude_error_line",
                            "rms_attitude_error", "attitude_exceeding_rows", "first_attitude_exceeding_time"})
      EXPECT_TRUE(j.at(key).is_null()) << key;
  }
}

// Bad input: q0..q3 with no attitude to compare them with, a bad --attitude-tol, q0..q3 in part,
// a row whose q is 0. Each one line, exit 2.
TEST(CheckAttitude, BadAttitudeInput) {
  temp_dir dir;
  ASSERT_NO_FATAL_FAILURE(write_rotated_trajectory(dir.path()));
  write_file(dir.path() / "plain.toml", attitude_scene("no-attitude", ""));
  const run_result plain_ref = run(dir.path(), {"reference", "plain.toml", "--out", "plain.csv"});
  ASSERT_EQ(plain_ref.exit_code, 0) << plain_ref.err;
  expect_one_line_error(run(dir.path(), {"check", "plain.toml", "traj.csv"}),
                        "trajectory traj.csv: line 1: columns q0..q3: scene no-attitude has no attitude ([initial] q)");
  expect_one_line_error(run(dir.path(), {"check", "plain.csv", "traj.csv"}),
                        "columns q0..q3: reference plain.csv has no attitude (no columns q0..q3)");
  expect_one_line_error(run(dir.path(), {"check", "att.toml", "traj.csv", "--attitude-tol", "-1e-9"}),
                        "--attitude-tol -1e-9: must be >= 0");
  expect_one_line_error(run(dir.path(), {"check", "att.toml", "traj.csv", "--attitude-tol", "nan"}),
                        "--attitude-tol nan: ");
  expect_one_line_error(run(dir.path(), {"check", "att.toml", "traj.csv", "--attitude-tol", "x"}),
                        "--attitude-tol x: ");
  // --attitude-tol with nothing to hold to it.
  std::string rates;
  for (const std::string& l : lines_of(read_file(dir.path() / "traj.csv"))) {
    const std::vector<std::string> c = cells_of(l);
    rates += fmt::format("{},{},{},{}\n", c[0], c[1], c[2], c[3]);
  }
  write_file(dir.path() / "rates.csv", rates);
  expect_one_line_error(run(dir.path(), {"check", "att.toml", "rates.csv", "--tol", "1", "--attitude-tol", "1e-6"}),
                        "--attitude-tol 1e-06: trajectory rates.csv has no columns q0..q3");
  // q0..q2 without q3.
  const std::string traj = read_file(dir.path() / "traj.csv");
  write_file(dir.path() / "partial.csv", replace_line(traj, 0, "t,omega1,omega2,omega3,q0,q1,q2,w"));
  expect_one_line_error(run(dir.path(), {"check", "att.toml", "partial.csv"}),
                        "line 1: the header has no column `q3` (column `q0` is there: an attitude needs q0..q3)");
  // A q of 0 on line 5, and a cell that is not a number on line 7, each against both references.
  write_file(dir.path() / "zero.csv", replace_line(traj, 4, cells_of(lines_of(traj)[4])[0] + "," +
                                                               cells_of(lines_of(traj)[4])[1] + "," +
                                                               cells_of(lines_of(traj)[4])[2] + "," +
                                                               cells_of(lines_of(traj)[4])[3] + ",0,0,0.0,0"));
  write_file(dir.path() / "text.csv", replace_cell(traj, 6, 6, "abc"));
  for (const std::string against : {"att.toml", "ref.csv"}) {
    expect_one_line_error(run(dir.path(), {"check", against, "zero.csv", "--errors-out", "e.csv"}),
                          "trajectory zero.csv: line 5: columns q0..q3 are all 0, which is no attitude");
    expect_one_line_error(run(dir.path(), {"check", against, "text.csv"}),
                          "trajectory text.csv: line 7: column q2 = `abc` is not a number");
    EXPECT_FALSE(fs::exists(dir.path() / "e.csv"));
  }
}

// ---- the user's terms: rad/s on the axes as listed, and no silent pass ---------------------------

// A body whose moments are listed out of the principal order (I = 200, 100, 150): its omega3 is
// the second principal axis. An error of 1e-6 rad/s put on omega3 alone is reported on omega3, in
// rad/s, and the normalized Eq. 20 error beside it is 1e-6 / sqrt(A2) with A2 = (I3 - I1) / I2 =
// (200 - 100) / 150 (Eq. 3, exact), 1e-6 sqrt(1.5).
TEST(CheckUserTerms, AnErrorOnOmega3AloneIsReportedOnOmega3InRadPerSecond) {
  temp_dir dir;
  std::string listed = attitude_scene("listed-out-of-order", "");
  listed.replace(listed.find("[100.0, 150.0, 200.0]"), 21, "[200.0, 100.0, 150.0]");
  write_file(dir.path() / "listed.toml", listed);
  const run_result ref = run(dir.path(), {"reference", "listed.toml", "--out", "ref.csv"});
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  std::vector<std::string> header;
  const auto rows = table_rows(read_file(dir.path() / "ref.csv"), &header);
  ASSERT_EQ(header, (std::vector<std::string>{"t", "omega1", "omega2", "omega3", "tau", "Omega1", "Omega2", "Omega3"}));
  const quad put("1e-6");
  std::string traj = "t,omega1,omega2,omega3\n";
  for (const auto& c : rows)
    traj += fmt::format("{},{},{},{}\n", c[0], c[1], c[2], eulervop::to_text(quad(c[3]) + put));
  write_file(dir.path() / "traj.csv", traj);
  const double expected = 1e-6, normalized = 1e-6 * std::sqrt(1.5);
  for (const std::string against : {"listed.toml", "ref.csv"}) {
    const run_result r = run(dir.path(), {"check", against, "traj.csv", "--format", "json", "--errors-out", "e.csv"});
    ASSERT_EQ(r.exit_code, 0) << against << ": " << r.err;
    const json j = json::parse(r.out);
    EXPECT_EQ(j.at("components"), json({"omega1", "omega2", "omega3"}));
    EXPECT_EQ(j.at("time_unit"), "s");
    EXPECT_EQ(j.at("error_unit"), "rad/s");
    const auto& components = j.at("max_component_errors");
    // The trajectory's cells carry every digit of quad: the rest of the error is its rounding.
    EXPECT_NEAR(components[2].get<double>(), expected, 1e-25) << against;
    EXPECT_LT(components[0].get<double>(), 1e-32) << against;
    EXPECT_LT(components[1].get<double>(), 1e-32) << against;
    EXPECT_NEAR(j.at("max_error").get<double>(), expected, 1e-25) << against;
    EXPECT_NEAR(j.at("normalized_max_error").get<double>(), normalized, 1e-15 * normalized) << against;
    EXPECT_TRUE(j.at("pass").is_null());
    const auto e = lines_of(read_file(dir.path() / "e.csv"));
    ASSERT_EQ(e.size(), 62u);
    EXPECT_NEAR(std::stod(cells_of(e[5])[2]), expected, 1e-25);
    // --tol is in rad/s: just above the error passes, just below fails.
    EXPECT_EQ(run(dir.path(), {"check", against, "traj.csv", "--tol", "1.000001e-6"}).exit_code, 0) << against;
    const run_result fail = run(dir.path(), {"check", against, "traj.csv", "--tol", "0.999999e-6"});
    EXPECT_EQ(fail.exit_code, 1) << against;
    EXPECT_NE(fail.out.find("tolerance: error <= 9.99999e-07 rad/s"), std::string::npos) << fail.out;
    EXPECT_NE(fail.out.find("omega3 1.000e-06 rad/s"), std::string::npos) << fail.out;
    if (against == "listed.toml") EXPECT_NE(fail.out.find("computed to t = 600 s"), std::string::npos) << fail.out;
  }
}

// A trajectory with q0..q3 is never passed on its rates alone: --tol without --attitude-tol asks
// for it (exit 2, one line), --attitude-tol needs a bar on the rates, --ignore-attitude judges the
// rates alone and says so, and no bar at all gives no verdict.
TEST(CheckUserTerms, NoSilentPassOnTheAttitude) {
  temp_dir dir;
  ASSERT_NO_FATAL_FAILURE(write_rotated_trajectory(dir.path()));
  for (const std::string against : {"att.toml", "ref.csv"}) {
    expect_one_line_error(run(dir.path(), {"check", against, "traj.csv", "--tol", "1e-9"}),
                          "--attitude-tol: required, since trajectory traj.csv has columns q0..q3 (give "
                          "--attitude-tol RAD, or --ignore-attitude to judge the rates alone)");
    expect_one_line_error(run(dir.path(), {"check", against, "traj.csv", "--rel-tol", "1e-9"}),
                          "--attitude-tol: required");
    expect_one_line_error(run(dir.path(), {"check", against, "traj.csv", "--attitude-tol", "1"}),
                          "--attitude-tol 1: give --tol or --rel-tol too");
    expect_one_line_error(
        run(dir.path(), {"check", against, "traj.csv", "--tol", "1", "--attitude-tol", "1", "--ignore-attitude"}),
        "--ignore-attitude: given with --attitude-tol 1");
    const run_result ignored = run(dir.path(), {"check", against, "traj.csv", "--tol", "1e-9", "--ignore-attitude"});
    EXPECT_EQ(ignored.exit_code, 0) << ignored.err;
    EXPECT_NE(ignored.out.find("result: PASS (every row within tolerance; the attitude not judged "
                               "(--ignore-attitude))"),
              std::string::npos)
        << ignored.out;
    const run_result none = run(dir.path(), {"check", against, "traj.csv", "--format", "json"});
    EXPECT_EQ(none.exit_code, 0) << none.err;
    EXPECT_TRUE(json::parse(none.out).at("pass").is_null());
    const run_result judged =
        run(dir.path(), {"check", against, "traj.csv", "--tol", "1e-9", "--attitude-tol", "1e-6", "--format", "json"});
    EXPECT_EQ(judged.exit_code, 0) << judged.err;
    EXPECT_TRUE(json::parse(judged.out).at("attitude_judged").get<bool>());
  }
}

// A physical reference written before t,omega1..3 came first (tau,Omega1..3,t,omega1..3,q0..q3)
// is read by name, with the same results.
TEST(CheckUserTerms, AReferenceInTheOldColumnOrderReadsTheSame) {
  temp_dir dir;
  ASSERT_NO_FATAL_FAILURE(write_rotated_trajectory(dir.path()));
  std::string old_order;
  for (const std::string& l : lines_of(read_file(dir.path() / "ref.csv"))) {
    if (l.starts_with("#")) {
      old_order += l + "\n";
      continue;
    }
    const std::vector<std::string> c = cells_of(l);  // t,omega1..3,q0..q3,tau,Omega1..3
    old_order += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\n", c[8], c[9], c[10], c[11], c[0], c[1], c[2], c[3],
                             c[4], c[5], c[6], c[7]);
  }
  ASSERT_TRUE(old_order.find("tau,Omega1,Omega2,Omega3,t,omega1,omega2,omega3,q0") != std::string::npos);
  write_file(dir.path() / "old.csv", old_order);
  const std::vector<std::string> flags = {"traj.csv", "--tol", "1e-9", "--attitude-tol", "1e-6", "--format", "json"};
  std::vector<std::string> now = {"check", "ref.csv"}, before = {"check", "old.csv"};
  now.insert(now.end(), flags.begin(), flags.end());
  before.insert(before.end(), flags.begin(), flags.end());
  const run_result a = run(dir.path(), now), b = run(dir.path(), before);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  json ja = json::parse(a.out), jb = json::parse(b.out);
  ja["reference"].erase("path");
  jb["reference"].erase("path");
  EXPECT_EQ(ja, jb);
}

// A spacecraft propagator of seven states in physical units, from another library (Boost.Odeint's
// classic RK4, h = 1/8 s, so that the thruster window [50, 60) s starts and ends on a step), as a
// user would test it: the correct one passes at bars in rad/s and radians, and each planted bug
// fails, by exit 1 with --attitude-tol or by exit 2 asking for it without. The max rate error
// `check` reports, in rad/s, is the one computed here from the reference file's omega columns.
enum class planted { none, product_order, thrust_sign, thrust_axis };

std::string propagate(planted bug) {
  using seven = std::array<double, 7>;
  const double I[3] = {100, 150, 200};
  bool firing = false;
  const auto rhs = [&](const seven& x, seven& dx, double) {
    double M[3] = {0, 0, 0};
    if (firing) M[bug == planted::thrust_axis ? 1 : 0] = bug == planted::thrust_sign ? -0.05 : 0.05;
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      dx[i] = ((I[j] - I[k]) * x[j] * x[k] + M[i]) / I[i];
    }
    // q' = 1/2 q (x) (0, w) (body rates on the right); the bug takes (0, w) (x) q.
    const double w = x[3], a = x[4], b = x[5], c = x[6], p = x[0], q = x[1], r = x[2];
    const double s = bug == planted::product_order ? -1.0 : 1.0;
    dx[3] = 0.5 * (-a * p - b * q - c * r);
    dx[4] = 0.5 * (w * p + s * (b * r - c * q));
    dx[5] = 0.5 * (w * q + s * (c * p - a * r));
    dx[6] = 0.5 * (w * r + s * (a * q - b * p));
  };
  odeint::runge_kutta4<seven> stepper;
  seven x = {0.02, 0.1, 0.05, 1, 0, 0, 0};
  const double h = 0.125;
  std::string csv = "t,omega1,omega2,omega3,q0,q1,q2,q3\n";
  for (int n = 0; n <= 960; ++n) {
    const double t = n * h;
    if (n % 8 == 0)
      csv += fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", t, x[0], x[1], x[2], x[3],
                         x[4], x[5], x[6]);
    firing = t + h / 2 >= 50 && t + h / 2 < 60;  // the window of the step's interior
    if (n < 960) stepper.do_step(rhs, x, t, h);
  }
  return csv;
}

TEST(CheckUserTerms, APropagatorOfSevenStatesAndThreePlantedBugs) {
  temp_dir dir;
  write_file(dir.path() / "sc.toml", R"(name = "thruster-window"
[body]
inertia = [100.0, 150.0, 200.0]
[torque]
M = [0.0, 0.0, 0.0]
[[torque.piece]]
from = 50.0
to = 60.0
M = [0.05, 0.0, 0.0]
[initial]
omega = [0.02, 0.1, 0.05]
q = [1.0, 0.0, 0.0, 0.0]
[span]
t_end = 120.0
samples = 121
)");
  const run_result ref = run(dir.path(), {"reference", "sc.toml", "--out", "ref.csv"});
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  const auto rows = table_rows(read_file(dir.path() / "ref.csv"));
  ASSERT_EQ(rows.size(), 121u);
  write_file(dir.path() / "good.csv", propagate(planted::none));
  // The max rate error computed here: the two-norm over omega1..3 against the file's columns.
  double independent = 0;
  const auto good = lines_of(read_file(dir.path() / "good.csv"));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::vector<std::string> c = cells_of(good[i + 1]);
    double sum = 0;
    for (int k = 1; k <= 3; ++k) sum += std::pow(std::stod(c[k]) - std::stod(rows[i][k]), 2);
    independent = std::max(independent, std::sqrt(sum));
  }
  ASSERT_GT(independent, 1e-13);  // RK4's own error, above the 17-digit text's
  ASSERT_LT(independent, 1e-8);
  const std::vector<std::string> bars = {"--tol", "1e-8", "--attitude-tol", "1e-7"};
  for (const std::string against : {"sc.toml", "ref.csv"}) {
    std::vector<std::string> args = {"check", against, "good.csv", "--format", "json"};
    args.insert(args.end(), bars.begin(), bars.end());
    const run_result r = run(dir.path(), args);
    ASSERT_EQ(r.exit_code, 0) << against << ": " << r.err << r.out;
    const json j = json::parse(r.out);
    EXPECT_TRUE(j.at("pass").get<bool>());
    EXPECT_NEAR(j.at("max_error").get<double>(), independent, 0.01 * independent) << against;
    std::printf("%s: max rate error %.6g rad/s reported, %.6g computed here\n", against.c_str(),
                j.at("max_error").get<double>(), independent);
  }
  for (const auto& [bug, name] : {std::pair{planted::product_order, "product"}, std::pair{planted::thrust_sign, "sign"},
                                  std::pair{planted::thrust_axis, "axis"}}) {
    const std::string file = std::string(name) + ".csv";
    write_file(dir.path() / file, propagate(bug));
    for (const std::string against : {"sc.toml", "ref.csv"}) {
      std::vector<std::string> args = {"check", against, file};
      args.insert(args.end(), bars.begin(), bars.end());
      EXPECT_EQ(run(dir.path(), args).exit_code, 1) << name << " against " << against;
      const run_result rates_only = run(dir.path(), {"check", against, file, "--tol", "1e-8"});
      EXPECT_EQ(rates_only.exit_code, 2) << name << " against " << against;
      EXPECT_NE(rates_only.err.find("--attitude-tol: required"), std::string::npos) << rates_only.err;
    }
  }
}

}  // namespace

// The SciML rigid body's reference at `samples` times, its rows written again as a trajectory
// (traj.csv: t, y1..3 as the reference printed them).
void write_reference_as_trajectory(const fs::path& dir, const std::string& samples) {
  const run_result ref = run(dir, {"reference", "sciml-rigid-body", "--samples", samples, "--out", "ref.csv"});
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  std::string traj = "t,y1,y2,y3\n";
  for (const auto& row : table_rows(read_file(dir / "ref.csv")))
    traj += fmt::format("{},{},{},{}\n", row[0], row[1], row[2], row[3]);
  write_file(dir / "traj.csv", traj);
}

// A shipped scene is taken by its name wherever a scene path goes; a name that is no scene says
// so in one line, with the shipped ones.
TEST(Check, AShippedSceneByItsName) {
  temp_dir dir;
  // The reference's own rows, as a trajectory: each cell is the reference's decimal, so 0 error.
  write_reference_as_trajectory(dir.path(), "11");
  const run_result by_name = run(dir.path(), {"check", "sciml-rigid-body", "traj.csv", "--tol", "1e-30"});
  EXPECT_EQ(by_name.exit_code, 0) << by_name.out << by_name.err;
  const run_result wrong = run(dir.path(), {"check", "sciml-rigid-bod", "traj.csv", "--tol", "1e-30"});
  expect_one_line_error(wrong, "scene sciml-rigid-bod: cannot read: no such file, nor a shipped scene (");
  EXPECT_NE(wrong.err.find("sciml-rigid-body"), std::string::npos) << wrong.err;
}

// Thousands of rows on each segment take the Chebyshev series (segment_sampler.hpp) from the fifth
// row of a segment on: the reference there must be the one the reference command prints at the
// same times to the last digits, so that its own rows judge to the printing's rounding.
TEST(Check, DenseRowsJudgeTheReferenceToItsDigits) {
  temp_dir dir;
  write_reference_as_trajectory(dir.path(), "20001");
  // |y| <= 2 here and each printed cell is within half a unit of its 36th digit of the quad value:
  // 3e-36 |y| per cell, so 1e-35 bounds a row's 2-norm; any series error above that would show.
  const run_result r = run(dir.path(), {"check", "sciml-rigid-body", "traj.csv", "--tol", "1e-35", "--format", "json"});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(json::parse(r.out).at("rows").get<int>(), 20001);
}
