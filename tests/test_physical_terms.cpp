// A physical scene in the user's own terms, run as an attitude engineer runs it: a gravity-gradient
// body with rate damping. `report` speaks t in s and the rates' error in rad/s (its normalized
// figures beside, named so), every error figure of a reference and of a batch manifest carries
// its unit, numbers may be constant formulas in every numeric key, and a quaternion rounded to six
// digits is normalized with a note, and --verify estimates the rates in rad/s too. `sweep` and
// `map` give the attitude error beside the rates'.
//
// Truths: the rates' error in rad/s is |sqrt(A) (Omega - Omega*)|_2 (Eq. 2, omega = P^T sqrt(A)
// Omega), so at each sample it lies between min_i sqrt(|A_i|) and max_i sqrt(|A_i|) times the
// normalized Eq. 20 error; t = tau / (dtau/dt) with dtau/dt = sqrt(|A1 A2 A3|) (Eq. 4). Both are
// computed here from the moments by Eqs. 3-4, not by the program's code.
#include "cli_test_support.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace {

using namespace eulervop::cli_test;

// The body, its damping and its orbit; `extra` ends the scene (its [span]).
std::string gravity_damped(const std::string& mean_motion, const std::string& q, const std::string& span) {
  return "name = \"gg-damped\"\n[body]\ninertia = [100.0, 150.0, 200.0]\n[torque]\n"
         "M = [\"-0.002*omega1\", \"-0.002*omega2\", \"-0.002*omega3\"]\n[torque.gravity_gradient]\nmean_motion = " +
         mean_motion + "\n[initial]\nomega = [0.02, 0.1, 0.05]\nq = " + q + "\n[span]\n" + span;
}

// sqrt(|A_i|) of Eq. 3 for the moments (100, 150, 200), A_i = (I_j - I_k) / I_i cyclic, and the
// rate of time of Eq. 4.
struct scaling_by_hand {
  double sqrt_A[3];
  double rate;
  scaling_by_hand() {
    const double I[3] = {100.0, 150.0, 200.0};
    double prod = 1;
    for (int i = 0; i < 3; ++i) {
      const double A = (I[(i + 1) % 3] - I[(i + 2) % 3]) / I[i];
      sqrt_A[i] = std::sqrt(std::abs(A));
      prod *= std::abs(A);
    }
    rate = std::sqrt(prod);
  }
};

// The header and the data rows of a CSV text, as one table (row 0 the header).
std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows = table_rows(text, &header);
  rows.insert(rows.begin(), header);
  return rows;
}

