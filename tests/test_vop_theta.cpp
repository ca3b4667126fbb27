// Beyond the paper's VOP (docs/vop-strategies.md): the secular-free elements (c1, c2, theta), the
// minor-axis regime (k > 1, reciprocal modulus), the Omega3 < 0 and Omega1 < 0 symmetries, and
// the direct-Euler fallback across the separatrix and near c1 = 0 (runs/detail/vop_run_state.hpp).
#include <eulervop/reference/integrate.hpp>
#include <eulervop/runs/comparison_run.hpp>
#include <eulervop/model/error_measure.hpp>
#include <eulervop/core/outcome_text.hpp>
#include <eulervop/vop/frame.hpp>
#include <eulervop/vop/vop_system.hpp>
#include <eulervop/vop/vop_theta_system.hpp>

#include "vop_test_support.hpp"

#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace {

using eulervop::formulation;
using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;

// Random states in both regimes and all four frames (vop_test::random_regime_states).
std::vector<vec3<quad>> random_states(int n, bool minor) {
  return vop_test::random_regime_states(n, minor, minor ? 977 : 20261123, 5.0);
}

// The theta equation (docs/vop-strategies.md section 1, derived in vop/vop_theta_system.hpp:
// Eq. 16 with E(u) - kc^2 u -> Z(u), times pi/(2K)) is the exact image of Eq. 5, in both regimes
// and all four frames.
TEST(VopThetaRhs, IsEulersEquationsInElements) {
  const vec3<quad> G = {quad(1), quad("-0.7"), quad("0.3")};
  for (bool minor : {false, true}) {
    double worst = 0;
    for (const auto& Om : random_states(100, minor)) {
      const auto frame = eulervop::vop_frame<quad>::for_state(Om);
      ASSERT_EQ(frame.minor_axis(), minor);
      const vec3<quad> y = frame.theta_elements_of(Om);
      ASSERT_TRUE(y[2] >= -boost::math::constants::pi<quad>() && y[2] < boost::math::constants::pi<quad>());
      // The conversion round-trips.
      const auto back = frame.Omega_of_theta(y);
      for (int i = 0; i < 3; ++i) ASSERT_LE(static_cast<double>(fabs(back[i] - Om[i])), 1e-30);
      eulervop::vop_theta_system<quad> sys(frame.rotate(G));
      worst = std::max(worst, vop_test::chain_rule_mismatch(y, sys, [&](const vec3<quad>& e) { return frame.Omega_of_theta(e); }, G));
    }
    EXPECT_LE(worst, 1e-15) << (minor ? "k > 1" : "k < 1");
  }
}

// The paper's (c1, c2, u) equations in the minor-axis regime: Eqs. 13 and 16 in the W frame
// (c1 <-> c2, G1 <-> G3, modulus 1/k), with u pushed out so the secular term is large.
TEST(VopMinorAxisRhs, IsEulersEquationsInElements) {
  const vec3<quad> G = {quad("0.4"), quad("-0.7"), quad("1.1")};
  double worst = 0;
  for (const auto& Om : random_states(200, true)) {
    const auto frame = eulervop::vop_frame<quad>::for_state(Om);
    ASSERT_TRUE(frame.minor_axis());
    vec3<quad> y = frame.elements_of(Om);
    const auto back = frame.Omega_of(y);
    for (int i = 0; i < 3; ++i) ASSERT_LE(static_cast<double>(fabs(back[i] - Om[i])), 1e-30);
    y[2] += quad(37);
    eulervop::vop_system<quad> sys(frame.rotate(G));
    worst = std::max(worst, vop_test::chain_rule_mismatch(y, sys, [&](const vec3<quad>& e) { return frame.Omega_of(e); }, G));
  }
  // The difference step is 1e-9 dy, and dy[2] reaches ~1e4 here (d1 down to 0.01 with the
  // secular term at u + 37): truncation up to ~1e-13 (measured 2.3e-14). A wrong term is O(1).
  EXPECT_LE(worst, 1e-12);
}

