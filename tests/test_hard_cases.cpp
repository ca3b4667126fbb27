// The hard-case suite (table: docs/hard-cases.md): data/scenes/hard/*.toml through the program,
// and the reference generator on hard cases against independent checks.
//
// - No NaN anywhere: every hard scene through `eulervop report` (all three formulations, rk4;
//   Euler only for a body in the direct form of Eq. 1, to which the paper's VOP does not apply),
//   on a short span with the scene's own quad reference, and on its full span with a double
//   reference (fast; it still drives the spin-up scene's Euler rk4 run into its explosion).
//   Nothing in stdout, errors.csv or summary.json may read nan or inf.
// - Reference near the separatrix (k = 1 - 1e-6, torque-free, tau to 100): quad against
//   mpfr:192 from the same (exactly widened) initial state.
// - Reference at large |Omega| (Omega0 = (50, 0, 100), torque-free, tau to 20, ~320 periods):
//   quad against the exact Eq. 12 solution by Boost.Math jacobi_elliptic in MPFR at 256 bits,
//   with dn stabilised as sqrt(1 - k^2 sn^2) (docs/design.md section 2).
// - A forced failure (a torque that overflows double at tau = DBL_MAX / G3 = 1.798e8) is
//   reported with tau and cause, exit code 3 and no output file, by `reference` and `report`.
#include "cli_test_support.hpp"

#include <eulervop/reference/integrate.hpp>
#include <eulervop/model/error_measure.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace eulervop::cli_test;
using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;

std::vector<fs::path> hard_scenes() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(fs::path(source_dir) / "data" / "scenes" / "hard"))
    if (e.path().extension() == ".toml") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

bool is_physical(const fs::path& scene) {
  return std::regex_search(read_file(scene), std::regex(R"(^\s*t_end\s*=)", std::regex::multiline));
}

// A body whose moments are equal or nearly so: integrated in the direct form, Euler only.
bool is_direct_form(const fs::path& scene) {
  return eulervop::scene::uses_direct_form(eulervop::scene::load_scene_file(scene));
}

// "nan", "-nan", "inf", "-inf", "infinity", "NaN", ... as a word.
bool has_non_finite_text(const std::string& text) {
  static const std::regex bad(R"((^|[^A-Za-z_])(nan|inf|infinity)([^A-Za-z_]|$))", std::regex::icase);
  return std::regex_search(text, bad);
}

// Runs report on `scene` with `extra` flags; checks exit code 0 and that no output says nan/inf.
void expect_report_without_nan(const fs::path& scene, const std::vector<std::string>& extra) {
  temp_dir dir;
  const bool direct = is_direct_form(scene);
  std::vector<std::string> args = {"report", scene.string(), "--methods", "rk4", "--formulations",
                                   direct ? "euler" : "euler,vop,vop-theta", "--no-plot", "--out-dir", "out"};
  args.insert(args.end(), extra.begin(), extra.end());
  const auto start = std::chrono::steady_clock::now();
  const run_result r = run(dir.path(), args);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string name = scene.filename().string();
  std::printf("%-28s %-24s %.2f s\n", name.c_str(), extra.empty() ? "" : (extra[0] + " " + extra[1]).c_str(), seconds);
  // A numerical failure of the reference itself would be exit 3 with a one-line message; the
  // hard suite is built so that it never happens.
  ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
  EXPECT_FALSE(has_non_finite_text(r.out)) << name << " stdout:\n" << r.out;
  const std::string csv = read_file(dir.path() / "out" / "errors.csv");
  const std::string summary = read_file(dir.path() / "out" / "summary.json");
  ASSERT_FALSE(csv.empty()) << name;
  EXPECT_FALSE(has_non_finite_text(csv)) << name << ": errors.csv";
  EXPECT_FALSE(has_non_finite_text(summary)) << name << ": summary.json";
  const auto j = nlohmann::json::parse(summary);
  ASSERT_EQ(j.at("runs").size(), direct ? 1u : 3u) << name;
  EXPECT_EQ(j.contains("note"), direct) << name;
  for (const auto& run : j["runs"]) {
    // Every run has an error (a diverged run has one up to where it stopped) and the fallback fields.
    EXPECT_TRUE(run.at("max_error").is_number()) << name << " " << run["formulation"];
    for (const char* key : {"separatrix_bands", "small_k_bands"}) {
      ASSERT_TRUE(run.at(key).is_array()) << name;
      for (const auto& band : run[key]) {
        ASSERT_EQ(band.size(), 2u);
        EXPECT_LE(band[0].get<double>(), band[1].get<double>()) << name << " " << key;
      }
    }
    EXPECT_TRUE(run.at("direct_steps").is_number_unsigned());
    EXPECT_TRUE(run.at("regime_changes").is_number_unsigned());
  }
}

