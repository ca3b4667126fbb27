// `eulervop report`: the output files and their layout, the paper's claim on a short span,
// divergence without NaN, bad flags, the --reference round trip and the adaptive runs of --tols.
// Also the step rule in process (resolve_step).
#include "cli_test_support.hpp"

#include "cli/flags.hpp"
#include "compute/step_rule.hpp"

#include <eulervop/special/elliptic.hpp>
#include <eulervop/scene/scene.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace eulervop::cli_test;
using nlohmann::json;

const json& run_of(const json& summary, const std::string& formulation, const std::string& method) {
  for (const json& r : summary.at("runs"))
    if (r.at("formulation") == formulation && r.at("method") == method) return r;
  throw std::runtime_error("no run " + formulation + "_" + method);
}

// The paper's step h = K(0.5)/200 (K(0.5) = 1.6857503548125960429, A&S table 17.1).
const double paper_h = 1.6857503548125960429 / 200;

// ---- the step rule (in process) -----------------------------------------------------------------

TEST(ReportStep, PaperSceneIsKHalfOver200) {
  const auto s = eulervop::scene::load_default_scene();
  ASSERT_TRUE(s.step && s.step->K_divisor);
  const auto st = eulervop::app::resolve_step(s, *s.step, "[run] step");
  EXPECT_NEAR(st.h, paper_h, 4e-16 * paper_h);
  EXPECT_NEAR(st.h, 0.0084288, 1e-7);
  EXPECT_FALSE(st.reciprocal);
  EXPECT_EQ(st.n_steps, static_cast<std::size_t>(std::floor(136 / st.h)));  // 16135
  EXPECT_EQ(st.n_steps, 16135u);
}

TEST(ReportStep, MinorAxisUsesTheReciprocalModulus) {
  // Omega(0) = (1, 0, 0.5): c1 = 1, c2 = 0.5, k0 = 2 -> h = K(1/2) / (N c1).
  const auto s = eulervop::scene::parse_scene(
      "name = \"minor\"\n[initial]\nOmega = [1.0, 0.0, 0.5]\n[span]\ntau_end = 10.0\nsamples = 3\n", "minor.toml");
  const auto st = eulervop::app::resolve_step(s, eulervop::app::flag_step("--step", "K/100"), "--step K/100");
  EXPECT_TRUE(st.reciprocal);
  EXPECT_NEAR(st.h, 1.6857503548125960429 / 100, 1e-16);
  EXPECT_NE(st.rule.find("reciprocal"), std::string::npos) << st.rule;
}

TEST(ReportStep, PlainNumberIsInTheScenesTimeVariable) {
  const auto s = eulervop::scene::load_scene_file(source_dir + "/data/scenes/spacecraft-physical.toml");
  const auto st = eulervop::app::resolve_step(s, eulervop::app::flag_step("--step", "2"), "--step 2");
  // Inertias 100, 150, 200: A = (50/100, 100/150, 50/200), dtau/dt = sqrt(A1 A2 A3) = sqrt(1/12).
  EXPECT_NEAR(st.h, 2 * std::sqrt(1.0 / 12), 1e-15);
  EXPECT_EQ(st.n_steps, 1800u);  // t_end = 3600 s
}

// ---- a short paper-scene report -----------------------------------------------------------------