// The rotation by pi about axis 3, (Omega1, Omega2, G1, G2) -> -(...), is a symmetry of Eq. 5
// (and so is the one about axis 1, used for Omega3 < 0); the reflection of Omega1 alone is not.
TEST(VopSymmetry, RotationsByPiAboutPrincipalAxesAreSymmetries) {
  const vec3<double> Om = {0.3, -1.2, 0.7}, G = {0.2, 0.5, -0.9};
  vec3<double> f, g;
  eulervop::euler_rhs(Om, G, f);
  eulervop::euler_rhs(vec3<double>{-Om[0], -Om[1], Om[2]}, vec3<double>{-G[0], -G[1], G[2]}, g);
  EXPECT_EQ(g[0], -f[0]);
  EXPECT_EQ(g[1], -f[1]);
  EXPECT_EQ(g[2], f[2]);
  eulervop::euler_rhs(vec3<double>{-Om[0], Om[1], Om[2]}, vec3<double>{-G[0], G[1], G[2]}, g);
  EXPECT_NE(g[1], f[1]);  // Omega2' = Omega1 Omega3 + G2 changes sign only in part
}

// Torque-free VOP is exact to rounding in every regime: error <= 1e-13 at tau = 1000 for any
// step and method, against Boost.Math jacobi_elliptic in MPFR at 200 bits.
// The free phase rate is 1 in each case (c2 = 1 for k < 1, c1 = 1 for k > 1), so the phase's
// own ulp (1.1e-13 at 1000) is the bound for the paper's u.
struct free_case {
  const char* name;
  vec3<double> Omega0;
};

vec3<mpfr_real> exact_free(const vec3<double>& O0, double tau) {
  const mpfr_real c1 = hypot(mpfr_real(O0[0]), mpfr_real(O0[1]));
  const mpfr_real c2 = hypot(mpfr_real(O0[1]), mpfr_real(O0[2]));
  mpfr_real cn, dn;
  if (c1 < c2) {  // Omega2(0) = 0 in these cases: u(0) = 0
    const mpfr_real k = c1 / c2, s = O0[2] > 0 ? 1 : -1;
    const mpfr_real sn = boost::math::jacobi_elliptic(k, c2 * mpfr_real(tau), &cn, &dn);
    return {c1 * cn, s * c1 * sn, s * c2 * sqrt(1 - k * k * sn * sn)};
  }
  const mpfr_real l = c2 / c1, s = O0[0] > 0 ? 1 : -1;
  const mpfr_real sn = boost::math::jacobi_elliptic(l, c1 * mpfr_real(tau), &cn, &dn);
  return {s * c1 * sqrt(1 - l * l * sn * sn), s * c2 * sn, c2 * cn};
}

TEST(VopRegimes, TorqueFreeExactToRoundingInEveryRegime) {
  const free_case cases[] = {{"k<1, Omega3>0", {0.5, 0, 1}},
                             {"k<1, Omega3<0", {0.5, 0, -1}},
                             {"k>1, Omega1>0", {1, 0, 0.5}},
                             {"k>1, Omega1<0", {-1, 0, 0.5}}};
  double worst = 0;
  for (formulation f : {formulation::vop, formulation::vop_theta})
    for (const auto& c : cases) {
      eulervop::euler_problem<double> p;
      p.torque.G = {0, 0, 0};
      p.Omega0 = c.Omega0;
      for (double h : {0.01, 0.125, 1.0, 7.0}) {
        eulervop::fixed_run_settings s;
        s.h = h;
        s.n_steps = static_cast<std::size_t>(std::llround(1000.0 / h));
        s.sample_every = s.n_steps;
        const double tau = h * static_cast<double>(s.n_steps);
        eulervop::mpfr_precision_scope scope(200);
        const vec3<mpfr_real> exact = exact_free(c.Omega0, tau);
        for (auto m : eulervop::rk::fixed_step_methods) {
          const auto r = eulervop::run_fixed(f, m, p, s);
          ASSERT_FALSE(r.diverged());
          EXPECT_TRUE(r.separatrix_bands.empty() && r.small_k_bands.empty() && r.direct_steps == 0);
          const double err = static_cast<double>(eulervop::eq20_error(exact, r.Omega.back()));
          worst = std::max(worst, err);
          EXPECT_LE(err, 1e-13) << eulervop::formulation_name(f) << " " << c.name << " h=" << h
                                << " method=" << eulervop::rk::method_name(m);
        }
      }
    }
  std::printf("torque-free, tau = 1000, all regimes, steps and methods: worst error %.3e\n", worst);
}

