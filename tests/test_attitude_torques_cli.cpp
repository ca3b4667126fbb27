// Torques of the attitude through the program (docs/attitude.md, "Torques of the attitude"):
// bad input in the scene (one line, exit 2, no file left), the commands that accept a coupled
// scene (reference, check, batch, report, sweep, map, --certify) and what refuses it.
#include "cli_test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace {

using namespace eulervop::cli_test;

// A physical scene with the attitude `q_line` (empty: none) and the [torque] block `torque`.
std::string body_scene(const std::string& torque, const std::string& q_line = "q = [0.7, 0.1, 0.1, 0.7]") {
  return "name = \"coupled\"\n[body]\ninertia = [100.0, 150.0, 220.0]\n" + torque +
         "\n[initial]\nomega = [0.0005, -0.0003, 0.0013]\n" + q_line + "\n[span]\nt_end = 600.0\nsamples = 7\n";
}

const std::string gravity = "[torque.gravity_gradient]\nmean_motion = 0.0011";

struct bad_case {
  std::string label, scene, expected;
};

class BadCoupledScene : public ::testing::TestWithParam<bad_case> {};

TEST_P(BadCoupledScene, OneLineExitTwoNoFileLeft) {
  temp_dir dir;
  write_file(dir.path() / "s.toml", GetParam().scene);
  expect_one_line_error(run(dir.path(), {"reference", "s.toml", "--out", "ref.csv"}), GetParam().expected);
  EXPECT_EQ(entries_except(dir.path(), "s.toml"), std::vector<std::string>{});
}

const std::string pd = R"([torque]
M = ["-2*q1 - 40*omega1", "-2*q2 - 40*omega2", "-2*q3 - 40*omega3"])";

INSTANTIATE_TEST_SUITE_P(
    Cases, BadCoupledScene,
    ::testing::Values(
        bad_case{"q_without_attitude", body_scene(pd, ""),
                 "[torque] M1 = \"-2*q1 - 40*omega1\": `q1` is the attitude, which this scene does not give"},
        bad_case{"q_in_a_piece_without_attitude",
                 body_scene("[[torque.piece]]\nfrom = 0.0\nto = 10.0\nM = [0.0, 0.0, \"q3\"]", ""),
                 "[[torque.piece]] 1 M3 = \"q3\": `q3` is the attitude"},
        bad_case{"q_in_a_normalized_scene",
                 "name = \"n\"\n[torque]\nG = [\"q1\", 0, 0]\n[initial]\nOmega = [1, 0, 1]\n[span]\ntau_end = 1\n"
                 "samples = 3\n",
                 "`q1` is a variable of a physical scene ([body])"},
        bad_case{"mean_motion_negative", body_scene("[torque.gravity_gradient]\nmean_motion = -0.0011"),
                 "[torque.gravity_gradient] mean_motion = -0.0011: must be positive"},
        bad_case{"mean_motion_zero", body_scene("[torque.gravity_gradient]\nmean_motion = 0"),
                 "[torque.gravity_gradient] mean_motion = 0: must be positive"},
        bad_case{"mean_motion_nan", body_scene("[torque.gravity_gradient]\nmean_motion = nan"),
                 "[torque.gravity_gradient] mean_motion = nan: must be finite"},
        bad_case{"mean_motion_inf", body_scene("[torque.gravity_gradient]\nmean_motion = inf"),
                 "[torque.gravity_gradient] mean_motion = inf: must be finite"},
        bad_case{"mean_motion_text", body_scene("[torque.gravity_gradient]\nmean_motion = \"fast\""),
                 "[torque.gravity_gradient] mean_motion = \"fast\": unknown identifier `fast`"},
        bad_case{"mean_motion_missing", body_scene("[torque.gravity_gradient]"),
                 "[torque.gravity_gradient]: required field `mean_motion` is missing"},
        bad_case{"gravity_unknown_key", body_scene("[torque.gravity_gradient]\nn = 0.0011"),
                 "unknown key `n` in [torque.gravity_gradient] (expected one of: mean_motion)"},
        bad_case{"gravity_without_attitude", body_scene(gravity, ""),
                 "[torque.gravity_gradient]: the gravity gradient depends on the attitude: give [initial] q"},
        bad_case{"gravity_without_body",
                 "name = \"n\"\n[torque.gravity_gradient]\nmean_motion = 0.0011\n[initial]\nOmega = [1, 0, 1]\n"
                 "[span]\ntau_end = 1\nsamples = 3\n",
                 "[torque.gravity_gradient]: the gravity gradient acts on a body: give [body] inertia and [initial] q"},
        bad_case{"gravity_in_the_coefficient_form",
                 "name = \"c\"\n[equations]\na = [-1, 1, -1]\n[torque.gravity_gradient]\nmean_motion = 0.0011\n"
                 "[initial]\ny = [1, 0, 1]\n[span]\nt_end = 1\nsamples = 3\n",
                 "[torque.gravity_gradient]: the gravity gradient acts on a body"}),
    [](const auto& info) { return info.param.label; });

