// `eulervop sweep` (docs/sweep.md): the grid in sweep.csv and its columns, identical error
// columns with --jobs 1 and --jobs 2, the observed order of rk4, divergence without NaN,
// cheapest.csv and summary.json, the formulations and the time of a scene in the coefficient
// form or in physical units, and bad flags.
#include "cli_test_support.hpp"

#include <eulervop/runs/comparison_run.hpp>

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

// sweep.csv as rows of named cells.
struct csv_table {
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
};

csv_table read_csv(const fs::path& p) {
  csv_table t;
  const auto lines = lines_of(read_file(p));
  if (lines.empty()) return t;
  t.header = cells_of(lines[0]);
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto cells = cells_of(lines[i]);
    EXPECT_EQ(cells.size(), t.header.size()) << lines[i];
    std::map<std::string, std::string> row;
    for (std::size_t c = 0; c < std::min(cells.size(), t.header.size()); ++c) row[t.header[c]] = cells[c];
    t.rows.push_back(std::move(row));
  }
  return t;
}

const std::map<std::string, std::string>& row_of(const csv_table& t, const std::string& form, const std::string& method,
                                                  const std::string& step) {
  for (const auto& r : t.rows)
    if (r.at("formulation") == form && r.at("method") == method && r.at("step") == step) return r;
  throw std::runtime_error("no row " + form + " " + method + " " + step);
}

const std::vector<std::string> tiny = {"sweep", "--tau-end", "5", "--steps", "K/25,K/50", "--methods", "rk4",
                                       "--repeat", "1", "--no-plot"};

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

