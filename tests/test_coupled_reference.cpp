// The reference of a body whose torque reads its attitude (model/coupled_problem.hpp): the rates
// and q as one problem of 7 states, against independent oracles.
//
// Truth:
//   - tests/data/coupled_oracles/*.csv: Taylor-series integrations of the same equations in
//     mpmath (tools/oracles/coupled_taylor.py, written apart from the C++ code, with R(q) and the
//     gravity gradient as the file header states), at 45 and 70 digits (gg_alone also at 100 and
//     120), agreeing to 2e-43 relative or better; the stored values carry 45 significant digits
//     (72 for gg_alone).
//   - the libration: the planar pitch motion of the shipped scene is exactly a pendulum in
//     2 theta (docs/attitude.md), whose period is 4 K(sin theta0) / omega_p (Boost.Math's
//     complete elliptic integral, evaluated in quad); and to order theta0^2 the linear theory's
//     2 pi / omega_p.
// Bounds:
//   - the libration period against the pendulum's: 1e-30 relative (derived at the check).
//   - quad against the oracles, every checked time to 6000 s: 1e-29 on omega (rad/s) and q. The
//     run holds each segment to eps = 1.9e-34 relative, and the rounding of a few hundred
//     segments and the phase it moves stay near 1e-32 (measured below 5e-33 on every case);
//     1e-29 is the bar users are promised.
//   - mpfr:256 on gg_alone: 1e-60 (eps 8.6e-78; the 72-digit oracle is good to 1e-70).
//   - |q| within 1e-31 of 1 at the nodes, in quad (measured 4.3e-33 on the libration).
#include "compute/reference_compute.hpp"

#include <eulervop/core/scalar.hpp>
#include <eulervop/reference/integrate.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <boost/math/special_functions/ellint_1.hpp>
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace sc = eulervop::scene;
using eulervop::mpfr_real;
using eulervop::quad;

const std::string source_dir = EULERVOP_SOURCE_DIR;

// The rows of an oracle file: t, then omega1..3 and q0..q3, as text.
std::vector<std::vector<std::string>> oracle_rows(const std::string& name) {
  std::ifstream in(source_dir + "/tests/data/coupled_oracles/" + name + ".csv");
  EXPECT_TRUE(in) << name;
  std::vector<std::vector<std::string>> rows;
  bool header = false;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      EXPECT_EQ(line, "t,omega1,omega2,omega3,q0,q1,q2,q3");
      header = true;
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string c; std::getline(s, c, ',');) cells.push_back(c);
    EXPECT_EQ(cells.size(), 8u) << line;
    rows.push_back(cells);
  }
  return rows;
}

// The scene of an oracle case (the parameters of tools/oracles/coupled_taylor.py), sampled at the
// oracle's times.
std::string case_scene(const std::string& name) {
  struct spec {
    const char *inertia, *torque, *omega, *q;
    bool gravity;
  };
  const std::map<std::string, spec> cases = {
      {"gg_alone", {"[100, 150, 220]", "", "[0.0005, -0.0003, 0.0013]", "[0.7, 0.1, 0.1, 0.7]", true}},
      {"gg_unordered", {"[220, 100, 150]", "", "[0.0004, 0.0012, -0.0006]", "[0.5, 0.5, 0.5, 0.5]", true}},
      {"pd_law",
       {"[100, 150, 120]", R"(M = ["-2*q1 - 40*omega1", "-2*q2 - 40*omega2", "-2*q3 - 40*omega3"])",
        "[0.01, -0.02, 0.005]", "[0.5, 0.5, -0.5, 0.5]", false}},
      {"gg_damped",
       {"[150, 90, 120]", R"(M = ["0.00001 - 0.05*omega1", "-0.00002 - 0.05*omega2", "0.000005 - 0.05*omega3"])",
        "[0.002, 0.001, -0.0015]", "[0.1, 0.7, 0.7, 0.1]", true}},
  };
  const spec& c = cases.at(name);
  std::string text = "name = \"" + name + "\"\n[body]\ninertia = " + c.inertia + "\n[torque]\n" + c.torque + "\n";
  if (c.gravity) text += "[torque.gravity_gradient]\nmean_motion = 0.0011\n";
  text += std::string("[initial]\nomega = ") + c.omega + "\nq = " + c.q + "\n";
  text += "[span]\nt_end = 6000\ntimes = [";
  for (int k = 0; k <= 10; ++k) text += (k ? ", " : "") + std::to_string(600 * k);
  return text + "]\n";
}