TEST(HardSuite, HasTheScenesOfIssue5) {
  const auto scenes = hard_scenes();
  EXPECT_GE(scenes.size(), 10u);
  for (const auto& s : scenes) {
    const std::string text = read_file(s);
    EXPECT_NE(text.find("description = \""), std::string::npos) << s << ": says what makes it hard";
    EXPECT_NE(text.find(is_direct_form(s) ? "formulations = [\"euler\"]"
                                          : "formulations = [\"euler\", \"vop\", \"vop-theta\"]"),
              std::string::npos)
        << s;
  }
}

// Short spans (the first ~20 tau, which include the crossing's band at 14.2-15.2 and the
// near-separatrix fallback) with the scenes' own quad reference.
TEST(HardSuite, NoNaNAnywhereOnShortSpans) {
  for (const auto& s : hard_scenes())
    expect_report_without_nan(s, is_physical(s) ? std::vector<std::string>{"--t-end", "360"}
                                                 : std::vector<std::string>{"--tau-end", "20"});
}

// Full spans with a double reference (the quad one of the long scenes takes ~10 s): the
// spin-up's Euler rk4 run explodes near tau = 340 and must stop with `diverged`, not NaN.
TEST(HardSuite, NoNaNAnywhereOnFullSpansWithADoubleReference) {
  for (const auto& s : hard_scenes()) expect_report_without_nan(s, {"--precision", "double"});
}