TEST(Sweep, TinySweepWritesTheGrid) {
  temp_dir dir;
  const run_result r = run(dir.path(), with(tiny, {"--out-dir", "out"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;

  const csv_table t = read_csv(dir.path() / "out" / "sweep.csv");
  const std::vector<std::string> columns = {"formulation", "method",    "step",      "h",         "tol",
                                            "steps",       "accepted",  "rejected",  "rhs_evals", "seconds",
                                            "max_error",   "final_error", "diverged", "diverged_at"};
  EXPECT_EQ(t.header, columns);
  const std::size_t formulations = eulervop::all_formulations.size();
  ASSERT_EQ(t.rows.size(), formulations * 1 * 2);  // formulations x methods x steps
  for (std::size_t f = 0; f < formulations; ++f) {
    const std::string name(eulervop::formulation_name(eulervop::all_formulations[f]));
    for (const std::string step : {"K/25", "K/50"}) {
      const auto& row = row_of(t, name, "rk4", step);
      EXPECT_EQ(row.at("diverged"), "false");
      EXPECT_TRUE(row.at("diverged_at").empty());
      EXPECT_GT(std::stod(row.at("max_error")), 0);
      EXPECT_LE(std::stod(row.at("final_error")), std::stod(row.at("max_error")));
      EXPECT_GT(std::stod(row.at("seconds")), 0);
      EXPECT_EQ(std::stoul(row.at("rhs_evals")), 4 * std::stoul(row.at("steps")));  // rk4: 4 stages
      // Fixed-step rows leave the adaptive columns empty.
      EXPECT_TRUE(row.at("tol").empty());
      EXPECT_TRUE(row.at("accepted").empty());
      EXPECT_TRUE(row.at("rejected").empty());
    }
    // Output order: formulation-major, then method, then the steps as given.
    EXPECT_EQ(t.rows[2 * f].at("formulation"), name);
    EXPECT_EQ(t.rows[2 * f].at("step"), "K/25");
    EXPECT_EQ(t.rows[2 * f + 1].at("step"), "K/50");
  }
  // K/25 of K(0.5) = 1.6857503548125960429 (c2 = 1): 74 steps to tau 5.
  EXPECT_NEAR(std::stod(t.rows[0].at("h")), 1.6857503548125960429 / 25, 1e-15);
  EXPECT_EQ(t.rows[0].at("steps"), "74");

  const csv_table cheap = read_csv(dir.path() / "out" / "cheapest.csv");
  EXPECT_EQ(cheap.rows.size(), 5 * formulations);  // 5 levels
  const json summary = json::parse(read_file(dir.path() / "out" / "summary.json"));
  EXPECT_EQ(summary.at("runs").size(), formulations * 2);
  EXPECT_EQ(summary.at("cheapest").size(), 5u);
  EXPECT_EQ(summary.at("reference").at("precision"), "quad");
  EXPECT_NE(r.out.find("cheapest configuration per formulation"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "work_precision.png"));  // --no-plot
}

// The errors do not depend on how the cases were scheduled; --jobs 2 says its timings are
// less pure.
TEST(Sweep, ErrorColumnsIdenticalWithTwoJobs) {
  temp_dir dir;
  const std::vector<std::string> args = {"sweep", "--tau-end", "5", "--steps", "K/25,K/50", "--methods", "rk4,rk8",
                                         "--repeat", "1", "--no-plot"};
  const run_result one = run(dir.path(), with(args, {"--out-dir", "one", "--jobs", "1"}));
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const run_result two = run(dir.path(), with(args, {"--out-dir", "two", "--jobs", "2"}));
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const csv_table a = read_csv(dir.path() / "one" / "sweep.csv"), b = read_csv(dir.path() / "two" / "sweep.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  ASSERT_EQ(a.rows.size(), eulervop::all_formulations.size() * 2 * 2);
  for (std::size_t i = 0; i < a.rows.size(); ++i)
    for (const char* c : {"formulation", "method", "step", "h", "steps", "rhs_evals", "max_error", "final_error",
                          "diverged", "diverged_at"})
      EXPECT_EQ(a.rows[i].at(c), b.rows[i].at(c)) << "row " << i << " column " << c;
  EXPECT_EQ(one.out.find("in parallel"), std::string::npos) << one.out;
  EXPECT_NE(two.out.find("timings were taken in parallel and are less pure"), std::string::npos) << two.out;
}

// --tols alone: adaptive runs only, with their tolerance, accepted and rejected steps and
// evaluations; the errors fall with the tolerance; the cheapest table takes them in.
TEST(Sweep, ToleranceLadderGivesAdaptiveRows) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"sweep", "--tau-end", "20", "--tols", "1e-5,1e-7,1e-9", "--methods",
                                        "dp45,dop853", "--repeat", "1", "--no-plot", "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const csv_table t = read_csv(dir.path() / "out" / "sweep.csv");
  ASSERT_EQ(t.rows.size(), eulervop::all_formulations.size() * 2 * 3);
  for (const auto& form : eulervop::all_formulations) {
    for (const std::string method : {"dp45", "dop853"}) {
      double previous = 1e300;
      for (const std::string tol : {"1e-05", "1e-07", "1e-09"}) {
        const auto it = std::find_if(t.rows.begin(), t.rows.end(), [&](const auto& row) {
          return row.at("formulation") == eulervop::formulation_name(form) && row.at("method") == method &&
                 std::stod(row.at("tol")) == std::stod(tol);
        });
        ASSERT_NE(it, t.rows.end()) << method << " " << tol;
        const auto& row = *it;
        EXPECT_TRUE(row.at("step").empty());
        EXPECT_TRUE(row.at("h").empty());
        EXPECT_EQ(row.at("accepted"), row.at("steps"));
        EXPECT_GT(std::stoul(row.at("accepted")), 0u);
        EXPECT_FALSE(row.at("rejected").empty());
        // dp45: 6 new evaluations per attempted step (FSAL) plus 2 to start.
        if (method == "dp45")
          EXPECT_EQ(std::stoul(row.at("rhs_evals")),
                    2 + 6 * (std::stoul(row.at("accepted")) + std::stoul(row.at("rejected"))));
        const double e = std::stod(row.at("max_error"));
        EXPECT_LT(e, previous) << eulervop::formulation_name(form) << " " << method << " " << tol;
        previous = e;
      }
    }
  }
  const json summary = json::parse(read_file(dir.path() / "out" / "summary.json"));
  EXPECT_EQ(summary.at("tols").size(), 3u);
  EXPECT_TRUE(summary.at("runs").at(0).at("step").is_null());
  EXPECT_EQ(summary.at("runs").at(0).at("tol"), 1e-5);
  EXPECT_TRUE(summary.at("runs").at(0).contains("accepted"));
  EXPECT_TRUE(summary.at("runs").at(0).contains("rejected"));
  const csv_table cheap = read_csv(dir.path() / "out" / "cheapest.csv");
  bool adaptive_cheapest = false;
  for (const auto& row : cheap.rows) adaptive_cheapest = adaptive_cheapest || !row.at("tol").empty();
  EXPECT_TRUE(adaptive_cheapest);
  EXPECT_NE(r.out.find("tol 1e-7"), std::string::npos) << r.out;
}

// --steps and --tols together: both ladders, each method on the ladders it runs on.
TEST(Sweep, BothLaddersTogether) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"sweep", "--tau-end", "5", "--steps", "K/25", "--tols", "1e-6", "--methods",
                                        "rk4,dp45,dop853", "--formulations", "euler", "--repeat", "1", "--no-plot",
                                        "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const csv_table t = read_csv(dir.path() / "out" / "sweep.csv");
  // rk4 at K/25; dp45 at K/25 and at 1e-6; dop853 at 1e-6.
  ASSERT_EQ(t.rows.size(), 4u);
  EXPECT_EQ(t.rows[0].at("method"), "rk4");
  EXPECT_EQ(t.rows[1].at("method"), "dp45");
  EXPECT_EQ(t.rows[1].at("step"), "K/25");
  EXPECT_EQ(t.rows[2].at("method"), "dp45");
  EXPECT_FALSE(t.rows[2].at("tol").empty());
  EXPECT_EQ(t.rows[3].at("method"), "dop853");
}

// Halving the step divides rk4's error by about 2^4 on the direct Euler equations.
TEST(Sweep, Rk4ErrorRatioIsAboutSixteen) {
  temp_dir dir;
  const run_result r = run(dir.path(), with(tiny, {"--out-dir", "out", "--formulations", "euler"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const csv_table t = read_csv(dir.path() / "out" / "sweep.csv");
  ASSERT_EQ(t.rows.size(), 2u);
  const double ratio = std::stod(row_of(t, "euler", "rk4", "K/25").at("max_error")) /
                       std::stod(row_of(t, "euler", "rk4", "K/50").at("max_error"));
  EXPECT_GT(ratio, 8) << ratio;
  EXPECT_LT(ratio, 32) << ratio;
}

// A step far too large for the spin-up diverges: kept, marked, no error number, no NaN, and not
// a candidate for the cheapest table.
TEST(Sweep, DivergedRunIsMarkedWithoutNaN) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"sweep", "--tau-end", "30", "--steps", "K/2,K/25", "--methods", "rk4",
                                        "--formulations", "euler", "--repeat", "1", "--no-plot", "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = read_file(dir.path() / "out" / "sweep.csv");
  expect_no_nan(csv, "sweep.csv");
  expect_no_nan(read_file(dir.path() / "out" / "cheapest.csv"), "cheapest.csv");
  expect_no_nan(read_file(dir.path() / "out" / "summary.json"), "summary.json");
  expect_no_nan(r.out, "stdout");
  const csv_table t = read_csv(dir.path() / "out" / "sweep.csv");
  const auto& bad = row_of(t, "euler", "rk4", "K/2");
  EXPECT_EQ(bad.at("diverged"), "true");
  EXPECT_TRUE(bad.at("max_error").empty());
  EXPECT_TRUE(bad.at("final_error").empty());
  EXPECT_GT(std::stod(bad.at("diverged_at")), 0);
  EXPECT_NE(r.out.find("DIVERGED at tau="), std::string::npos) << r.out;
  const json summary = json::parse(read_file(dir.path() / "out" / "summary.json"));
  for (const json& level : summary.at("cheapest")) {
    const json& e = level.at("by_formulation").at("euler");
    if (!e.is_null()) EXPECT_EQ(e.at("step"), "K/25");
  }
}

// ---- the scene's own forms and time ----------------------------------------------------------------

const std::string sciml_scene = source_dir + "/data/scenes/problems/sciml-rigid-body.toml";

// The coefficient form takes euler alone: chosen by default and said so, in t (the scene's time,
// which has no unit), never in tau.
TEST(Sweep, CoefficientFormRunsEulerAloneInItsOwnTime) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"sweep", sciml_scene, "--tols", "1e-6,1e-9", "--methods", "dop853", "--repeat",
                                        "1", "--no-plot", "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("1 formulation(s) x 1 method(s) on 0 step(s) and 2 tolerance(s) = 2 runs, to t = 10\n"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("tau"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\nnote: the paper's VOP does not apply to the coefficient form"), std::string::npos) << r.out;
  const csv_table t = read_csv(dir.path() / "out" / "sweep.csv");
  ASSERT_EQ(t.rows.size(), 2u);
  for (const auto& row : t.rows) EXPECT_EQ(row.at("formulation"), "euler");
  const json summary = json::parse(read_file(dir.path() / "out" / "summary.json"));
  EXPECT_EQ(summary.at("time"), json({{"name", "t"}, {"unit", nullptr}, {"end", 10.0}}));  // the scene's t_end
  EXPECT_TRUE(summary.at("note").get<std::string>().ends_with("so only euler runs"));
}

// A formulation the scene cannot take, asked for, is refused in one line naming the flag, before
// anything is computed or written.
TEST(Sweep, RefusesVopForTheCoefficientForm) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"sweep", sciml_scene, "--tols", "1e-6", "--formulations", "euler,vop-theta",
                                        "--no-plot", "--out-dir", "out"});
  expect_one_line_error(r, "--formulations euler,vop-theta: formulation vop-theta cannot run on scene "
                           "`sciml-rigid-body`: the paper's VOP does not apply to the coefficient form");
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