// The minor-axis regime under torque matches its mirror image bit for bit (Omega1 < 0 symmetry).
TEST(VopRegimes, NegativeOmega1MirrorsThePositiveCase) {
  eulervop::euler_problem<double> p, q;
  p.torque.G = {0.1, 0.2, -0.1};
  p.Omega0 = {1, 0.1, 0.5};
  q.torque.G = {-0.1, -0.2, -0.1};
  q.Omega0 = {-1, -0.1, 0.5};
  eulervop::fixed_run_settings s{0.01, 500, 50};
  for (formulation f : {formulation::vop, formulation::vop_theta}) {
    const auto a = eulervop::run_fixed(f, eulervop::rk::method::rk4, p, s);
    const auto b = eulervop::run_fixed(f, eulervop::rk::method::rk4, q, s);
    ASSERT_EQ(a.Omega.size(), b.Omega.size());
    for (std::size_t i = 0; i < a.Omega.size(); ++i) {
      EXPECT_EQ(a.Omega[i][0], -b.Omega[i][0]);
      EXPECT_EQ(a.Omega[i][1], -b.Omega[i][1]);
      EXPECT_EQ(a.Omega[i][2], b.Omega[i][2]);
    }
  }
}

// The max Eq. 20 error of a run against a quad reference.
double max_error(const eulervop::run_result& r, const eulervop::dense_trajectory<quad>& ref, double h) {
  double worst = 0;
  for (std::size_t i = 0; i < r.Omega.size(); ++i) {
    for (double v : r.Omega[i]) EXPECT_TRUE(std::isfinite(v));
    worst = std::max(worst, static_cast<double>(eulervop::eq20_error(
                                ref(quad(h) * quad(r.sample_steps[i])), r.Omega[i])));
  }
  return worst;
}

eulervop::euler_problem<quad> to_quad(const eulervop::euler_problem<double>& p) {
  eulervop::euler_problem<quad> q;
  for (int i = 0; i < 3; ++i) {
    q.torque.G[i] = p.torque.G[i];
    q.Omega0[i] = p.Omega0[i];
  }
  return q;
}

// Crossing scene (docs/vop-strategies.md section 4): from the paper's Omega(0) = (0.5, 0, 1)
// (k = 0.5), the constant torque G = (-0.05, 0, -0.05) drains c2 (G3 against Omega3 = c2 dn > 0)
// until k passes 1 near tau = 14.7; the state ends near the minor axis (k ~ 5). Every
// formulation completes without NaN, the VOP runs record the band and one regime change, and
// their max error is within 10x Euler's at the same step h = K(0.5)/200.
TEST(VopCrossing, CarriesKAcrossOneAndRecordsTheBand) {
  eulervop::euler_problem<double> p;
  p.torque.G = {-0.05, 0, -0.05};
  p.Omega0 = {0.5, 0, 1};
  const double h = eulervop::elliptic_modulus<double>(0.5).K() / 200;
  const std::size_t n = static_cast<std::size_t>(40 / h);
  const auto ref = eulervop::integrate_reference<quad>(to_quad(p), quad(h) * quad(n));
  for (auto m : {eulervop::rk::method::rk4, eulervop::rk::method::rk8}) {
    eulervop::fixed_run_settings s{h, n, 5};
    const auto e = eulervop::run_fixed(formulation::euler, m, p, s);
    ASSERT_FALSE(e.diverged());
    const double e_max = max_error(e, ref, h);
    for (formulation f : {formulation::vop, formulation::vop_theta}) {
      const auto r = eulervop::run_fixed(f, m, p, s);
      ASSERT_FALSE(r.diverged()) << eulervop::describe(r.status);
      ASSERT_EQ(r.steps, n);
      ASSERT_FALSE(r.separatrix_bands.empty());
      const auto band = r.separatrix_bands.front();
      EXPECT_LT(band.first, band.second);
      EXPECT_GE(r.regime_changes, 1u);
      const double v_max = max_error(r, ref, h);
      std::printf("crossing %s %s: band [%.4f, %.4f] (%zu direct steps, %zu regime changes), max error %.3e vs euler %.3e\n",
                  std::string(eulervop::formulation_name(f)).c_str(),
                  std::string(eulervop::rk::method_name(m)).c_str(), band.first, band.second,
                  r.direct_steps, r.regime_changes, v_max, e_max);
      EXPECT_LE(v_max, 10 * e_max);
    }
  }
}

