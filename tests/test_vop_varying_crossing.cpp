// A VOP run under a torque of time that carries k across 1, against the quad reference.
// Truth and precision as in test_vop_varying_torque.cpp's header; the torques and helpers are in
// vop_varying_torque_support.hpp.
#include "vop_varying_torque_support.hpp"

#include <gtest/gtest.h>

namespace {

using namespace vop_varying;

// A torque of time that carries k across 1 (the crossing scene of docs/vop-strategies.md section
// 4, G = (-0.05, 0, -0.05), with a wobble 0.02 (cos tau, sin tau, 0) added): the bands use |G| of
// the last accepted step, the run steps across the separatrix with Eq. 5 (each direct step
// evaluating the torque in its own copy), records the band and the regime change, and its error
// stays within 10x Euler's, the bound of test_vop_theta.cpp's crossing test. Measured (tau = 40,
// band [14.24, 15.37], 134 direct steps): rk4 euler 1.26e-9, vop 3.21e-9, vop-theta 2.21e-11; rk8
// euler 3.1e-15, vop 4.1e-15, vop-theta 4.3e-15; dp45 at 1e-10: vop 2.8e-10, vop-theta 5.8e-11.
template <class T>
struct draining_torque {
  static constexpr bool depends_on_time = true;
  static constexpr bool depends_on_state = false;
  vec3<T> value(const T& t, const vec3<T>&) const {
    using std::cos;
    using std::sin;
    return {T(-5) / 100 + T(2) / 100 * cos(t), T(2) / 100 * sin(t), T(-5) / 100};
  }
};
template <class U, class T>
draining_torque<U> convert_torque(const draining_torque<T>&) {
  return {};
}

TEST(VopVaryingTorque, CrossesTheSeparatrixUnderATorqueOfTime) {
  const double h = paper_h();
  const std::size_t n = static_cast<std::size_t>(40 / h);
  const eulervop::fixed_run_settings s{h, n, 5};
  const auto ref = eulervop::integrate_reference<quad>(problem<quad>(draining_torque<quad>{}, paper_Omega0_q),
                                                       quad(h * static_cast<double>(n)));
  const auto p = problem<double>(draining_torque<double>{}, paper_Omega0);
  for (auto m : {eulervop::rk::method::rk4, eulervop::rk::method::rk8}) {
    const auto e = eulervop::run_fixed(formulation::euler, m, p, s);
    ASSERT_FALSE(e.diverged());
    const double e_max = max_error(e, ref, h);
    for (formulation f : {formulation::vop, formulation::vop_theta}) {
      const auto r = eulervop::run_fixed(f, m, p, s);
      ASSERT_FALSE(r.diverged()) << eulervop::describe(r.status);
      ASSERT_EQ(r.steps, n);
      ASSERT_FALSE(r.separatrix_bands.empty());
      EXPECT_GE(r.regime_changes, 1u);
      const double v_max = max_error(r, ref, h);
      std::printf("crossing under a torque of time, %s %s: band [%.4f, %.4f] (%zu direct steps, %zu regime "
                  "changes), max error %.3e vs euler %.3e\n",
                  std::string(eulervop::formulation_name(f)).c_str(), std::string(eulervop::rk::method_name(m)).c_str(),
                  r.separatrix_bands.front().first, r.separatrix_bands.front().second, r.direct_steps,
                  r.regime_changes, v_max, e_max);
      EXPECT_LE(v_max, 10 * e_max);
    }
  }
  eulervop::adaptive_run_settings as;
  as.atol = as.rtol = 1e-10;
  as.tau_end = h * static_cast<double>(n);  // the reference's span
  as.h_max = 1;
  for (formulation f : {formulation::vop, formulation::vop_theta}) {
    const auto r = eulervop::run_adaptive(f, eulervop::rk::method::dp45, p, as);
    ASSERT_FALSE(r.diverged()) << eulervop::describe(r.status);
    ASSERT_FALSE(r.separatrix_bands.empty());
    const double v_max = max_error_at_taus(r, ref);
    std::printf("crossing under a torque of time, %s dp45 at 1e-10: %zu steps, max error %.3e\n",
                std::string(eulervop::formulation_name(f)).c_str(), r.steps, v_max);
    EXPECT_LE(v_max, 1e-8);
  }
}


}  // namespace
