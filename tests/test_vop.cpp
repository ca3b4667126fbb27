// The paper's VOP formulation (Eqs. 12-16): element conversions, the right-hand side against
// Euler's equations, torque-free exactness, the Omega3 < 0 symmetry, and the paper scene in quad.
#include <eulervop/reference/integrate.hpp>
#include <eulervop/runs/comparison_run.hpp>
#include <eulervop/model/error_measure.hpp>
#include <eulervop/rk/fixed_step.hpp>
#include <eulervop/vop/frame.hpp>
#include <eulervop/vop/vop_system.hpp>

#include "type_test_names.hpp"
#include "vop_test_support.hpp"

#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;

template <class T>
class VopTyped : public ::testing::Test {};
using Types = ::testing::Types<double, quad>;
TYPED_TEST_SUITE(VopTyped, Types, scalar_test_names);

// Random states with 0.05 <= k <= 0.95, both signs of Omega3.
template <class T>
std::vector<vec3<T>> random_states(int n) {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> ang(-3.14159, 3.14159), kk(0.05, 0.95), c2d(0.2, 5.0);
  std::vector<vec3<T>> out;
  for (int i = 0; i < n; ++i) {
    // Build from (c1, c2, am) so that k is controlled: Omega = (c1 cos am, c1 sin am, s sqrt(c2^2 - Omega2^2)).
    const T c2 = T(c2d(rng)), k = T(kk(rng)), am = T(ang(rng));
    using std::cos;
    using std::sin;
    using std::sqrt;
    const T c1 = k * c2;
    const T O2 = c1 * sin(am);
    const T sign = (i % 2) ? T(-1) : T(1);
    out.push_back({c1 * cos(am), O2, sign * sqrt(c2 * c2 - O2 * O2)});
  }
  return out;
}

// Omega -> (c1, c2, u) -> Omega reproduces the state (Eqs. 7, 11, 12).
TYPED_TEST(VopTyped, ElementsRoundTrip) {
  using T = TypeParam;
  T worst = 0;
  for (const auto& Om : random_states<T>(500)) {
    const auto frame = eulervop::vop_frame<T>::of(Om);
    const auto back = frame.Omega_of(frame.elements_of(Om));
    for (int i = 0; i < 3; ++i) {
      using std::abs;
      worst = std::max<T>(worst, abs(back[i] - Om[i]) / (abs(Om[0]) + abs(Om[1]) + abs(Om[2])));
    }
  }
  // A handful of roundings through hypot, atan2, the Landen sequence and back: measured
  // <= 6 eps for both types; 32 eps leaves room and still catches any formula error.
  EXPECT_LE(worst, 32 * std::numeric_limits<T>::epsilon());
}

// Eqs. 13 and 16 are the exact image of Eq. 5: d/dtau Omega(c1, c2, u) along the VOP right-hand
// side equals f(Omega) + G. The derivative of the map y -> Omega is taken by a central difference
// in quad (step 1e-9: truncation ~1e-18 |Omega'''|, rounding ~1e-34/1e-9 = 1e-25), so any wrong
// term of Eq. 16 (including the secular E(u) - kc^2 u) shows as an O(1) mismatch.
TEST(VopRhs, IsEulersEquationsInElements) {
  const vec3<quad> G = {quad(1), quad("-0.7"), quad("0.3")};
  double worst = 0;
  for (const auto& Om : random_states<quad>(200)) {
    const auto frame = eulervop::vop_frame<quad>::of(Om);
    vec3<quad> y = frame.elements_of(Om);
    // Push u several periods out so that the secular term E(u) - kc^2 u is large.
    y[2] += quad(37);
    eulervop::vop_system<quad> sys(frame.rotate(G));
    worst = std::max(worst, vop_test::chain_rule_mismatch(
                                y, sys, [&](const vec3<quad>& e) { return frame.Omega_of(e); }, G));
  }
  EXPECT_LE(worst, 1e-15);
}

