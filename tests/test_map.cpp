// `eulervop map`: the torque scaled exactly, the cheapest configuration per formulation, scale and
// level, the speed-up of the best VOP over Euler, the pruned ladders, the output files, and bad
// flags. Also the exact decimal product behind the scaling (in process).
#include "cli_test_support.hpp"

#include <eulervop/scene/decimal.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace eulervop::cli_test;
using nlohmann::json;

// ---- the exact product (in process) ---------------------------------------------------------------

TEST(DecimalProduct, IsExactAndCanonical) {
  auto product = [](const char* a, const char* b) {
    const auto x = eulervop::scene::parse_decimal(a).number, y = eulervop::scene::parse_decimal(b).number;
    return eulervop::scene::decimal_product(*x, *y)->text;
  };
  EXPECT_EQ(product("1.0", "1e-6"), "1e-6");
  EXPECT_EQ(product("0.03", "1e-4"), "3e-6");    // in double 0.03 * 1e-4 = 2.9999999999999997e-06
  EXPECT_EQ(product("-0.05", "20"), "-1");
  EXPECT_EQ(product("1.5", "2.5"), "3.75");
  EXPECT_EQ(product("123.456", "1000"), "1.23456e5");
  EXPECT_EQ(product("0", "5"), "0");
  EXPECT_EQ(eulervop::scene::decimal_product(*eulervop::scene::parse_decimal("1e300").number,
                                             *eulervop::scene::parse_decimal("1e300").number),
            std::nullopt);  // beyond a double
}

// ---- a small map ------------------------------------------------------------------------------------

const std::vector<std::string> small = {"map",      "--tau-end", "20",        "--torque-scales", "1e-3,1e-1",
                                        "--levels", "1e-5,1e-8", "--steps",   "K/6,K/25,K/100",  "--tols",
                                        "1e-6,1e-9,1e-12",       "--methods", "rk8,dop853",      "--no-plot"};

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