// A physical body in the normalized form: the span, the steps and the times in s, tau beside the
// span (the runs integrate in it). t_end = 600 s is the scene's; h in s times dtau/dt (the
// reference's tau_end over the span in s) gives back the step rule's h in tau.
TEST(Sweep, PhysicalSceneSpeaksSeconds) {
  temp_dir dir;
  const run_result r =
      run(dir.path(), {"sweep", source_dir + "/data/scenes/spacecraft-physical.toml", "--t-end", "600", "--steps",
                       "K/25", "--tols", "1e-6", "--methods", "rk4,dop853", "--formulations", "euler,vop", "--repeat",
                       "1", "--no-plot", "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("runs, to t = 600 s (tau = "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" h (s) "), std::string::npos) << r.out;
  const json summary = json::parse(read_file(dir.path() / "out" / "summary.json"));
  EXPECT_EQ(summary.at("time").at("unit"), "s");
  EXPECT_NEAR(summary.at("time").at("end").get<double>(), 600.0, 1e-12 * 600);
  EXPECT_TRUE(summary.at("note").is_null());
  const double rate = summary.at("reference").at("tau_end").get<double>() / 600.0;
  const json& step = summary.at("steps").at(0);
  const std::string rule = step.at("rule");  // "h = K(k0)/(25 c2) = H with ..."
  const double h_tau = std::stod(rule.substr(rule.find(" = ", 4) + 3));
  EXPECT_NEAR(step.at("h").get<double>() * rate, h_tau, 1e-12 * h_tau);
  const csv_table t = read_csv(dir.path() / "out" / "sweep.csv");
  EXPECT_EQ(std::stod(row_of(t, "euler", "rk4", "K/25").at("h")), step.at("h").get<double>());
}

// ---- bad input ------------------------------------------------------------------------------------

struct bad_sweep {
  const char* label;
  std::vector<std::string> args;
  std::string expected;  // must appear in the one-line message
};

std::vector<bad_sweep> bad_sweeps() {
  return {
      {"step K over 0", {"--steps", "K/25,K/0"}, "--steps K/0"},
      {"step negative", {"--steps", "-1"}, "--steps -1"},
      {"step text", {"--steps", "K/25,abc"}, "--steps abc"},
      {"step empty item", {"--steps", "K/25,"}, "--steps K/25,"},
      {"step twice", {"--steps", "K/25,K/25"}, "K/25 is listed twice"},
      {"step longer than span", {"--steps", "100"}, "--steps 100"},
      {"repeat 0", {"--repeat", "0"}, "--repeat 0"},
      {"jobs 0", {"--jobs", "0"}, "--jobs 0"},
      {"jobs text", {"--jobs", "two"}, "--jobs two"},
      {"unknown method", {"--methods", "rk4,euler1"}, "method `euler1` is unknown"},
      {"unknown formulation", {"--formulations", "euler,lagrange"}, "formulation `lagrange` is unknown"},
      {"samples 1", {"--samples", "1"}, "--samples 1"},
      {"precision", {"--precision", "half"}, "--precision half"},
      {"out dir is a file", {"--out-dir", "scene.toml"}, "--out-dir scene.toml"},
      {"tols negative", {"--tols", "1e-6,-1e-8"}, "--tols 1e-6,-1e-8: -1e-8 is not a positive finite number"},
      {"tols zero", {"--tols", "0"}, "--tols 0: 0 is not a positive finite number"},
      {"tols nan", {"--tols", "1e-6,nan"}, "--tols 1e-6,nan"},
      {"tols unsorted", {"--tols", "1e-6,1e-4,1e-8"}, "--tols 1e-6,1e-4,1e-8: not sorted at 1e-8"},
      {"tols repeated", {"--tols", "1e-6,1e-6"}, "not sorted"},
      {"tols not below one", {"--tols", "2,1e-6"}, "--tols 2,1e-6: 2 is not below 1"},
      {"tols with rk4 only", {"--tols", "1e-6", "--methods", "rk4"}, "rk4 has no embedded error estimate"},
      {"dop853 without tols", {"--steps", "K/25", "--methods", "dop853"}, "dop853 is run under error control"},
      {"max step zero", {"--max-step", "0"}, "--max-step 0"},
      {"max step K/0", {"--max-step", "K/0"}, "--max-step K/0"},
  };
}

class BadSweep : public ::testing::TestWithParam<bad_sweep> {};

TEST_P(BadSweep, ExitsTwoWithOneLineAndNoFiles) {
  const bad_sweep& c = GetParam();
  temp_dir dir;
  write_file(dir.path() / "scene.toml", "not a directory\n");
  std::vector<std::string> args = {"sweep", "--no-plot", "--tau-end", "2"};
  args.insert(args.end(), c.args.begin(), c.args.end());
  const run_result r = run(dir.path(), args);
  expect_one_line_error(r, c.expected);
  const std::vector<std::string> files = entries_except(dir.path(), "scene.toml");
  EXPECT_TRUE(files.empty()) << files.front();  // not even the default ./eulervop-sweep/
}

INSTANTIATE_TEST_SUITE_P(Table, BadSweep, ::testing::ValuesIn(bad_sweeps()),
                         [](const ::testing::TestParamInfo<bad_sweep>& info) { return test_name_of(info.param.label); });

TEST(Sweep, UnknownCommandListsSweep) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"swep"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("expected: reference, report, sweep"), std::string::npos) << r.err;
}

// ---- the figure ----------------------------------------------------------------------------------

TEST(Sweep, FigureOrOneLineHowToGetIt) {
  temp_dir dir;
  std::vector<std::string> args = tiny;
  args.erase(std::find(args.begin(), args.end(), "--no-plot"));
  const run_result r = run(dir.path(), with(args, {"--out-dir", "out"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  if (fs::exists(dir.path() / "out" / "work_precision.png")) {
    EXPECT_TRUE(fs::exists(dir.path() / "out" / "work_precision.svg"));
    EXPECT_TRUE(r.err.empty()) << r.err;
  } else {
    ASSERT_EQ(lines_of(r.err).size(), 1u) << r.err;
    EXPECT_TRUE(r.err.starts_with("figure skipped: matplotlib not found (apt-get install python3-matplotlib")) << r.err;
  }
}

}  // namespace