TEST(Report, ShortPaperReportWritesTheFiles) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"report", "--tau-end", "5", "--samples", "50", "--no-plot", "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;

  // 593 steps of h to tau 5; sample every 593/50 = 11 steps (0, 11, ..., 583) plus the last.
  const std::size_t n_steps = static_cast<std::size_t>(std::floor(5 / paper_h));
  ASSERT_EQ(n_steps, 593u);
  const std::size_t every = n_steps / 50;
  const std::size_t expected_rows = n_steps / every + 1 + (n_steps % every != 0);

  const auto lines = lines_of(read_file(dir.path() / "out" / "errors.csv"));
  ASSERT_EQ(lines.size(), expected_rows + 1);
  EXPECT_EQ(lines[0], "tau,euler_rk4,euler_rkf45,vop_rk4,vop_rkf45");
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto cells = cells_of(lines[i]);
    ASSERT_EQ(cells.size(), 5u) << lines[i];
    for (const auto& c : cells) EXPECT_FALSE(c.empty()) << lines[i];
  }
  EXPECT_EQ(std::stod(cells_of(lines[1])[0]), 0.0);
  EXPECT_NEAR(std::stod(cells_of(lines.back())[0]), n_steps * paper_h, 1e-13);
  EXPECT_NEAR(std::stod(cells_of(lines[2])[0]), every * paper_h, 1e-15);

  const json summary = json::parse(read_file(dir.path() / "out" / "summary.json"));
  EXPECT_EQ(summary.at("scene"), "paper-fig1");
  ASSERT_TRUE(summary.at("reference").contains("precision"));
  EXPECT_EQ(summary["reference"]["precision"], "quad");
  ASSERT_TRUE(summary["reference"].contains("estimated_max_error"));
  EXPECT_TRUE(summary["reference"]["estimated_max_error"].is_null());  // no --verify
  ASSERT_EQ(summary.at("runs").size(), 4u);
  for (const json& run : summary["runs"]) {
    for (const char* key : {"formulation", "method", "step", "steps", "rhs_evals", "seconds", "max_error",
                            "final_tau", "final_error", "diverged", "diverged_at"})
      EXPECT_TRUE(run.contains(key)) << key << " in " << run.dump();
    EXPECT_EQ(run["steps"], n_steps);
    EXPECT_DOUBLE_EQ(run["step"].get<double>(), paper_h);
    EXPECT_EQ(run["diverged"], false);
    EXPECT_TRUE(run["diverged_at"].is_null());
    EXPECT_GT(run["rhs_evals"].get<double>(), 4.0 * n_steps - 1);
    EXPECT_NEAR(run["final_tau"].get<double>(), n_steps * paper_h, 1e-13);
    EXPECT_GE(run["max_error"].get<double>(), run["final_error"].get<double>());
  }
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "fig1.png"));  // --no-plot

  // The table: a header and one row per run, aligned (every row as wide as the header's columns).
  const auto out = lines_of(r.out);
  const auto header = std::find_if(out.begin(), out.end(), [](const std::string& l) { return l.starts_with("formulation"); });
  ASSERT_NE(header, out.end()) << r.out;
  ASSERT_EQ(out.end() - header, 5) << r.out;
  for (const char* col : {"method", "h", "steps", "rhs evals", "seconds", "max error", "final tau", "final error"})
    EXPECT_NE(header->find(col), std::string::npos) << col;
  EXPECT_TRUE(header[1].starts_with("euler        rk4 ")) << header[1];
  EXPECT_EQ(header[1].size(), header->size());
}