// c1 = 0 exactly: without torque the VOP forms are exact (u' = c2, no division); with a torque
// the run starts in the small-k fallback, records it, and stays within 10x of Euler.
TEST(VopSmallK, ExactZeroC1) {
  eulervop::euler_problem<double> p;
  p.Omega0 = {0, 0, 1};
  eulervop::fixed_run_settings s{0.01, 2000, 100};
  for (formulation f : {formulation::vop, formulation::vop_theta}) {
    const auto r = eulervop::run_fixed(f, eulervop::rk::method::rk4, p, s);
    ASSERT_FALSE(r.diverged());
    EXPECT_EQ(r.direct_steps, 0u);
    for (const auto& O : r.Omega) {
      EXPECT_EQ(O[0], 0);
      EXPECT_EQ(O[1], 0);
      EXPECT_EQ(O[2], 1);
    }
  }
  p.torque.G = {0.01, 0.01, 0};
  const auto ref = eulervop::integrate_reference<quad>(to_quad(p), quad(s.h) * quad(s.n_steps));
  const auto e = eulervop::run_fixed(formulation::euler, eulervop::rk::method::rk4, p, s);
  const double e_max = max_error(e, ref, s.h);
  for (formulation f : {formulation::vop, formulation::vop_theta}) {
    const auto r = eulervop::run_fixed(f, eulervop::rk::method::rk4, p, s);
    ASSERT_FALSE(r.diverged()) << eulervop::describe(r.status);
    ASSERT_FALSE(r.small_k_bands.empty());
    EXPECT_EQ(r.small_k_bands.front().first, 0.0);
    const double v_max = max_error(r, ref, s.h);
    std::printf("c1 = 0, G = (0.01, 0.01, 0) %s: %zu small-k bands, first [%.3f, %.3f], max error %.3e vs euler %.3e\n",
                std::string(eulervop::formulation_name(f)).c_str(), r.small_k_bands.size(),
                r.small_k_bands.front().first, r.small_k_bands.front().second, v_max, e_max);
    EXPECT_LE(v_max, 10 * e_max);
  }
}

// No NaN anywhere: hard starting states, every formulation and method, short spans. A run either
// completes or stops with diverged and a reason; sampled states are always finite.
TEST(VopHardStates, NeverProduceNaN) {
  struct hard {
    const char* name;
    vec3<double> Omega0, G;
  };
  const double kk = 1 - 1e-6;
  const hard cases[] = {
      {"k = 1 - 1e-6, torque-free", {kk, 0, 1}, {0, 0, 0}},
      {"k = 1 - 1e-6, small torque", {kk, 0, 1}, {1e-3, -2e-3, 1e-3}},
      {"on the separatrix, c1 = c2", {0, 1, 0}, {1e-3, 0, 1e-3}},
      {"saddle, torque-free", {0, 1, 0}, {0, 0, 0}},
      {"c1/c2 = 1e-6", {1e-6, 0, 1}, {0.01, 0.02, 0}},
      {"k = 1 + 1e-6", {1 + 1e-6, 0, 1}, {0, 0, 1e-3}},
      {"Omega = 0 with torque", {0, 0, 0}, {0.1, 0.1, 0.1}},
      {"k > 1, Omega1 < 0", {-1, 0.2, 0.5}, {0.3, 0, 0.1}},
      {"paper scene", {0.5, 0, 1}, {1, 1, 1}},
  };
  for (const auto& c : cases)
    for (formulation f : eulervop::all_formulations)
      for (auto m : eulervop::rk::fixed_step_methods) {
        eulervop::euler_problem<double> p;
        p.Omega0 = c.Omega0;
        p.torque.G = c.G;
        const auto r = eulervop::run_fixed(f, m, p, eulervop::fixed_run_settings{0.01, 1000, 10});
        EXPECT_FALSE(r.diverged()) << c.name << " " << eulervop::formulation_name(f) << ": "
                                   << eulervop::describe(r.status);
        for (const auto& O : r.Omega)
          for (double v : O) ASSERT_TRUE(std::isfinite(v)) << c.name << " " << eulervop::formulation_name(f);
      }
}

}  // namespace