TEST(PhysicalTerms, ReportSpeaksSecondsAndRadiansPerSecond) {
  temp_dir dir;
  write_file(dir.path() / "s.toml", gravity_damped("0.00113", "[1.0, 0.0, 0.0, 0.0]", "t_end = 600.0\nsamples = 31\n"));
  const run_result r = run(dir.path(), {"report", "s.toml", "--out-dir", "rep", "--no-plot"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("steps to t = "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max error (rad/s)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("final t (s)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max normalized"), std::string::npos) << r.out;

  const scaling_by_hand by_hand;
  const double lo = *std::min_element(by_hand.sqrt_A, by_hand.sqrt_A + 3);
  const double hi = *std::max_element(by_hand.sqrt_A, by_hand.sqrt_A + 3);
  const auto rows = csv_rows(read_file(dir.path() / "rep/errors.csv"));
  ASSERT_GT(rows.size(), 3u);
  const std::vector<std::string>& header = rows[0];
  ASSERT_EQ(header[0], "t");
  const auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t tau = column("tau"), rk4 = column("euler_rk4"), rk4_n = column("euler_rk4_normalized");
  ASSERT_LT(tau, header.size());
  ASSERT_LT(rk4_n, header.size());
  EXPECT_LT(rk4, column("euler_rk4_attitude")) << "the rates' error first, then the attitude's";
  std::size_t compared = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const double t = std::stod(rows[i][0]), tau_i = std::stod(rows[i][tau]);
    EXPECT_NEAR(t, tau_i / by_hand.rate, 1e-12 * std::max(1.0, t)) << "row " << i;
    if (rows[i][rk4].empty() || rows[i][rk4_n].empty()) continue;
    const double rate = std::stod(rows[i][rk4]), normalized = std::stod(rows[i][rk4_n]);
    EXPECT_GE(rate, lo * normalized * (1 - 1e-12)) << "row " << i;
    EXPECT_LE(rate, hi * normalized * (1 + 1e-12)) << "row " << i;
    compared += normalized > 0;
  }
  EXPECT_GT(compared, 10u);

  const nlohmann::json j = nlohmann::json::parse(read_file(dir.path() / "rep/summary.json"));
  EXPECT_EQ(j["units"]["time"], "s");
  EXPECT_EQ(j["units"]["error"].get<std::string>().substr(0, 5), "rad/s");
  EXPECT_TRUE(j["reference"].contains("estimated_max_error_normalized"));
  const auto& run0 = j["runs"][0];
  EXPECT_NEAR(run0["final_t"].get<double>(), run0["final_tau"].get<double>() / by_hand.rate, 1e-9);
  EXPECT_LE(run0["max_error"].get<double>(), hi * run0["max_error_normalized"].get<double>() * (1 + 1e-12));
  EXPECT_GE(run0["max_error"].get<double>(), lo * run0["max_error_normalized"].get<double>() * (1 - 1e-12));

  // Under error control too.
  const run_result a = run(dir.path(), {"report", "s.toml", "--tols", "1e-8", "--out-dir", "ad", "--no-plot"});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_NE(a.out.find("max error (rad/s)"), std::string::npos) << a.out;
  EXPECT_TRUE(read_file(dir.path() / "ad/errors.csv").starts_with("formulation,method,tol,t,error,attitude_error,tau,"
                                                                   "error_normalized\n"));
}

// A normalized scene's report keeps the integrator's variables: tau and Eq. 20.
TEST(PhysicalTerms, NormalizedReportKeepsTau) {
  temp_dir dir;
  const run_result r =
      run(dir.path(), {"report", "--tau-end", "5", "--samples", "11", "--out-dir", "rep", "--no-plot"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("steps to tau = "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("rad/s"), std::string::npos) << r.out;
  EXPECT_TRUE(read_file(dir.path() / "rep/errors.csv").starts_with("tau,"));
}

// When VOP's elements hold for almost none of the run (the damping leaves omega1 and omega2 near
// 0 while the gravity gradient still acts: the small-k fallback), the table says the run is
// mostly direct Euler steps.
TEST(PhysicalTerms, ReportSaysWhenVopMostlyFellBack) {
  temp_dir dir;
  std::string scene = gravity_damped("0.00113", "[1.0, 0.0, 0.0, 0.0]", "t_end = 2000.0\nsamples = 3\n");
  scene.replace(scene.find("\"-0.002*omega1\", \"-0.002*omega2\""), 32, "\"-20*omega1\", \"-20*omega2\"");
  scene.replace(scene.find("[0.02, 0.1, 0.05]"), 17, "[0.002, 0.001, 0.05]");
  write_file(dir.path() / "s.toml", scene);
  const run_result r = run(dir.path(), {"report", "s.toml", "--out-dir", "rep", "--no-plot"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("vop rk4: VOP applied on only "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("so its row measures mostly the direct integration"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("small-k band"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" s ("), std::string::npos) << "the stretches in s: " << r.out;
}

// Every error figure of a physical reference and of a batch manifest carries its unit.
TEST(PhysicalTerms, EveryFigureCarriesItsUnit) {
  temp_dir dir;
  write_file(dir.path() / "s.toml", gravity_damped("0.00113", "[1.0, 0.0, 0.0, 0.0]", "t_end = 60.0\nsamples = 3\n"));
  const run_result r = run(dir.path(), {"reference", "s.toml", "--verify", "--certify", "--out", "ref.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = read_file(dir.path() / "ref.csv");
  const std::size_t at = text.find("\n# error_units: ");
  ASSERT_NE(at, std::string::npos) << text;
  const std::string units = text.substr(at, text.find('\n', at + 1) - at);
  for (const char* figure :
       {"estimated_max_error = normalized Omega (Eq. 20, no unit)", "estimated_max_error_omega = rad/s",
        "estimated_max_attitude_error = rad", "certified_max_error_omega = rad/s", "certified_max_error_q = |q - q*|_2"})
    EXPECT_NE(units.find(figure), std::string::npos) << figure << " in " << units;

  const run_result b = run(dir.path(), {"batch", "s.toml", "--verify", "--out-dir", "b"});
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const nlohmann::json m = nlohmann::json::parse(read_file(dir.path() / "b/manifest.json"));
  const auto& figures = m["scenes"][0]["figures"];
  EXPECT_EQ(figures["estimated_max_error"]["unit"], "normalized Omega (Eq. 20, no unit)");
  EXPECT_EQ(figures["estimated_max_attitude_error"]["unit"], "rad (rotation angle)");
  EXPECT_EQ(figures["estimated_max_error_omega"]["unit"], "rad/s");
  EXPECT_GT(figures["estimated_max_error"]["value"].get<double>(), 0.0);
}

// The value of the header line `# key: value`.
double header_value(const std::string& text, const std::string& key) {
  const std::size_t at = text.find("\n# " + key + ": ");
  EXPECT_NE(at, std::string::npos) << key << " in:\n" << text;
  return at == std::string::npos ? 0.0 : std::stod(text.substr(at + key.size() + 5));
}

// --verify's estimate in rad/s is that of the same comparison: the row of its largest normalized
// difference holds between min and max sqrt(|A_i|) times it in rad/s, and no row exceeds max
// sqrt(|A_i|) times the largest. Each figure is printed to three digits (0.5% either way), and
// the rows' own rounding to quad (1e-34 of |omega|) is far below these 1e-32.
TEST(PhysicalTerms, VerifyEstimatesTheRatesInRadPerSecond) {
  temp_dir dir;
  write_file(dir.path() / "s.toml", gravity_damped("0.00113", "[1.0, 0.0, 0.0, 0.0]", "t_end = 600.0\nsamples = 61\n"));
  const run_result r = run(dir.path(), {"reference", "s.toml", "--verify", "--out", "ref.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = read_file(dir.path() / "ref.csv");
  const double normalized = header_value(text, "estimated_max_error");
  const double rates = header_value(text, "estimated_max_error_omega");
  const scaling_by_hand by_hand;
  const double lo = *std::min_element(by_hand.sqrt_A, by_hand.sqrt_A + 3);
  const double hi = *std::max_element(by_hand.sqrt_A, by_hand.sqrt_A + 3);
  ASSERT_GT(normalized, 0.0);
  EXPECT_GE(rates * 1.005, lo * normalized / 1.005) << rates << " vs " << normalized;
  EXPECT_LE(rates / 1.005, hi * normalized * 1.005) << rates << " vs " << normalized;

  // The direct form's state is omega: the two figures are one. Other forms have no rates.
  write_file(dir.path() / "axi.toml", "name = \"axi\"\n[body]\ninertia = [100.0, 100.0, 200.0]\n"
                                      "[initial]\nomega = [0.02, 0.1, 0.05]\n[span]\nt_end = 60.0\nsamples = 7\n");
  ASSERT_EQ(run(dir.path(), {"reference", "axi.toml", "--verify", "--out", "axi.csv"}).exit_code, 0);
  const std::string axi = read_file(dir.path() / "axi.csv");
  EXPECT_EQ(header_value(axi, "estimated_max_error_omega"), header_value(axi, "estimated_max_error"));
  const run_result paper = run(dir.path(), {"reference", "--tau-end", "2", "--samples", "5", "--verify"});
  ASSERT_EQ(paper.exit_code, 0) << paper.err;
  EXPECT_EQ(paper.out.find("estimated_max_error_omega"), std::string::npos) << paper.out;
  EXPECT_NE(paper.out.find("\n# error_units: estimated_max_error = Eq. 20 (no unit)\n"), std::string::npos);
}

// Every numeric key takes a constant formula: t_end and mean_motion here. The run equals the one
// with the same numbers written as 40-digit decimals (2 pi / 5560 and 6 pi / 0.0113, by mpmath),
// to the reference's own accuracy.
TEST(PhysicalTerms, ANumberIsANumberEverywhere) {
  temp_dir dir;
  write_file(dir.path() / "f.toml",
             gravity_damped("\"2*pi/5560\"", "[1.0, 0.0, 0.0, 0.0]", "t_end = \"6*pi/0.0113\"\nsamples = 5\n"));
  write_file(dir.path() / "d.toml",
             gravity_damped("0.001130069299852443610957785389668885929567327",
                            "[1.0, 0.0, 0.0, 0.0]", "t_end = 1668.102293941483135466890292006815690724161\nsamples = 5\n"));
  const run_result f = run(dir.path(), {"reference", "f.toml", "--out", "f.csv"});
  ASSERT_EQ(f.exit_code, 0) << f.err;
  ASSERT_EQ(run(dir.path(), {"reference", "d.toml", "--out", "d.csv"}).exit_code, 0);
  const auto rf = csv_rows(read_file(dir.path() / "f.csv")), rd = csv_rows(read_file(dir.path() / "d.csv"));
  ASSERT_EQ(rf.size(), 6u);
  ASSERT_EQ(rd.size(), rf.size());
  for (std::size_t i = 1; i < rf.size(); ++i)
    for (std::size_t c = 0; c < 4; ++c)  // t, omega1..3
      EXPECT_NEAR(std::stod(rf[i][c]), std::stod(rd[i][c]), 1e-14 * std::max(1.0, std::abs(std::stod(rd[i][c]))))
          << "row " << i << " column " << c;
  // The elements, the span and [run] step too; "K/N" keeps its meaning.
  write_file(dir.path() / "n.toml", "name = \"n\"\n[initial]\nc1 = \"1/2\"\nc2 = 1.0\nu = \"0.3\"\n[span]\n"
                                    "tau_end = \"pi\"\nsamples = 3\n[run]\nstep = \"pi/400\"\n");
  const run_result n = run(dir.path(), {"report", "n.toml", "--out-dir", "rn", "--no-plot"});
  ASSERT_EQ(n.exit_code, 0) << n.err;
  EXPECT_NE(n.out.find("400 steps to tau = 3.14159"), std::string::npos) << n.out;
  // A formula that is no number names the key.
  write_file(dir.path() / "bad.toml",
             gravity_damped("\"fast\"", "[1.0, 0.0, 0.0, 0.0]", "t_end = 60.0\nsamples = 3\n"));
  expect_one_line_error(run(dir.path(), {"reference", "bad.toml"}),
                        "[torque.gravity_gradient] mean_motion = \"fast\": unknown identifier `fast`");
  write_file(dir.path() / "neg.toml",
             gravity_damped("0.00113", "[1.0, 0.0, 0.0, 0.0]", "t_end = \"-6*pi\"\nsamples = 3\n"));
  expect_one_line_error(run(dir.path(), {"reference", "neg.toml"}), "[span] t_end = \"-6*pi\": must be positive");
}

// A quaternion rounded to six digits is normalized, with a note giving its norm; one further off
// is an error giving its norm. The printed q(0) is the unit quaternion (1/sqrt(2), 0, 0, 1/sqrt(2))
// to quad's digits (its exact value, as 0.707107 = 0.707107).
TEST(PhysicalTerms, AQuaternionRoundedToSixDigitsIsNormalized) {
  temp_dir dir;
  write_file(dir.path() / "q.toml",
             gravity_damped("0.00113", "[0.707107, 0.0, 0.0, 0.707107]", "t_end = 60.0\nsamples = 3\n"));
  const run_result r = run(dir.path(), {"reference", "q.toml", "--out", "ref.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("[initial] q: its norm is 1.000000309; it is divided by it"), std::string::npos) << r.err;
  const auto rows = csv_rows(read_file(dir.path() / "ref.csv"));
  ASSERT_GE(rows.size(), 2u);
  EXPECT_EQ(rows[1][4].substr(0, 33), "7.0710678118654752440084436210484") << "q0 at t = 0";
  EXPECT_EQ(rows[1][7].substr(0, 33), "7.0710678118654752440084436210484") << "q3 at t = 0";
  write_file(dir.path() / "far.toml",
             gravity_damped("0.00113", "[0.70711, 0.0, 0.0, 0.7071]", "t_end = 60.0\nsamples = 3\n"));
  expect_one_line_error(run(dir.path(), {"reference", "far.toml"}),
                        "[initial] q = [0.70711, 0.0, 0.0, 0.7071]: its norm is 0.999997481");
  const run_result far = run(dir.path(), {"reference", "far.toml"});
  EXPECT_NE(far.err.find("not 1 (to 1e-6)"), std::string::npos) << far.err;
}

// sweep and map on a scene whose torque reads the attitude: every run carries q, and its attitude
// error stands beside the rates'. The last sample of a fixed-step run lies at the same tau in
// `report` and in `sweep` (n h), so their final attitude errors are the same figure, reached by
// two different reference paths (report's at its samples, sweep's at every run's).
TEST(PhysicalTerms, SweepAndMapGiveTheAttitudeError) {
  temp_dir dir;
  write_file(dir.path() / "s.toml", gravity_damped("0.00113", "[1.0, 0.0, 0.0, 0.0]", "t_end = 300.0\nsamples = 3\n"));
  const run_result sw = run(dir.path(), {"sweep", "s.toml", "--steps", "K/50,K/200", "--tols", "1e-8", "--methods",
                                         "rk4,dop853", "--out-dir", "sw", "--no-plot"});
  ASSERT_EQ(sw.exit_code, 0) << sw.err;
  EXPECT_NE(sw.out.find("max att err"), std::string::npos) << sw.out;
  const auto rows = csv_rows(read_file(dir.path() / "sw/sweep.csv"));
  ASSERT_GT(rows.size(), 1u);
  const auto& h = rows[0];
  const std::size_t col = static_cast<std::size_t>(std::find(h.begin(), h.end(), "final_attitude_error") - h.begin());
  ASSERT_LT(col, h.size());
  std::optional<double> sweep_final;
  for (const auto& r : rows)
    if (r[0] == "euler" && r[1] == "rk4" && r[2] == "K/200") sweep_final = std::stod(r[col]);
  ASSERT_TRUE(sweep_final);
  const run_result rp = run(dir.path(), {"report", "s.toml", "--step", "K/200", "--methods", "rk4", "--formulations",
                                         "euler", "--out-dir", "rp", "--no-plot"});
  ASSERT_EQ(rp.exit_code, 0) << rp.err;
  const nlohmann::json j = nlohmann::json::parse(read_file(dir.path() / "rp/summary.json"));
  const double report_final = j["runs"][0]["final_attitude_error"].get<double>();
  EXPECT_GT(report_final, 0.0);
  EXPECT_NEAR(*sweep_final, report_final, 1e-9 * report_final);

  const run_result mp = run(dir.path(), {"map", "s.toml", "--torque-scales", "1", "--steps", "K/50,K/200", "--tols",
                                         "1e-8", "--levels", "1e-6", "--out-dir", "mp", "--no-plot"});
  ASSERT_EQ(mp.exit_code, 0) << mp.err;
  EXPECT_NE(read_file(dir.path() / "mp/runs.csv").find(",max_attitude_error,final_attitude_error,"),
            std::string::npos);
}

}  // namespace