// An axisymmetric body: the paper's VOP does not apply, report says so in one line and runs
// Euler only (on Eq. 1, in t and omega); asking for vop is bad input.
TEST(Report, AxisymmetricBodyRunsEulerOnly) {
  temp_dir dir;
  const std::string scene = source_dir + "/data/scenes/axisymmetric.toml";
  const run_result r = run(dir.path(), {"report", scene, "--t-end", "60", "--no-plot", "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto out = lines_of(r.out);
  EXPECT_EQ(std::count_if(out.begin(), out.end(),
                          [](const std::string& l) { return l.starts_with("note: the paper's VOP does not apply"); }),
            1)
      << r.out;
  const json summary = json::parse(read_file(dir.path() / "out" / "summary.json"));
  ASSERT_EQ(summary.at("runs").size(), 2u);  // euler rk4, euler rkf45 (the scene's methods)
  for (const json& run : summary["runs"]) {
    EXPECT_EQ(run["formulation"], "euler");
    EXPECT_EQ(run["steps"], 60);  // h = 1 s, the scene's step
    // rk4 at h = 1 s on rates of 0.05 rad/s: the error is small but not at rounding.
    EXPECT_GT(run["max_error"].get<double>(), 0.0);
    EXPECT_LT(run["max_error"].get<double>(), 1e-6) << run.dump();
  }
  // The same runs against a reference file of the body (t, omega columns) give the same errors.
  const run_result ref = run(dir.path(), {"reference", scene, "--t-end", "60", "--samples", "61", "--out", "ref.csv"});
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  const run_result from_file =
      run(dir.path(), {"report", scene, "--t-end", "60", "--reference", "ref.csv", "--no-plot", "--out-dir", "out3"});
  ASSERT_EQ(from_file.exit_code, 0) << from_file.err;
  const json summary3 = json::parse(read_file(dir.path() / "out3" / "summary.json"));
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_EQ(summary3["runs"][i]["final_error"], summary["runs"][i]["final_error"]) << summary3.dump();

  const run_result vop = run(dir.path(), {"report", scene, "--t-end", "60", "--formulations", "euler,vop", "--no-plot",
                                          "--out-dir", "out2"});
  EXPECT_EQ(vop.exit_code, 2);
  // Named by the flag, the formulation, the scene and why (not the probe's failure to start).
  EXPECT_NE(vop.err.find("--formulations euler,vop: formulation vop cannot run on scene `axisymmetric`: the paper's "
                         "VOP does not apply to this body"),
            std::string::npos)
      << vop.err;
  EXPECT_EQ(std::count(vop.err.begin(), vop.err.end(), '\n'), 1) << vop.err;
  EXPECT_FALSE(fs::exists(dir.path() / "out2"));
}

TEST(Report, JsonFormatPrintsTheSummary) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"report", "--tau-end", "1", "--samples", "4", "--no-plot", "--format", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Default output directory: ./eulervop-report/, created.
  EXPECT_EQ(json::parse(r.out), json::parse(read_file(dir.path() / "eulervop-report" / "summary.json")));
  EXPECT_TRUE(fs::exists(dir.path() / "eulervop-report" / "errors.csv"));
}

// The paper's claim on a short span. Measured (quad reference, h = K(0.5)/200, rk4, tau = 20):
// euler 1.30e-3, vop 3.34e-7 at tau = 20 (both also the maxima): VOP wins by about 3.6 orders.
TEST(Report, VopBeatsEulerWithRk4AtTau20) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"report", "--tau-end", "20", "--methods", "rk4", "--samples", "100",
                                        "--no-plot", "--out-dir", "out", "--format", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json summary = json::parse(r.out);
  const json& euler = run_of(summary, "euler", "rk4");
  const json& vop = run_of(summary, "vop", "rk4");
  const double e = euler["max_error"], v = vop["max_error"];
  EXPECT_LT(v, e);
  EXPECT_LT(v * 1e3, e) << "vop " << v << ", euler " << e;  // at least three orders of magnitude
  EXPECT_LT(vop["final_error"].get<double>() * 1e3, euler["final_error"].get<double>());
  EXPECT_GT(e, 1e-4);  // the Euler run is really that far off (1.3e-3): not a vacuous comparison
}

// A step far too long: with h = 0.5 the Euler rk4 run explodes at tau = 7.5, and the VOP run
// reaches c1 = 0 at tau = 51.5 (measured). Both stop there; nothing after is a number.
TEST(Report, DivergedRunHasNoNaN) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"report", "--tau-end", "60", "--step", "0.5", "--methods", "rk4", "--samples",
                                        "1000", "--no-plot", "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = read_file(dir.path() / "out" / "errors.csv");
  const std::string summary_text = read_file(dir.path() / "out" / "summary.json");
  expect_no_nan(r.out, "stdout");
  expect_no_nan(csv, "errors.csv");
  expect_no_nan(summary_text, "summary.json");

  const json summary = json::parse(summary_text);
  const json& euler = run_of(summary, "euler", "rk4");
  EXPECT_EQ(euler["diverged"], true);
  ASSERT_TRUE(euler["diverged_at"].is_number());
  const double at = euler["diverged_at"];
  EXPECT_GT(at, 0);
  EXPECT_LT(at, 60);
  EXPECT_LE(euler["final_tau"].get<double>(), at);
  EXPECT_LT(euler["steps"].get<int>(), 120);
  EXPECT_NE(r.out.find("diverged at tau="), std::string::npos) << r.out;

  // errors.csv: 121 rows (every step); the euler cells are empty from the divergence on.
  const auto lines = lines_of(csv);
  ASSERT_EQ(lines.size(), 122u);
  EXPECT_EQ(lines[0], "tau,euler_rk4,vop_rk4");
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto cells = cells_of(lines[i]);
    ASSERT_EQ(cells.size(), 3u) << lines[i];
    const double tau = std::stod(cells[0]);
    EXPECT_EQ(cells[1].empty(), tau >= at) << lines[i];
  }
}

// ---- bad input -----------------------------------------------------------------------------------

struct bad_report {
  const char* label;
  std::vector<std::string> args;  // after "report"
  std::string expected;           // the flag and value the message must name
};

