// The attitude beside the rates of the double-precision runs (docs/attitude-runs.md):
// runs/detail/attitude.hpp in process (the rates of every formulation bit for bit those of the
// run without q, across the separatrix band and a regime change), and `eulervop report` on
// scenes with [initial] q: the attitude error converges at the method's order, the VOP's
// attitude error on a torque-free body is q's own truncation, the outputs' columns and keys.
#include "cli_test_support.hpp"

#include <eulervop/runs/comparison_run.hpp>

#include <eulervop/core/quaternion.hpp>
#include <eulervop/model/euler_problem.hpp>
#include <eulervop/runs/comparison_run.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace eulervop::cli_test;
using nlohmann::json;

// ---- in process: the runs ------------------------------------------------------------------------

bool same_bits(const std::vector<eulervop::vec3<double>>& a, const std::vector<eulervop::vec3<double>>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
}

// The crossing scene of docs/vop-strategies.md section 4: k rises through 1 near tau = 14.7, so
// the VOP runs take direct steps across the band and re-derive their elements in the other
// regime. With q (identity body rates: q turns by Omega), every formulation's rates, steps,
// bands and counts are bit for bit those of the run without q, and q stays a unit quaternion that
// agrees between formulations.
TEST(AttitudeRuns, QLeavesTheRatesBitForBitAcrossTheBand) {
  eulervop::euler_problem<double> p;
  p.torque = eulervop::constant_torque<double>{{-0.05, 0.0, -0.05}};
  p.Omega0 = {0.5, 0.0, 1.0};
  const double h = 1.6857503548125960429 / 200;
  const std::size_t n = static_cast<std::size_t>(40 / h);
  std::vector<eulervop::quaternion<double>> last;
  for (const eulervop::formulation f : eulervop::all_formulations) {
    const std::string name(eulervop::formulation_name(f));
    for (const auto m : {eulervop::rk::method::rk4, eulervop::rk::method::rk8}) {
      eulervop::fixed_run_settings s{h, n, 10};
      const eulervop::run_result a = eulervop::run_fixed(f, m, p, s);
      s.attitude = eulervop::attitude_settings{};
      const eulervop::run_result b = eulervop::run_fixed(f, m, p, s);
      EXPECT_TRUE(same_bits(a.Omega, b.Omega)) << name;
      EXPECT_EQ(a.sample_steps, b.sample_steps) << name;
      EXPECT_EQ(a.separatrix_bands, b.separatrix_bands) << name;
      EXPECT_EQ(a.direct_steps, b.direct_steps) << name;
      EXPECT_EQ(a.regime_changes, b.regime_changes) << name;
      EXPECT_TRUE(a.q.empty());
      ASSERT_EQ(b.q.size(), b.Omega.size()) << name;
      if (f != eulervop::formulation::euler) {
        EXPECT_EQ(b.separatrix_bands.size(), 1u) << name;  // the band was crossed
        EXPECT_EQ(b.regime_changes, 1u) << name;
      }
      for (const auto& q : b.q) EXPECT_NEAR(norm(q), 1.0, 1e-9) << name;
      if (m == eulervop::rk::method::rk8) last.push_back(b.q.back());
    }
    eulervop::adaptive_run_settings s;
    s.tau_end = 40;
    s.atol = s.rtol = 1e-10;
    s.samples = 100;
    for (const auto m : {eulervop::rk::method::rkf45, eulervop::rk::method::dp45, eulervop::rk::method::dop853}) {
      s.attitude.reset();
      const eulervop::run_result a = eulervop::run_adaptive(f, m, p, s);
      s.attitude = eulervop::attitude_settings{};
      const eulervop::run_result b = eulervop::run_adaptive(f, m, p, s);
      EXPECT_TRUE(same_bits(a.Omega, b.Omega)) << name;
      EXPECT_EQ(a.sample_tau, b.sample_tau) << name;
      EXPECT_EQ(a.steps, b.steps) << name;
      EXPECT_EQ(a.rejected, b.rejected) << name;
      EXPECT_EQ(a.rhs_evals, b.rhs_evals) << name;
      EXPECT_EQ(a.separatrix_bands, b.separatrix_bands) << name;
      ASSERT_EQ(b.q.size(), b.Omega.size()) << name;
      // The controller does not measure q: the VOP's long element steps leave |q| off by ~5e-8 here.
      EXPECT_NEAR(norm(b.q.back()), 1.0, 1e-6) << name;
    }
  }
  // rk8 at K/200 resolves q far below 1e-8: the three formulations end at the same attitude.
  ASSERT_EQ(last.size(), 3u);
  EXPECT_LT(eulervop::rotation_angle(last[0], last[1]), 1e-8);
  EXPECT_LT(eulervop::rotation_angle(last[0], last[2]), 1e-8);
  EXPECT_GT(eulervop::rotation_angle(eulervop::quaternion<double>{1, 0, 0, 0}, last[0]), 0.1);  // q did turn
}