TEST(HardSuite, ReportSaysWhereTheFallbackHappened) {
  temp_dir dir;
  const fs::path scene = fs::path(source_dir) / "data" / "scenes" / "hard" / "crossing.toml";
  const run_result r = run(dir.path(), {"report", scene.string(), "--methods", "rk4", "--no-plot", "--out-dir", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Under the table: "vop rk4: separatrix band tau 14.19..15.19 (118 direct Euler steps, 1 regime change)".
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(\nvop rk4: separatrix band tau 14\.\d+\.\.15\.\d+ \(\d+ direct Euler steps, 1 regime change\)\n)")))
      << r.out;
  EXPECT_NE(r.out.find("\nvop-theta rk4: separatrix band tau 14."), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("euler rk4: "), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(read_file(dir.path() / "out" / "summary.json"));
  for (const auto& run : j["runs"]) {
    if (run["formulation"] == "euler") {
      EXPECT_TRUE(run["separatrix_bands"].empty());
      EXPECT_EQ(run["direct_steps"], 0);
      continue;
    }
    ASSERT_EQ(run["separatrix_bands"].size(), 1u) << run;
    const double in = run["separatrix_bands"][0][0], out = run["separatrix_bands"][0][1];
    EXPECT_GT(in, 14.0);
    EXPECT_LT(out, 15.5);
    EXPECT_GT(run["direct_steps"].get<int>(), 50);
    EXPECT_EQ(run["regime_changes"], 1);
    EXPECT_TRUE(run["small_k_bands"].empty());
  }
}

// ---- the reference generator on hard cases ---------------------------------------------------

template <class A, class B>
double eq20(const vec3<A>& a, const vec3<B>& b) {
  mpfr_real s = 0;
  for (int i = 0; i < 3; ++i) {
    const mpfr_real d = mpfr_real(a[i]) - mpfr_real(b[i]);
    s += d * d;
  }
  return static_cast<double>(sqrt(s));
}

// k = 1 - 1e-6 torque-free to tau = 100 (K = 7.95: ~3 periods of slow creeping near the
// intermediate axis with fast flips): quad against mpfr:192 at tau = i/16 (exact in both).
// The mpfr run starts from the quad initial state widened exactly, so the difference is the
// quad integration's own error, not the input rounding (amplified by dK/dk ~ 5e5 here).
TEST(HardReference, NearSeparatrixQuadAgreesWithMpfr192) {
  eulervop::euler_problem<quad> pq;
  pq.torque.G = {quad(0), quad(0), quad(0)};
  pq.Omega0 = {*eulervop::from_text<quad>("0.999999"), quad(0), quad(1)};
  const auto t0 = std::chrono::steady_clock::now();
  const auto q = eulervop::integrate_reference<quad>(pq, quad(100));
  const double tq = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  eulervop::mpfr_precision_scope scope(192);
  eulervop::euler_problem<mpfr_real> pm;
  pm.torque.G = {mpfr_real(0), mpfr_real(0), mpfr_real(0)};
  pm.Omega0 = {mpfr_real(pq.Omega0[0]), mpfr_real(0), mpfr_real(1)};
  ASSERT_EQ(quad(pm.Omega0[0]), pq.Omega0[0]);  // widened exactly
  const auto t1 = std::chrono::steady_clock::now();
  const auto m = eulervop::integrate_reference<mpfr_real>(pm, mpfr_real(100));
  const double tm = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  double worst = 0, worst_tau = 0;
  for (int i = 0; i <= 1600; ++i) {
    const double e = eq20(q(quad(i) / 16), m(mpfr_real(i) / 16));
    if (e > worst) {
      worst = e;
      worst_tau = i / 16.0;
    }
  }
  std::printf("k = 1 - 1e-6, tau 100: quad %.2f s, mpfr:192 %.2f s, max |quad - mpfr:192| = %.3e at tau %.4g\n", tq, tm,
              worst, worst_tau);
  EXPECT_LE(worst, 1e-25);
}

// The exact torque-free solution, Eq. 12, with u(0) = 0 (Omega2(0) = 0, Omega3(0) > 0, k < 1).
vec3<mpfr_real> exact_eq12(const mpfr_real& c1, const mpfr_real& c2, const mpfr_real& tau) {
  const mpfr_real k = c1 / c2;
  mpfr_real cn, dn;
  const mpfr_real sn = boost::math::jacobi_elliptic(k, c2 * tau, &cn, &dn);
  return {c1 * cn, c1 * sn, c2 * sqrt(1 - k * k * sn * sn)};
}

// Omega0 = (50, 0, 100) torque-free to tau = 20: u = c2 tau reaches 2000, ~300 periods 4K
// at a rotation rate 100 times the paper's.
TEST(HardReference, LargeOmegaQuadAgreesWithExactEq12) {
  eulervop::euler_problem<quad> p;
  p.torque.G = {quad(0), quad(0), quad(0)};
  p.Omega0 = {quad(50), quad(0), quad(100)};
  const auto t0 = std::chrono::steady_clock::now();
  eulervop::picard_stats stats;
  const auto q = eulervop::integrate_reference<quad>(p, quad(20), {}, {}, &stats);
  const double tq = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  eulervop::mpfr_precision_scope scope(256);
  double worst = 0, worst_tau = 0;
  for (int i = 0; i <= 640; ++i) {  // tau = i/32, exact in both
    const double e = eq20(q(quad(i) / 32), exact_eq12(mpfr_real(50), mpfr_real(100), mpfr_real(i) / 32));
    if (e > worst) {
      worst = e;
      worst_tau = i / 32.0;
    }
  }
  const double eps = static_cast<double>(std::numeric_limits<quad>::epsilon());
  std::printf("Omega0 = (50, 0, 100), tau 20: quad %.2f s (%zu segments), max |quad - exact| = %.3e (%.3g eps |Omega|) at tau %.4g\n",
              tq, stats.segments, worst, worst / (eps * 111.8), worst_tau);
  EXPECT_LE(worst, 1e-27);
}

// ---- failures are reported, never silent ------------------------------------------------------

// A torque that overflows double: Omega3 = G3 tau passes DBL_MAX = 1.798e308 at tau = 1.798e8.
// The double reference must stop there with exit code 3, "numerical failure at tau=<that>: why",
// and write nothing. (Nothing in the CLI caps segments or iterations, and a tolerance below
// epsilon does not fail: `reference --degree 4 --tolerance 1e-30` on crossing.toml succeeds
// after ~90 s of short segments. Overflow is the failure a user can provoke.)
double failure_tau(const std::string& err) {
  std::smatch m;
  if (!std::regex_search(err, m, std::regex(R"(numerical failure at tau=([0-9.eE+-]+): )"))) return -1;
  return std::stod(m[1]);
}

TEST(HardReference, ForcedFailureReportsTauAndCauseWithExitCode3) {
  temp_dir dir;
  write_file(dir.path() / "overflow.toml", overflow_scene());
  {
    const run_result r = run(dir.path(), {"reference", "overflow.toml", "--precision", "double", "--out", "ref.csv"});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    const auto lines = lines_of(r.err);
    ASSERT_FALSE(lines.empty());
    const std::string& last = lines.back();  // the progress line, if any, is cleared before it
    EXPECT_TRUE(last.starts_with("eulervop: numerical failure at tau=")) << r.err;
    EXPECT_NE(last.find("not converge"), std::string::npos) << last;  // the cause
    const double tau = failure_tau(last);
    EXPECT_NEAR(tau, 1.7977e8, 0.01e8) << last;
    EXPECT_FALSE(fs::exists(dir.path() / "ref.csv"));
    EXPECT_FALSE(has_non_finite_text(r.out + r.err));
  }
  {
    const run_result r = run(dir.path(), {"report", "overflow.toml", "--precision", "double", "--no-plot", "--out-dir",
                                          "rep"});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NEAR(failure_tau(r.err), 1.7977e8, 0.01e8) << r.err;
    EXPECT_FALSE(fs::exists(dir.path() / "rep")) << "no partial output";
    EXPECT_FALSE(has_non_finite_text(r.out + r.err));
  }
}

}  // namespace