void PrintTo(const bad_report& c, std::ostream* os) { *os << c.label; }

std::vector<bad_report> bad_reports() {
  return {
      {"method rk5", {"--methods", "rk5"}, "--methods rk5"},
      {"formulation foo", {"--formulations", "foo"}, "--formulations foo"},
      {"formulation twice", {"--formulations", "euler,vop,euler"}, "--formulations euler,vop,euler"},
      {"empty method item", {"--methods", "rk4,"}, "--methods rk4,"},
      {"step K over 0", {"--step", "K/0"}, "--step K/0"},
      {"step negative", {"--step", "-1"}, "--step -1"},
      {"step text", {"--step", "fast"}, "--step fast"},
      {"step longer than span", {"--step", "100", "--tau-end", "1"}, "--step 100"},
      {"out dir in proc", {"--out-dir", "/proc/x"}, "--out-dir /proc/x"},
      {"out dir is a file", {"--out-dir", "scene.toml"}, "--out-dir scene.toml"},
      {"format xml", {"--format", "xml"}, "--format xml"},
      {"samples 1", {"--samples", "1"}, "--samples 1"},
      {"reference missing", {"--reference", "missing.csv"}, "--reference missing.csv"},
      {"reference and precision", {"--reference", "scene.toml", "--precision", "double"}, "--precision"},
      {"tols with a step", {"--tols", "1e-6", "--step", "K/100"}, "--tols 1e-6 and --step K/100"},
      {"tols with a reference file", {"--tols", "1e-6", "--reference", "scene.toml"}, "--reference: not used with --tols"},
      {"tols with verify", {"--tols", "1e-6", "--verify"}, "--verify: not used with --tols"},
      {"tols negative", {"--tols", "-1e-6"}, "--tols -1e-6"},
      {"tols nan", {"--tols", "nan"}, "--tols nan"},
      {"tols unsorted", {"--tols", "1e-6,1e-8,1e-7"}, "not sorted at 1e-7"},
      {"tols with rk4", {"--tols", "1e-6", "--methods", "rk4,dp45"}, "rk4 has no embedded error estimate"},
      {"tols with rk8", {"--tols", "1e-6", "--methods", "rk8"}, "rk8 has no embedded error estimate"},
      {"dop853 at a step", {"--methods", "dop853"}, "dop853 is run under error control"},
      {"max step without tols", {"--max-step", "K/4"}, "--max-step K/4: only for the adaptive runs of --tols"},
      {"max step negative", {"--tols", "1e-6", "--max-step", "-2"}, "--max-step -2"},
  };
}

class BadReport : public ::testing::TestWithParam<bad_report> {};

TEST_P(BadReport, ExitsTwoWithOneLineAndNoFiles) {
  const bad_report& c = GetParam();
  temp_dir dir;
  write_file(dir.path() / "scene.toml", "not a directory\n");
  std::vector<std::string> args = {"report", "--no-plot"};
  args.insert(args.end(), c.args.begin(), c.args.end());
  const run_result r = run(dir.path(), args);
  expect_one_line_error(r, c.expected);
  const std::vector<std::string> files = entries_except(dir.path(), "scene.toml");
  EXPECT_TRUE(files.empty()) << files.front();  // not even the default ./eulervop-report/
}

INSTANTIATE_TEST_SUITE_P(Table, BadReport, ::testing::ValuesIn(bad_reports()),
                         [](const ::testing::TestParamInfo<bad_report>& info) { return test_name_of(info.param.label); });