// ---- `eulervop report` on scenes with an attitude ----------------------------------------------

const fs::path scenes = fs::path(source_dir) / "data" / "scenes";

// A copy of a shipped scene with `q = [...]` after its [initial] table's first line, renamed.
void write_with_attitude(const fs::path& from, const fs::path& to, const std::string& q) {
  std::string text = read_file(from);
  const std::size_t initial = text.find("[initial]");
  ASSERT_NE(initial, std::string::npos);
  const std::size_t eol = text.find('\n', text.find('\n', initial) + 1);
  text.insert(eol + 1, "q = " + q + "\n");
  write_file(to, text);
}

json report_json(const fs::path& dir, std::vector<std::string> args) {
  args.insert(args.begin(), "report");
  for (const char* a : {"--no-plot", "--format", "json"}) args.push_back(a);
  const run_result r = run(dir, args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return json::parse(r.out);
}

const json& run_of(const json& summary, const std::string& formulation, const std::string& method) {
  for (const json& r : summary.at("runs"))
    if (r.at("formulation") == formulation && r.at("method") == method) return r;
  throw std::runtime_error("no run " + formulation + "_" + method);
}

double max_attitude(const json& summary, const std::string& formulation, const std::string& method) {
  return run_of(summary, formulation, method).at("max_attitude_error").get<double>();
}

// The attitude error of euler rk4 falls 16-fold when the step halves (fourth order): the attitude
// is integrated by the run's own method, and the reference's attitude is far below it.
TEST(ReportAttitude, EulerRk4AttitudeConvergesAtFourthOrder) {
  temp_dir dir;
  write_with_attitude(scenes / "spacecraft-physical.toml", dir.path() / "s.toml", "[1.0, 0.0, 0.0, 0.0]");
  std::vector<double> e;
  for (const char* step : {"K/50", "K/100"}) {
    const json summary =
        report_json(dir.path(), {"s.toml", "--t-end", "600", "--step", step, "--formulations", "euler,vop", "--methods",
                                 "rk4", "--out-dir", step[2] == '5' ? "a" : "b"});
    e.push_back(max_attitude(summary, "euler", "rk4"));
  }
  ASSERT_GT(e[1], 0);
  EXPECT_GT(e[0] / e[1], 13.0) << e[0] << " " << e[1];
  EXPECT_LT(e[0] / e[1], 19.0) << e[0] << " " << e[1];
}

// Torque-free, the VOP elements are exact (rates at the rounding level) and every stage's Omega is
// exact, so the VOP's attitude error is q's own truncation by the method: the same for vop and
// vop-theta, falling 16-fold with the step for rk4, and with rk8 at K/200 at the rounding level
// of a thousand rotations (below 1e-13 for vop-theta, whose phase stays in [-pi, pi)).
TEST(ReportAttitude, TorqueFreeVopAttitudeIsQsOwnTruncation) {
  temp_dir dir;
  std::string text = read_file(scenes / "spacecraft-physical.toml");
  text.replace(text.find("M = ["), text.find('\n', text.find("M = [")) - text.find("M = ["), "M = [0.0, 0.0, 0.0]");
  write_file(dir.path() / "free.toml", text);
  write_with_attitude(dir.path() / "free.toml", dir.path() / "s.toml", "[0.5, 0.5, 0.5, 0.5]");
  std::vector<json> at;
  for (const char* step : {"K/100", "K/200"})
    at.push_back(report_json(dir.path(), {"s.toml", "--step", step, "--formulations", "euler,vop,vop-theta",
                                          "--methods", "rk4,rk8", "--out-dir", step[3] == '0' ? "a" : "b"}));
  for (const json& s : at)
    for (const char* f : {"vop", "vop-theta"}) {
      for (const char* m : {"rk4", "rk8"}) EXPECT_LT(run_of(s, f, m).at("max_error").get<double>(), 1e-13) << f << m;
      const double vop = max_attitude(s, "vop", "rk4"), theta = max_attitude(s, "vop-theta", "rk4");
      EXPECT_NEAR(vop / theta, 1.0, 1e-3);
    }
  const double ratio = max_attitude(at[0], "vop", "rk4") / max_attitude(at[1], "vop", "rk4");
  EXPECT_GT(ratio, 14.0);
  EXPECT_LT(ratio, 18.0);
  EXPECT_LT(max_attitude(at[1], "vop-theta", "rk8"), 1e-13);
  // Euler's rates carry an rk4 truncation error that its attitude integrates on top of q's own.
  EXPECT_GT(max_attitude(at[1], "euler", "rk4"), max_attitude(at[1], "vop", "rk4"));
}

// With an attitude: the table's attitude columns, max_attitude_error and final_attitude_error in
// every run of summary.json, errors.csv's second block `<run>_attitude` (after the rates' errors
// in rad/s, before the normalized `tau` and `<run>_normalized` block of a physical scene); every
// other column is that of the same scene without q, cell for cell. Without an attitude: none.
TEST(ReportAttitude, OutputsHaveTheAttitudeOnlyWithIt) {
  temp_dir dir;
  write_with_attitude(scenes / "spacecraft-physical.toml", dir.path() / "q.toml", "[0.5, 0.5, -0.5, 0.5]");
  const std::vector<std::string> common = {"--t-end", "900", "--formulations", "euler,vop,vop-theta", "--methods",
                                           "rk4,rkf45", "--no-plot"};
  auto args = [&](const std::string& scene, const std::string& out) {
    std::vector<std::string> a = {"report", scene};
    a.insert(a.end(), common.begin(), common.end());
    a.insert(a.end(), {"--out-dir", out});
    return a;
  };
  const run_result with = run(dir.path(), args("q.toml", "with"));
  ASSERT_EQ(with.exit_code, 0) << with.err;
  const run_result without = run(dir.path(), args((scenes / "spacecraft-physical.toml").string(), "without"));
  ASSERT_EQ(without.exit_code, 0) << without.err;
  EXPECT_NE(with.out.find("max att err"), std::string::npos) << with.out;
  EXPECT_EQ(without.out.find("att err"), std::string::npos) << without.out;

  const auto lines_with = lines_of(read_file(dir.path() / "with" / "errors.csv"));
  const auto lines_without = lines_of(read_file(dir.path() / "without" / "errors.csv"));
  ASSERT_EQ(lines_with.size(), lines_without.size());
  const std::vector<std::string> runs = {"euler_rk4", "euler_rkf45", "vop_rk4", "vop_rkf45", "vop-theta_rk4",
                                         "vop-theta_rkf45"};
  std::string rates = "t", normalized = ",tau", attitude;
  for (const auto& r : runs) {
    rates += "," + r;
    normalized += "," + r + "_normalized";
    attitude += "," + r + "_attitude";
  }
  EXPECT_EQ(lines_without[0], rates + normalized);
  EXPECT_EQ(lines_with[0], rates + attitude + normalized);
  const std::size_t n = runs.size();
  for (std::size_t i = 1; i < lines_with.size(); ++i) {
    const auto a = cells_of(lines_with[i]), b = cells_of(lines_without[i]);
    ASSERT_EQ(a.size(), 2 + 3 * n);
    ASSERT_EQ(b.size(), 2 + 2 * n);
    for (std::size_t c = 0; c <= n; ++c) EXPECT_EQ(a[c], b[c]) << "line " << i << " column " << c;
    for (std::size_t c = n + 1; c < b.size(); ++c) EXPECT_EQ(a[c + n], b[c]) << "line " << i << " column " << c;
    for (std::size_t c = n + 1; c <= 2 * n; ++c) {
      ASSERT_FALSE(a[c].empty()) << "line " << i;
      EXPECT_GE(std::stod(a[c]), 0);
      EXPECT_LT(std::stod(a[c]), 1e-3);
    }
  }
  const json sw = json::parse(read_file(dir.path() / "with" / "summary.json"));
  const json so = json::parse(read_file(dir.path() / "without" / "summary.json"));
  ASSERT_EQ(sw.at("runs").size(), runs.size());
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const json& a = sw.at("runs")[i];
    const json& b = so.at("runs")[i];
    EXPECT_GT(a.at("max_attitude_error").get<double>(), 0);
    EXPECT_LE(a.at("final_attitude_error").get<double>(), a.at("max_attitude_error").get<double>());
    EXPECT_FALSE(b.contains("max_attitude_error"));
    EXPECT_FALSE(b.contains("final_attitude_error"));
    EXPECT_EQ(a.at("max_error"), b.at("max_error"));
    EXPECT_EQ(a.at("steps"), b.at("steps"));
    EXPECT_EQ(a.at("rhs_evals"), b.at("rhs_evals"));
  }
  EXPECT_TRUE(sw.at("reference").contains("estimated_max_attitude_error"));
  EXPECT_FALSE(so.at("reference").contains("estimated_max_attitude_error"));
}

