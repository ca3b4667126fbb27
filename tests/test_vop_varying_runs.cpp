// The VOP runs under a torque of time (a type of our own and the same formulas) and of the state,
// against the quad reference; a torque without attitude runs refuses an attitude.
// Truth and precision as in test_vop_varying_torque.cpp's header; the torques and helpers are in
// vop_varying_torque_support.hpp.
#include "vop_varying_torque_support.hpp"

#include <gtest/gtest.h>

#include <type_traits>

namespace {

using namespace vop_varying;

// A wobbling torque of time: G = (0.01 sin tau, 0.01 cos 2 tau, 0.01), Omega0 = (0.5, 0, 1), rk4 at
// h = K(0.5)/200 to tau = 100, as a torque type of our own and as the scene's formulas
// (time_torque from a torque_law). The elements vary slowly (|G| ~ 0.01), so their truncation
// error is far below Euler's, which integrates the fast rotation itself.
TEST(VopVaryingTorque, TimeTorqueBeatsEulerAtTheSameStep) {
  const double h = paper_h();
  const std::size_t n = static_cast<std::size_t>(100 / h);
  const eulervop::fixed_run_settings s{h, n, 10};
  const auto ref = eulervop::integrate_reference<quad>(problem<quad>(wobble_torque<quad>{quad("0.01")}, paper_Omega0_q),
                                                       quad(h * static_cast<double>(n)));
  const auto own = problem<double>(wobble_torque<double>{0.01}, paper_Omega0);
  const auto law = wobble_law();
  const auto formulas = problem<double>(eulervop::time_torque<double>(law, {}), paper_Omega0);
  double errors[2][3];
  for (int which = 0; which < 2; ++which) {
    const auto run = [&](formulation f) {
      const auto r = which == 0 ? eulervop::run_fixed(f, eulervop::rk::method::rk4, own, s)
                                : eulervop::run_fixed(f, eulervop::rk::method::rk4, formulas, s);
      EXPECT_FALSE(r.diverged());
      EXPECT_EQ(r.steps, n);
      EXPECT_TRUE(r.separatrix_bands.empty() && r.small_k_bands.empty());
      return max_error(r, ref, h);
    };
    errors[which][0] = run(formulation::euler);
    errors[which][1] = run(formulation::vop);
    errors[which][2] = run(formulation::vop_theta);
    std::printf("G = 0.01 (sin tau, cos 2tau, 1), rk4, h = K/200, tau = 100 (%s): max error euler %.3e, vop %.3e, "
                "vop-theta %.3e\n",
                which == 0 ? "torque type" : "torque_law formulas", errors[which][0], errors[which][1],
                errors[which][2]);
  }
  ::testing::Test::RecordProperty("euler_max_error", std::to_string(errors[1][0]));
  ::testing::Test::RecordProperty("vop_max_error", std::to_string(errors[1][1]));
  ::testing::Test::RecordProperty("vop_theta_max_error", std::to_string(errors[1][2]));
  // Measured: euler 1.88e-8, vop 1.31e-12, vop-theta 1.22e-12 (both forms of the torque).
  for (int which = 0; which < 2; ++which) {
    EXPECT_LT(errors[which][1], errors[which][0]);
    EXPECT_LT(errors[which][2], errors[which][0]);
    EXPECT_LE(errors[which][1], 1e-11);
    EXPECT_LE(errors[which][2], 1e-11);
  }
  // The formulas evaluate the same functions (sin, cos in double): the runs agree closely.
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(errors[0][i], errors[1][i], 0.01 * errors[0][i] + 1e-14);
}

// A torque of the state, G = -0.05 Omega (damping: c1, c2 decay like e^{-0.05 tau}, k stays 0.5),
// rk4 at K/200 to tau = 40. The elements decay smoothly while Euler integrates the rotation.
TEST(VopVaryingTorque, DampingTorqueOfTheState) {
  const double h = paper_h();
  const std::size_t n = static_cast<std::size_t>(40 / h);
  const eulervop::fixed_run_settings s{h, n, 10};
  const auto ref = eulervop::integrate_reference<quad>(problem<quad>(damping_torque<quad>{quad("0.05")}, paper_Omega0_q),
                                                       quad(h * static_cast<double>(n)));
  const auto p = problem<double>(damping_torque<double>{0.05}, paper_Omega0);
  double err[3];
  const formulation forms[3] = {formulation::euler, formulation::vop, formulation::vop_theta};
  for (int i = 0; i < 3; ++i) {
    const auto r = eulervop::run_fixed(forms[i], eulervop::rk::method::rk4, p, s);
    ASSERT_FALSE(r.diverged());
    ASSERT_EQ(r.steps, n);
    err[i] = max_error(r, ref, h);
  }
  std::printf("G = -0.05 Omega, rk4, h = K/200, tau = 40: max error euler %.3e, vop %.3e, vop-theta %.3e\n", err[0],
              err[1], err[2]);
  // Measured: euler 5.2e-11, vop 9.5e-16, vop-theta 6.7e-16 (k stays 0.5 and the elements decay
  // smoothly, so their truncation is negligible). Asserted with a margin of 100.
  EXPECT_LE(err[1], 1e-13);
  EXPECT_LE(err[2], 1e-13);
  EXPECT_LE(err[1], 0.01 * err[0]);
  EXPECT_LE(err[2], 0.01 * err[0]);
}

// A torque type of our own runs in the drivers compiled for every torque (runs/varying_torque.hpp)
// with or without the attitude; with it, q rides on the same stages and the rates are bit for bit
// those of the run without it (runs/comparison_run.hpp), at a fixed step and under error control.
// A type of our own is no kind of varying_torque: it runs behind the erased kind's virtual call.
static_assert(!std::is_constructible_v<eulervop::varying_torque<double>::kinds, const damping_torque<double>&>);
TEST(VopVaryingTorque, ATorqueOfOurOwnCarriesTheAttitudeWithTheSameRates) {
  const auto p = problem<double>(damping_torque<double>{0.05}, paper_Omega0);
  eulervop::fixed_run_settings fixed{0.01, 500, 10};
  eulervop::adaptive_run_settings adaptive;
  adaptive.tau_end = 5;
  adaptive.atol = adaptive.rtol = 1e-10;
  for (const formulation f : {formulation::euler, formulation::vop, formulation::vop_theta}) {
    const auto rates = eulervop::run_fixed(f, eulervop::rk::method::rk4, p, fixed);
    const auto rates_adaptive = eulervop::run_adaptive(f, eulervop::rk::method::dp45, p, adaptive);
    fixed.attitude = adaptive.attitude = eulervop::attitude_settings{};
    const auto both = eulervop::run_fixed(f, eulervop::rk::method::rk4, p, fixed);
    const auto both_adaptive = eulervop::run_adaptive(f, eulervop::rk::method::dp45, p, adaptive);
    fixed.attitude.reset();
    adaptive.attitude.reset();
    EXPECT_TRUE(rates.q.empty());
    ASSERT_EQ(both.q.size(), both.Omega.size());
    EXPECT_EQ(both.Omega, rates.Omega);
    ASSERT_EQ(both_adaptive.q.size(), both_adaptive.Omega.size());
    EXPECT_EQ(both_adaptive.Omega, rates_adaptive.Omega);
    // q stays a unit quaternion to the method's accuracy (rk4 at h = 0.01, |Omega| ~ 1).
    const auto& q = both.q.back();
    EXPECT_NEAR(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z, 1.0, 1e-9);
  }
}

// A torque of our own that reads the attitude (it has set_attitude): its runs carry q, and a run
// without it is refused with a reason rather than run at the initial attitude.
struct attitude_reading_torque {
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = true;
  mutable eulervop::quaternion<double> q{1, 0, 0, 0};
  void set_attitude(const eulervop::quaternion<double>& x) const { q = x; }
  vec3<double> value(double, const vec3<double>&) const { return {0.01 * q.x, 0.01 * q.y, 0.01 * q.z}; }
  void add_jacobian(double, const vec3<double>&, std::array<vec3<double>, 3>&) const {}
};
template <class U>
[[maybe_unused]] attitude_reading_torque convert_torque(const attitude_reading_torque& g) {
  return g;
}

TEST(VopVaryingTorque, ATorqueThatReadsTheAttitudeRefusesARunWithoutIt) {
  const auto p = problem<double>(attitude_reading_torque{}, paper_Omega0);
  eulervop::fixed_run_settings s{0.01, 10, 1};
  EXPECT_THROW((void)eulervop::run_fixed(formulation::euler, eulervop::rk::method::rk4, p, s), std::invalid_argument);
  s.attitude = eulervop::attitude_settings{eulervop::body_rates<double>{}, {0.5, 0.5, 0.5, 0.5}};
  const auto r = eulervop::run_fixed(formulation::euler, eulervop::rk::method::rk4, p, s);
  EXPECT_EQ(r.steps, 10u);
  // The torque saw the attitude: with q0 = (1/2)(1, 1, 1, 1) its G is 0.005 (1, 1, 1), so the rates
  // leave the torque-free motion within the first step.
  const auto free = eulervop::run_fixed(formulation::euler, eulervop::rk::method::rk4,
                                        problem<double>(eulervop::constant_torque<double>{}, paper_Omega0), s);
  EXPECT_NE(r.Omega.back(), free.Omega.back());
}

}  // namespace