TEST(Report, SceneFormulationListedTwiceIsBadInput) {
  temp_dir dir;
  write_file(dir.path() / "s.toml",
             "name = \"t\"\n[torque]\nG = [1.0, 1.0, 1.0]\n[initial]\nOmega = [0.5, 0.0, 1.0]\n[span]\ntau_end = 1.0\n"
             "samples = 3\n[run]\nformulations = [\"euler\", \"vop-theta\", \"euler\"]\n");
  const run_result r = run(dir.path(), {"report", "s.toml", "--no-plot"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("formulations"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("euler"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "eulervop-report"));
}

// ---- --tols: adaptive runs ------------------------------------------------------------------------

// Each run under error control is measured at its own accepted steps: errors.csv has a row per
// sample with the run's formulation, method and tolerance; the summary carries tol, accepted,
// rejected and rhs_evals; a tighter tolerance gives a smaller error.
TEST(Report, ToleranceLadderRunsAdaptively) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"report", "--tau-end", "10", "--tols", "1e-6,1e-9", "--methods", "dp45,dop853",
                                        "--formulations", "euler,vop-theta", "--samples", "50", "--no-plot",
                                        "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const auto lines = lines_of(read_file(dir.path() / "out" / "errors.csv"));
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0], "formulation,method,tol,tau,error");
  std::map<std::string, std::size_t> rows;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto c = cells_of(lines[i]);
    ASSERT_EQ(c.size(), 5u) << lines[i];
    ++rows[c[0] + " " + c[1] + " " + c[2]];
    EXPECT_GE(std::stod(c[3]), 0);
    EXPECT_LE(std::stod(c[3]), 10);
    EXPECT_GE(std::stod(c[4]), 0);
  }
  EXPECT_EQ(rows.size(), 2u * 2u * 2u);
  for (const auto& [run_name, n] : rows) {
    EXPECT_GE(n, 50u) << run_name;   // about --samples, between it and twice it, and the last step
    EXPECT_LE(n, 101u) << run_name;
  }
  const json summary = json::parse(read_file(dir.path() / "out" / "summary.json"));
  ASSERT_EQ(summary.at("runs").size(), 8u);
  for (const json& run : summary.at("runs")) {
    EXPECT_TRUE(run.at("step").is_null());
    EXPECT_GT(run.at("tol").get<double>(), 0);
    EXPECT_EQ(run.at("accepted"), run.at("steps"));
    EXPECT_GE(run.at("rejected").get<int>(), 0);
    EXPECT_GT(run.at("rhs_evals").get<int>(), 0);
    EXPECT_FALSE(run.at("diverged").get<bool>());
    EXPECT_EQ(run.at("final_tau"), 10.0);  // the last step lands on the span end
  }
  for (const char* f : {"euler", "vop-theta"})
    for (const char* m : {"dp45", "dop853"}) {
      double loose = 0, tight = 0;
      for (const json& run : summary.at("runs"))
        if (run.at("formulation") == f && run.at("method") == m)
          (run.at("tol") == 1e-6 ? loose : tight) = run.at("max_error").get<double>();
      EXPECT_LT(tight, loose) << f << " " << m;
    }
  EXPECT_TRUE(summary.at("max_step").at("rule").get<std::string>().starts_with("K/2")) << summary.at("max_step");
  EXPECT_NE(r.out.find("under error control"), std::string::npos) << r.out;
}

// The fixed-step summary carries the same keys, empty for what only adaptive runs have.
TEST(Report, FixedStepSummaryHasTheAdaptiveKeysEmpty) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"report", "--tau-end", "2", "--format", "json", "--no-plot", "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json summary = json::parse(r.out);
  for (const json& run : summary.at("runs")) {
    EXPECT_TRUE(run.at("tol").is_null());
    EXPECT_TRUE(run.at("accepted").is_null());
    EXPECT_TRUE(run.at("rejected").is_null());
    EXPECT_GT(run.at("rhs_evals").get<int>(), 0);
  }
}

// ---- --reference FILE ---------------------------------------------------------------------------

// A reference written by `eulervop reference` at tau = 0, 0.25, ..., 2 (step points of h = 0.25)
// gives the same errors as the reference computed in process, to 1e-12 relative in every cell.
TEST(Report, ReferenceFileRoundTrip) {
  temp_dir dir;
  const run_result ref = run(dir.path(), {"reference", "--tau-end", "2", "--samples", "9", "--out", "ref.csv"});
  ASSERT_EQ(ref.exit_code, 0) << ref.err;
  const run_result from_file = run(dir.path(), {"report", "--reference", "ref.csv", "--tau-end", "2", "--step", "0.25",
                                                "--no-plot", "--out-dir", "file"});
  ASSERT_EQ(from_file.exit_code, 0) << from_file.err;
  const run_result computed = run(dir.path(), {"report", "--tau-end", "2", "--step", "0.25", "--samples", "8",
                                               "--no-plot", "--out-dir", "computed"});
  ASSERT_EQ(computed.exit_code, 0) << computed.err;

  const auto a = lines_of(read_file(dir.path() / "file" / "errors.csv"));
  const auto b = lines_of(read_file(dir.path() / "computed" / "errors.csv"));
  ASSERT_EQ(a.size(), 10u);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a[0], b[0]);
  for (std::size_t i = 1; i < a.size(); ++i) {
    const auto ca = cells_of(a[i]), cb = cells_of(b[i]);
    ASSERT_EQ(ca.size(), cb.size());
    EXPECT_EQ(std::stod(ca[0]), 0.25 * static_cast<double>(i - 1));
    for (std::size_t c = 0; c < ca.size(); ++c) {
      const double x = std::stod(ca[c]), y = std::stod(cb[c]);
      EXPECT_LE(std::abs(x - y), 1e-12 * std::abs(y)) << "row " << i << " col " << c << ": " << x << " vs " << y;
    }
  }
  const json summary = json::parse(read_file(dir.path() / "file" / "summary.json"));
  EXPECT_EQ(summary["reference"]["precision"], "quad");
  EXPECT_TRUE(summary["reference"]["estimated_max_error"].is_null());  // not verified
}

