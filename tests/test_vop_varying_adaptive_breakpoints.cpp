// The adaptive VOP runs under a piecewise torque step onto its breakpoint, against the quad
// reference (the fixed steps: test_vop_varying_breakpoints.cpp).
// Truth and precision as in test_vop_varying_torque.cpp's header; the torques and helpers are in
// vop_varying_torque_support.hpp.
#include "vop_varying_torque_support.hpp"

#include <gtest/gtest.h>

namespace {

using namespace vop_varying;

// The same piecewise torque under error control: the adaptive runs step onto b and restart there,
// so they meet their tolerance as they do without a breakpoint.
TEST(VopVaryingTorque, AdaptiveRunsStepOntoTheBreakpoint) {
  const double b = 7.77;
  const quad bq = quad(b);
  const auto ref = eulervop::integrate_reference<quad>(
      problem<quad>(switched_torque<quad, true>{quad("0.02"), bq, {bq}, std::nullopt}, paper_Omega0_q), quad(20));
  const auto pieces = problem<double>(switched_torque<double, true>{0.02, b, {b}, std::nullopt}, paper_Omega0);
  const auto across = problem<double>(switched_torque<double, false>{0.02, b, {b}, std::nullopt}, paper_Omega0);
  eulervop::adaptive_run_settings s;
  s.atol = s.rtol = 1e-10;
  s.tau_end = 20;
  s.h_max = 1;  // the euler formulation reads h_max = 0 as a zero step
  for (formulation f : {formulation::euler, formulation::vop, formulation::vop_theta}) {
    const auto r = eulervop::run_adaptive(f, eulervop::rk::method::dp45, pieces, s);
    ASSERT_FALSE(r.diverged()) << eulervop::formulation_name(f) << ": " << eulervop::describe(r.status);
    const auto q = eulervop::run_adaptive(f, eulervop::rk::method::dp45, across, s);
    ASSERT_FALSE(q.diverged());
    const double e_split = max_error_at_taus(r, ref), e_across = max_error_at_taus(q, ref);
    std::printf("piecewise G, dp45 at 1e-10, %s: max error %.3e (%zu steps, %zu rejected) onto b, %.3e (%zu steps, "
                "%zu rejected) across\n",
                std::string(eulervop::formulation_name(f)).c_str(), e_split, r.steps, r.rejected, e_across, q.steps,
                q.rejected);
    // Measured: onto b 3.8e-10 (euler), 4.1e-11 (vop), 7.7e-11 (vop-theta), no rejected step;
    // across 6.8e-9, 2.0e-8, 3.1e-8 with 18-27 rejections: the controller shrinks the step at the
    // jump until its estimate passes, but the estimate of a step across a jump is unreliable.
    EXPECT_LE(e_split, f == formulation::euler ? 4e-9 : 1e-9);
    EXPECT_GE(e_across, 5 * e_split);
    EXPECT_LE(r.rejected, q.rejected);
  }
}


}  // namespace