// Torque-free VOP is exact to rounding: c1, c2 stay put and u = u0 + c2 tau (the bound: Omega
// error <= 1e-13 at tau = 1000 for any step). Exact Omega from Boost.Math's
// jacobi_elliptic in MPFR at 200 bits (dn as sqrt(1 - k^2 sn^2), docs/design.md section 2).
TEST(VopTorqueFree, ExactToRoundingForAnyStep) {
  // c2 = 1 keeps u = c2 tau <= 1001 where ulp(u) = 1.1e-13: a larger c2 would make the rounding
  // of u itself exceed the 1e-13 bound.
  const double c1 = 0.5, c2 = 1.0;
  eulervop::euler_problem<double> p;
  p.torque.G = {0, 0, 0};
  p.Omega0 = {c1, 0, c2};
  for (double h : {0.01, 0.125, 1.0, 7.0}) {
    eulervop::fixed_run_settings s;
    s.h = h;
    s.n_steps = static_cast<std::size_t>(std::llround(1000.0 / h));
    s.sample_every = s.n_steps;
    for (auto m : eulervop::rk::fixed_step_methods) {
      const auto r = eulervop::run_fixed(eulervop::formulation::vop, m, p, s);
      ASSERT_FALSE(r.diverged());
      const double tau = h * static_cast<double>(s.n_steps);
      eulervop::mpfr_precision_scope scope(200);
      const mpfr_real k = mpfr_real(c1) / mpfr_real(c2), u = mpfr_real(c2) * mpfr_real(tau);
      mpfr_real cn, dn;
      const mpfr_real sn = boost::math::jacobi_elliptic(k, u, &cn, &dn);
      const vec3<mpfr_real> exact = {mpfr_real(c1) * cn, mpfr_real(c1) * sn,
                                     mpfr_real(c2) * sqrt(1 - k * k * sn * sn)};
      const double err = static_cast<double>(eulervop::eq20_error(exact, r.Omega.back()));
      EXPECT_LE(err, 1e-13) << "h=" << h << " method=" << eulervop::rk::method_name(m);
    }
  }
}

// The Omega3 < 0 symmetry (docs/design.md section 1.3): the mirrored problem gives the mirrored
// run.
TEST(VopSymmetry, NegativeOmega3MirrorsThePositiveCase) {
  eulervop::euler_problem<double> p, q;
  p.torque.G = {1, 1, 1};
  p.Omega0 = {0.5, 0.1, 1};
  q.torque.G = {1, -1, -1};
  q.Omega0 = {0.5, -0.1, -1};
  eulervop::fixed_run_settings s{0.01, 500, 50};
  const auto a = eulervop::run_fixed(eulervop::formulation::vop, eulervop::rk::method::rk4, p, s);
  const auto b = eulervop::run_fixed(eulervop::formulation::vop, eulervop::rk::method::rk4, q, s);
  ASSERT_EQ(a.Omega.size(), b.Omega.size());
  for (std::size_t i = 0; i < a.Omega.size(); ++i) {
    // Same arithmetic on the same elements, mirrored only at the end: bit-identical.
    EXPECT_EQ(a.Omega[i][0], b.Omega[i][0]);
    EXPECT_EQ(a.Omega[i][1], -b.Omega[i][1]);
    EXPECT_EQ(a.Omega[i][2], -b.Omega[i][2]);
  }
}

TEST(VopDomain, RefusesStatesOutsideTheRegime) {
  // k = |(Omega1, Omega2)| / |(Omega2, Omega3)| = 1.2 / 0.5 > 1: rotation near the minor axis.
  EXPECT_THROW(eulervop::vop_frame<double>::of({1.2, 0, 0.5}), std::domain_error);
  EXPECT_THROW(eulervop::vop_frame<double>::of({0.5, 0.2, 0.0}), std::domain_error);
  try {
    eulervop::vop_frame<double>::of({1.2, 0, 0.5});
  } catch (const std::domain_error& e) {
    EXPECT_NE(std::string(e.what()).find("k = c1/c2 = 2.4"), std::string::npos) << e.what();
  }
}

// The VOP equations are implemented exactly: on the paper scene, VOP in quad with rk8 at a small
// step matches the quad Chebyshev-Picard reference (independent: Eq. 5 directly) to <= 1e-20 at
// tau = 10.
TEST(VopPaperScene, QuadRk8MatchesTheReference) {
  eulervop::euler_problem<quad> p;
  p.torque.G = {quad(1), quad(1), quad(1)};
  p.Omega0 = {quad("0.5"), quad(0), quad(1)};
  const auto ref = eulervop::integrate_reference<quad>(p, quad(10));
  const auto frame = eulervop::vop_frame<quad>::of(p.Omega0);
  eulervop::vop_system<quad> sys(frame.rotate(p.torque.G));
  vec3<quad> y = frame.elements_of(p.Omega0);
  const std::size_t n = 20000;  // h = 5e-4: rk8 truncation ~ (5e-4 * |Omega| ~ 1e-2)^8 per unit
  const quad h = quad(10) / n;
  const auto r = eulervop::rk::integrate_fixed(eulervop::rk::method::rk8, sys, y, quad(0), h, n);
  ASSERT_FALSE(r.diverged());
  const double err = static_cast<double>(eulervop::eq20_error(ref(quad(10)), frame.Omega_of(y)));
  std::printf("VOP quad rk8, h = 5e-4, tau = 10: error %.3e against the reference\n", err);
  EXPECT_LE(err, 1e-20);
}

}  // namespace