// Under error control (--tols): errors.csv's sixth column `attitude_error`, the rate columns and the
// steps those of the scene without q; a torque of time and state (the damped tumbling brick) and a
// piecewise torque with breakpoints (HNW's EULR), each with and without q.
TEST(ReportAttitude, AdaptiveRunsKeepTheirStepsAndAddTheAttitudeColumn) {
  temp_dir dir;
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const char* name : {"hnw-eulr", "tumbling-brick-damped"}) {
    std::string text = read_file(scenes / "problems" / (std::string(name) + ".toml"));
    if (const std::size_t q = text.find("\nq = "); q != std::string::npos)  // the scene without q
      text.erase(q, text.find('\n', q + 1) - q);
    const fs::path without = dir.path() / (std::string(name) + "-no-q.toml");
    write_file(without, text);
    const fs::path with = dir.path() / (std::string(name) + "-q.toml");
    write_with_attitude(without, with, "[0.6, 0.0, 0.8, 0.0]");
    pairs.emplace_back(with.string(), without.string());
  }
  for (const auto& [with_q, without_q] : pairs) {
    std::vector<std::vector<std::string>> rows[2];
    json summaries[2];
    for (int k = 0; k < 2; ++k) {
      const std::string out = k ? "without" : "with";
      const run_result r = run(dir.path(), {"report", k ? without_q : with_q, "--tols", "1e-7,1e-10", "--formulations",
                                            "euler,vop,vop-theta", "--methods", "rkf45,dp45,dop853", "--samples", "60",
                                            "--no-plot", "--out-dir", out});
      ASSERT_EQ(r.exit_code, 0) << r.err;
      const auto lines = lines_of(read_file(dir.path() / out / "errors.csv"));
      const bool physical = lines[0].find(",t,") != std::string::npos;  // t (s) and rad/s, then tau (Eq. 20)
      const std::string tail = physical ? ",tau,error_normalized" : "";
      EXPECT_EQ(lines[0], std::string(physical ? "formulation,method,tol,t,error" : "formulation,method,tol,tau,error") +
                              (k ? "" : ",attitude_error") + tail);
      for (std::size_t i = 1; i < lines.size(); ++i) rows[k].push_back(cells_of(lines[i]));
      summaries[k] = json::parse(read_file(dir.path() / out / "summary.json"));
    }
    ASSERT_EQ(rows[0].size(), rows[1].size()) << with_q;
    for (std::size_t i = 0; i < rows[0].size(); ++i) {
      // The row with q is the row without it and the attitude error as its sixth cell.
      ASSERT_EQ(rows[0][i].size(), rows[1][i].size() + 1);
      ASSERT_FALSE(rows[0][i][5].empty());
      EXPECT_GE(std::stod(rows[0][i][5]), 0);
      std::vector<std::string> without_attitude = rows[0][i];
      without_attitude.erase(without_attitude.begin() + 5);
      EXPECT_EQ(without_attitude, rows[1][i]) << with_q << " " << i;
    }
    for (std::size_t i = 0; i < summaries[0].at("runs").size(); ++i) {
      const json& a = summaries[0].at("runs")[i];
      const json& b = summaries[1].at("runs")[i];
      for (const char* key : {"steps", "rejected", "rhs_evals", "max_error", "final_error"})
        EXPECT_EQ(a.at(key), b.at(key)) << key;
      EXPECT_LT(a.at("max_attitude_error").get<double>(), 1e-3) << with_q;
      EXPECT_FALSE(b.contains("max_attitude_error"));
    }
    // The tighter tolerance gives the smaller attitude error, run by run.
    for (const json& a : summaries[0].at("runs")) {
      if (a.at("tol") != 1e-10) continue;
      for (const json& b : summaries[0].at("runs"))
        if (b.at("tol") == 1e-7 && b.at("formulation") == a.at("formulation") && b.at("method") == a.at("method"))
          EXPECT_LT(a.at("max_attitude_error").get<double>(), b.at("max_attitude_error").get<double>())
              << with_q << " " << a.at("formulation") << " " << a.at("method");
    }
  }
}

}  // namespace