// `report --reference` refuses a file without q for a coupled scene, in one line, leaving nothing.
TEST(CoupledScene, CommandsThatCannotRunItSayWhy) {
  temp_dir dir;
  write_file(dir.path() / "s.toml", body_scene(gravity));
  // A rates-only reference file of another scene under the same name: no q for the runs.
  write_file(dir.path() / "r.toml", "name = \"coupled\"\n[body]\ninertia = [100.0, 150.0, 220.0]\n[initial]\n"
                                    "omega = [0.0005, -0.0003, 0.0013]\n[span]\nt_end = 600.0\nsamples = 7\n");
  ASSERT_EQ(run(dir.path(), {"reference", "r.toml", "--out", "rates.csv"}).exit_code, 0);
  expect_one_line_error(run(dir.path(), {"report", "s.toml", "--reference", "rates.csv", "--out-dir", "rp"}),
                        "the file has no attitude (q0..q3), and the torque of scene `coupled` reads it");
  std::vector<std::string> left = entries_except(dir.path(), "s.toml");
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"r.toml", "rates.csv"}));
}

// --certify proves the coupled problem, the gravity gradient included: the rows of the plain run,
// and radii of the rates and of q (their soundness: test_general_certify_cli.cpp's oracles).
TEST(CoupledScene, CertifyProvesTheCoupledProblem) {
  temp_dir dir;
  write_file(dir.path() / "s.toml", body_scene(gravity));
  const run_result r = run(dir.path(), {"reference", "s.toml", "--certify", "--out", "c.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string c = read_file(dir.path() / "c.csv");
  EXPECT_NE(c.find("# certified_max_error_q: "), std::string::npos);
  EXPECT_NE(c.find(",radius_q\n"), std::string::npos);
}

// A formula of q that is not finite where it is evaluated: exit 3, naming it and the time, no file.
TEST(CoupledScene, ANonFiniteFormulaOfQIsANumericalFailureAtItsTime) {
  temp_dir dir;
  write_file(dir.path() / "s.toml", body_scene("[torque]\nM = [\"log(q0 - 0.8)\", 0.0, 0.0]"));
  const run_result r = run(dir.path(), {"reference", "s.toml", "--out", "ref.csv"});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("numerical failure at t=0 s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("M1 = log(q0 - 0.8) is nan at t = 0"), std::string::npos) << r.err;
  EXPECT_EQ(entries_except(dir.path(), "s.toml"), std::vector<std::string>{});
}

// The reference says it is coupled and how far |q| drifted; check passes the reference's own rows
// and fails a planted error on q; batch runs the scene.
TEST(CoupledScene, ReferenceCheckAndBatch) {
  temp_dir dir;
  write_file(dir.path() / "s.toml", body_scene(gravity));
  const run_result r = run(dir.path(), {"reference", "s.toml", "--out", "ref.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string ref = read_file(dir.path() / "ref.csv");
  EXPECT_NE(ref.find("# coupled: the torque reads the attitude"), std::string::npos);
  EXPECT_NE(ref.find("# q_norm_drift: "), std::string::npos);
  // The trajectory: t, omega, q of the reference's rows, to 20 digits.
  std::string trajectory = "t,omega1,omega2,omega3,q0,q1,q2,q3\n", planted = trajectory;
  int row = 0;
  for (const std::string& line : lines_of(ref)) {
    if (line.empty() || line[0] == '#' || line[0] == 't') continue;
    std::vector<std::string> c = cells_of(line);
    std::string out;
    for (int k = 0; k < 8; ++k) {  // 20 digits of the mantissa, then the exponent
      const std::size_t e = c[k].find('e');
      ASSERT_NE(e, std::string::npos) << c[k];
      out += (k ? "," : "");
      out.append(c[k], 0, 22).append(c[k], e);
    }
    trajectory += out + "\n";
    if (++row == 4) c[6] = std::to_string(std::stod(c[6]) + 1e-6);  // q2 off by 1e-6 on one row
    std::string bad;
    for (int k = 0; k < 8; ++k) bad += (k ? "," : "") + c[k];
    planted += bad + "\n";
  }
  write_file(dir.path() / "mine.csv", trajectory);
  write_file(dir.path() / "planted.csv", planted);
  const std::vector<std::string> bars = {"--tol", "1e-15", "--attitude-tol", "1e-15"};
  std::vector<std::string> args = {"check", "s.toml", "mine.csv"};
  args.insert(args.end(), bars.begin(), bars.end());
  const run_result pass = run(dir.path(), args);
  EXPECT_EQ(pass.exit_code, 0) << pass.out << pass.err;
  args = {"check", "ref.csv", "planted.csv"};
  args.insert(args.end(), bars.begin(), bars.end());
  const run_result fail = run(dir.path(), args);
  EXPECT_EQ(fail.exit_code, 1) << fail.out << fail.err;

  const run_result b = run(dir.path(), {"batch", "s.toml", "--out-dir", "b"});
  EXPECT_EQ(b.exit_code, 0) << b.out << b.err;
}

// report's runs feed each stage's q to the torque: on the PD slew, rk4 at 0.5 s is within 1e-5 of
// the reference in rates (normalized) and attitude (measured 3.6e-7 and 5.5e-7 rad). Were the
// torque held at q(0), its constant 1 N m would spin the body up instead of slewing it, an error
// of order one.
TEST(CoupledScene, ReportRunsSeeTheStagesAttitude) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"report", source_dir + "/data/scenes/attitude/pd-slew.toml", "--methods", "rk4",
                                        "--formulations", "euler,vop", "--no-plot", "--format", "json", "--out-dir",
                                        "rp"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["runs"].size(), 2u) << r.out;
  for (const auto& run : j["runs"]) {
    EXPECT_LT(run["max_error"].get<double>(), 1e-5) << run.dump();
    EXPECT_LT(run["max_attitude_error"].get<double>(), 1e-5) << run.dump();
  }
}

}  // namespace