// The largest |ours - oracle| over every row and the seven columns, ours computed in T by the
// program's own path (integrate_scene_attitude), omega in rad/s in the listed axes.
template <class T>
double worst_against_oracle(const sc::scene& s, const std::vector<std::vector<std::string>>& oracle) {
  const sc::sample_times<T> times = sc::sample_times_of<T>(s);
  EXPECT_EQ(times.t.size(), oracle.size());
  const auto scale = sc::scaling_of<T>(s);
  const bool direct = sc::uses_direct_form(s);
  double worst = 0;
  eulervop::app::integrate_scene_attitude<T>(
      s, sc::tau_end_of<T>(s), times.tau, {}, "",
      [&](std::size_t i, const eulervop::vec3<T>& y, const eulervop::quaternion<T>& q) {
        const eulervop::vec3<T> omega = direct ? y : scale.omega_of_Omega(y);
        const T ours[7] = {omega[0], omega[1], omega[2], q.w, q.x, q.y, q.z};
        for (int c = 0; c < 7; ++c) {
          using std::abs;
          const T truth = *eulervop::from_text<T>(oracle[i][1 + c]);
          worst = std::max(worst, static_cast<double>(abs(ours[c] - truth)));
        }
      });
  return worst;
}

class Oracle : public ::testing::TestWithParam<std::string> {};

TEST_P(Oracle, QuadWithin1e29EveryCheckedTime) {
  const sc::scene s = sc::parse_scene(case_scene(GetParam()), GetParam());
  ASSERT_TRUE(s.couples_attitude());
  const double worst = worst_against_oracle<quad>(s, oracle_rows(GetParam()));
  std::cout << GetParam() << ": quad worst |error| " << worst << "\n";
  EXPECT_LE(worst, 1e-29);
}

INSTANTIATE_TEST_SUITE_P(Cases, Oracle, ::testing::Values("gg_alone", "gg_unordered", "pd_law", "gg_damped"),
                         [](const auto& info) { return info.param; });

TEST(CoupledReference, Mpfr256Within1e60OfTheSeventyTwoDigitOracle) {
  const eulervop::mpfr_precision_scope scope(256);
  const sc::scene s = sc::parse_scene(case_scene("gg_alone"), "gg_alone");
  const double worst = worst_against_oracle<mpfr_real>(s, oracle_rows("gg_alone"));
  std::cout << "gg_alone: mpfr:256 worst |error| " << worst << "\n";
  EXPECT_LE(worst, 1e-60);
}