TEST(Map, SmallMapWritesTheCellsAndTheirSpeedUps) {
  temp_dir dir;
  const run_result r = run(dir.path(), with(small, {"--out-dir", "out"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  expect_no_nan(read_file(dir.path() / "out" / "map.csv"), "map.csv");

  const auto lines = lines_of(read_file(dir.path() / "out" / "map.csv"));
  ASSERT_EQ(lines.size(), 1u + 2 * 2);  // header, scales x levels
  const auto header = cells_of(lines[0]);
  std::map<std::string, std::size_t> col;
  for (std::size_t c = 0; c < header.size(); ++c) col[header[c]] = c;
  for (const char* name : {"scale", "level", "euler_config", "euler_seconds", "euler_max_error", "vop_config",
                           "vop-theta_config", "vop-theta_seconds", "best_vop", "speedup"})
    EXPECT_TRUE(col.count(name)) << name;

  const json summary = json::parse(read_file(dir.path() / "out" / "summary.json"));
  ASSERT_EQ(summary.at("scales").size(), 2u);
  EXPECT_EQ(summary.at("scales").at(0).at("torque"), "(1e-3, 1e-3, 1e-3)");  // the paper's G = (1, 1, 1) scaled
  EXPECT_EQ(summary.at("scales").at(1).at("torque"), "(1e-1, 1e-1, 1e-1)");
  for (const json& scale : summary.at("scales")) {
    ASSERT_EQ(scale.at("cells").size(), 2u);
    for (const json& cell : scale.at("cells")) {
      const json& by = cell.at("by_formulation");
      for (const auto& [name, best] : by.items()) {
        if (best.is_null()) continue;
        EXPECT_LE(best.at("max_error").get<double>(), cell.at("level").get<double>()) << name;
      }
      if (cell.at("speedup").is_null()) continue;
      // The speed-up is the cheapest Euler time over the cheapest VOP time, and the best VOP is
      // the faster of vop and vop-theta.
      const double euler = by.at("euler").at("seconds");
      const std::string best_vop = cell.at("best_vop");
      const double vop = by.at(best_vop).at("seconds");
      EXPECT_NEAR(cell.at("speedup").get<double>(), euler / vop, 1e-12 * euler / vop);
      for (const char* other : {"vop", "vop-theta"})
        if (!by.at(other).is_null()) EXPECT_LE(vop, by.at(other).at("seconds").get<double>());
    }
  }
  EXPECT_NE(r.out.find("speed-up of the cheapest VOP configuration"), std::string::npos) << r.out;
}

// A ladder stops at the first rung that reaches the smallest level: the rungs after it are
// marked skipped in runs.csv and never chosen.
TEST(Map, LaddersStopOnceTheyReachTheSmallestLevel) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"map", "--tau-end", "20", "--torque-scales", "1e-4", "--levels", "1e-4",
                                        "--steps", "K/25,K/50,K/100", "--tols", "1e-6,1e-9", "--methods", "rk8,dop853",
                                        "--formulations", "euler,vop", "--no-plot", "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto lines = lines_of(read_file(dir.path() / "out" / "runs.csv"));
  ASSERT_EQ(lines.size(), 1u + 2 * (3 + 2));
  // rk8 at K/25 reaches 1e-4 over 20 tau (about 1e-9 for Euler): K/50 and K/100 are skipped.
  std::size_t skipped = 0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto c = cells_of(lines[i]);
    if (c.back() == "true") {
      ++skipped;
      EXPECT_TRUE(c[10].empty()) << lines[i];  // no error number for a run not run
    }
  }
  EXPECT_EQ(skipped, 2u * (2 + 1));
}

// ---- bad input --------------------------------------------------------------------------------------

struct bad_map {
  const char* label;
  std::vector<std::string> args;
  std::string expected;
};

std::vector<bad_map> bad_maps() {
  return {
      {"scales negative", {"--torque-scales", "1e-4,-1"}, "--torque-scales 1e-4,-1: -1 is not a positive finite number"},
      {"scales zero", {"--torque-scales", "0,1"}, "--torque-scales 0,1: 0 is not a positive finite number"},
      {"scales nan", {"--torque-scales", "nan,1"}, "--torque-scales nan,1"},
      {"scales unsorted", {"--torque-scales", "1e-4,1,1e-2"}, "--torque-scales 1e-4,1,1e-2: not sorted at 1e-2"},
      {"scales repeated", {"--torque-scales", "1,1"}, "not sorted"},
      {"scales text", {"--torque-scales", "big"}, "--torque-scales big"},
      {"levels negative", {"--levels", "-1e-6"}, "--levels -1e-6"},
      {"levels not below one", {"--levels", "1e-6,2"}, "--levels 1e-6,2"},
      {"tols unsorted", {"--tols", "1e-6,1e-4,1e-8"}, "--tols 1e-6,1e-4,1e-8: not sorted"},
      {"tols with rk4 only", {"--tols", "1e-6", "--methods", "rk4"}, "rk4 has no embedded error estimate"},
      {"euler only", {"--formulations", "euler"}, "--formulations euler: the map compares euler with vop"},
      {"jobs 0", {"--jobs", "0"}, "--jobs 0"},
      {"repeat text", {"--repeat", "x"}, "--repeat x"},
      {"torque-free scene", {"free.toml"}, "scene `free` has no torque to scale"},
  };
}

class BadMap : public ::testing::TestWithParam<bad_map> {};

TEST_P(BadMap, ExitsTwoWithOneLineAndNoFiles) {
  const bad_map& c = GetParam();
  temp_dir dir;
  write_file(dir.path() / "free.toml",
             "name = \"free\"\n[initial]\nOmega = [0.5, 0.0, 1.0]\n[span]\ntau_end = 2.0\nsamples = 3\n");
  std::vector<std::string> args = {"map", "--no-plot", "--tau-end", "2"};
  args.insert(args.end(), c.args.begin(), c.args.end());
  const run_result r = run(dir.path(), args);
  expect_one_line_error(r, c.expected);
  const std::vector<std::string> files = entries_except(dir.path(), "free.toml");
  EXPECT_TRUE(files.empty()) << files.front();  // not even the default ./eulervop-map/
}

INSTANTIATE_TEST_SUITE_P(Table, BadMap, ::testing::ValuesIn(bad_maps()),
                         [](const ::testing::TestParamInfo<bad_map>& info) { return test_name_of(info.param.label); });

// The coefficient form takes euler alone, and a map compares euler with VOP: refused in one line
// naming the scene and why, before anything is written.
TEST(Map, RefusesASceneWhereOnlyEulerRuns) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"map", source_dir + "/data/scenes/problems/sciml-rigid-body.toml", "--no-plot",
                                        "--out-dir", "out"});
  expect_one_line_error(r, "scene `sciml-rigid-body`: the paper's VOP does not apply to the coefficient form");
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

TEST(Map, UnknownCommandListsMap) {
  temp_dir dir;
  const run_result r = run(dir.path(), {"mapp"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("map"), std::string::npos) << r.err;
}

// ---- the figure ------------------------------------------------------------------------------------

TEST(Map, FigureOrOneLineHowToGetIt) {
  temp_dir dir;
  std::vector<std::string> args = small;
  args.pop_back();  // --no-plot
  const run_result r = run(dir.path(), with(args, {"--out-dir", "out"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  if (fs::exists(dir.path() / "out" / "regime_map.png")) {
    EXPECT_TRUE(fs::exists(dir.path() / "out" / "regime_map.svg"));
    EXPECT_TRUE(r.err.empty()) << r.err;
  } else {
    ASSERT_EQ(lines_of(r.err).size(), 1u) << r.err;
    EXPECT_TRUE(r.err.starts_with("figure skipped: matplotlib not found (apt-get install python3-matplotlib")) << r.err;
  }
}

}  // namespace