TEST(Report, ReferenceFileProblemsNameTheLine) {
  temp_dir dir;
  const std::string good = "# precision: quad\n# estimated_max_error: 1.0e-30\ntau,Omega1,Omega2,Omega3\n"
                           "0,0.5,0,1\n0.5,0.5,0.1,1.1\n";
  struct bad_file {
    std::string text;
    std::vector<std::string> flags;
    std::string expected;
  };
  const std::vector<bad_file> cases = {
      {good, {"--step", "0.3"}, "line 5: tau = 0.5 is not a step point of h = 0.3"},
      {good, {"--step", "0.3"}, "--step"},
      {"tau,Omega1,Omega3\n0,0.5,1\n", {"--step", "0.25"}, "line 1: the header has no column `Omega2`"},
      {"# c\ntau,Omega1,Omega2,Omega3\n0,0.5,0,1\n0.25,0.5,x,1\n", {"--step", "0.25"}, "line 4: column Omega2 = `x`"},
      {"tau,Omega1,Omega2,Omega3\n0,0.5,0,1\n0.25,0.5,1\n", {"--step", "0.25"}, "line 3:"},
      {"# scene: other\ntau,Omega1,Omega2,Omega3\n0,0.5,0,1\n", {"--step", "0.25"},
       "the reference is for scene `other`, the report is for scene `paper-fig1`"},
      {good, {"--step", "0.25", "--tau-end", "0.25"}, "line 5: tau = 0.5 is beyond the span end"},
  };
  for (const bad_file& c : cases) {
    SCOPED_TRACE(c.expected);
    write_file(dir.path() / "r.csv", c.text);
    std::vector<std::string> args = {"report", "--reference", "r.csv", "--no-plot", "--out-dir", "out"};
    args.insert(args.end(), c.flags.begin(), c.flags.end());
    const run_result r = run(dir.path(), args);
    EXPECT_EQ(r.exit_code, 2);
    ASSERT_EQ(lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find("--reference r.csv: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir.path() / "out"));
  }
  // The good file with a fitting step: its metadata reaches the summary.
  write_file(dir.path() / "r.csv", good);
  const run_result ok = run(dir.path(), {"report", "--reference", "r.csv", "--step", "0.25", "--no-plot", "--format", "json",
                                         "--out-dir", "out"});
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const json summary = json::parse(ok.out);
  EXPECT_EQ(summary["reference"]["estimated_max_error"], 1e-30);
  EXPECT_EQ(run_of(summary, "vop", "rk4")["steps"], 2);  // the runs end at the file's last tau
}

// ---- the figure ----------------------------------------------------------------------------------

// Drawn when matplotlib is there; otherwise one line saying how to get it, and still exit 0.
TEST(Report, FigureOrOneLineHowToGetIt) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"report", "--tau-end", "2", "--samples", "20", "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  if (fs::exists(dir.path() / "out" / "fig1.png")) {
    EXPECT_TRUE(fs::exists(dir.path() / "out" / "fig1.svg"));
    EXPECT_TRUE(r.err.empty()) << r.err;
  } else {
    ASSERT_EQ(lines_of(r.err).size(), 1u) << r.err;
    EXPECT_TRUE(r.err.starts_with("figure skipped: matplotlib not found (apt-get install python3-matplotlib")) << r.err;
  }
}

}  // namespace