// The shipped libration scene against its oracle (the same scene, q(0) from the formula, to
// 4000 s), and its period against the pendulum's.
TEST(Libration, PeriodIsThePendulumsAndTheLinearTheorysToOrderAmplitudeSquared) {
  const sc::scene s = sc::load_scene_file(source_dir + "/data/scenes/attitude/gravity-gradient-libration.toml");
  ASSERT_TRUE(s.couples_attitude());
  const eulervop::coupled_problem<quad> p = sc::to_coupled_problem<quad>(s);
  eulervop::coupled_stats stats;
  const quad tau_end = sc::tau_end_of<quad>(s);
  const auto trajectory = eulervop::integrate_coupled(p, tau_end, {}, nullptr, &stats);
  EXPECT_LE(stats.norm_drift, 1e-31);
  std::cout << "libration: max | |q| - 1 | = " << stats.norm_drift << "\n";

  const auto scale = sc::scaling_of<quad>(s);
  const quad n = quad("0.0011");
  const quad pi = eulervop::pi_in<quad>();
  // theta(t): the pitch from the orbit frame, 2 atan2(q3, q0) - n t reduced to (-pi, pi]; the
  // motion stays planar.
  const auto theta = [&](const quad& t) {
    const auto v = trajectory(scale.tau_of_t(t));
    using std::atan2;
    using std::round;
    EXPECT_EQ(v[4], 0);
    EXPECT_EQ(v[5], 0);
    const quad d = 2 * atan2(v[6], v[3]) - n * t;
    return quad(d - 2 * pi * round(d / (2 * pi)));
  };
  // The downward zero crossings of theta, by bisection on the dense output.
  std::vector<quad> crossings;
  const quad t_end = scale.t_of_tau(tau_end);
  for (quad a = 0; a + 10 <= t_end; a += 10) {
    quad lo = a, hi = a + 10;
    if (!(theta(lo) > 0 && theta(hi) <= 0)) continue;
    for (int it = 0; it < 120; ++it) {
      const quad mid = (lo + hi) / 2;
      (theta(mid) > 0 ? lo : hi) = mid;
    }
    crossings.push_back(lo);
  }
  ASSERT_GE(crossings.size(), 5u);
  const quad period = (crossings.back() - crossings.front()) / quad(crossings.size() - 1);

  using std::sqrt;
  const quad theta0 = pi / 36;
  const quad omega_p = n * sqrt(3 * (quad(12250) - quad(500)) / quad(12250));
  const quad linear = 2 * pi / omega_p;
  const quad pendulum = 4 * boost::math::ellint_1(sin(theta0)) / omega_p;
  const double rel_linear = static_cast<double>(period / linear - 1);
  const double theta0_2 = static_cast<double>(theta0 * theta0);
  std::cout << "libration period " << period << " s; linear " << linear << " s; pendulum " << pendulum
            << " s; (period / linear - 1) / theta0^2 = " << rel_linear / theta0_2 << "\n";
  // To order theta0^2 (the pendulum's 1 + theta0^2 / 4 + ...): the correction is seen, and bounded.
  EXPECT_GT(rel_linear, theta0_2 / 8);
  EXPECT_LT(rel_linear, theta0_2 / 2);
  // The closed form. A crossing's time errs by the reference's error in theta (about 1e-32 rad)
  // over theta' there (omega_p theta0 = 1.6e-4 rad/s): 6e-29 s, 2e-32 of a period; the bisection
  // adds 10 s 2^-120. Bound 1e-30, a margin of 50 (measured 7.7e-34).
  const double rel_pendulum = static_cast<double>(abs(period / pendulum - 1));
  std::cout << "libration: |period / pendulum - 1| = " << rel_pendulum << "\n";
  EXPECT_LE(rel_pendulum, 1e-30);

  // The scene's reference against the mpmath oracle of the same scene.
  const auto oracle = oracle_rows("libration");
  double worst = 0;
  for (const auto& row : oracle) {
    const quad t = *eulervop::from_text<quad>(row[0]);
    const auto v = trajectory(scale.tau_of_t(t));
    const eulervop::vec3<quad> omega = sc::uses_direct_form(s) ? eulervop::vec3<quad>{v[0], v[1], v[2]}
                                                              : scale.omega_of_Omega({v[0], v[1], v[2]});
    const quad ours[7] = {omega[0], omega[1], omega[2], v[3], v[4], v[5], v[6]};
    for (int c = 0; c < 7; ++c)
      worst = std::max(worst, static_cast<double>(abs(ours[c] - *eulervop::from_text<quad>(row[1 + c]))));
  }
  std::cout << "libration: worst |error| against the oracle " << worst << "\n";
  EXPECT_LE(worst, 1e-29);
}

}  // namespace
