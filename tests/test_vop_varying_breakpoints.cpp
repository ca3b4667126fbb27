// The fixed-step VOP runs under a piecewise torque split the step at its breakpoint, against the
// quad reference (the adaptive runs: test_vop_varying_adaptive_breakpoints.cpp).
// Truth and precision as in test_vop_varying_torque.cpp's header; the torques and helpers are in
// vop_varying_torque_support.hpp.
#include "vop_varying_torque_support.hpp"

#include <gtest/gtest.h>

namespace {

using namespace vop_varying;

// A piecewise torque whose breakpoint b falls between grid points: the fixed-step runs keep
// their samples on the grid t0 + n h (every sample index a multiple of sample_every, n steps in
// all) and their errors small, because the step that crosses b is split there and each part sees
// its own formulas. The same function without breakpoints (stepped across) errs far more: an RK
// step across a jump of G is first order in h there.
TEST(VopVaryingTorque, PiecewiseTorqueSplitsTheStepAtTheBreakpoint) {
  const double h = paper_h();
  const std::size_t n = static_cast<std::size_t>(20 / h);
  const double b = 7.77;  // (b / h) = 921.8...: between grid points
  ASSERT_NE(std::floor(b / h), b / h);
  const eulervop::fixed_run_settings s{h, n, 5};
  const quad bq = quad(b);
  const auto ref = eulervop::integrate_reference<quad>(
      problem<quad>(switched_torque<quad, true>{quad("0.02"), bq, {bq}, std::nullopt}, paper_Omega0_q),
      quad(h * static_cast<double>(n)));
  const auto pieces = problem<double>(switched_torque<double, true>{0.02, b, {b}, std::nullopt}, paper_Omega0);
  const auto across = problem<double>(switched_torque<double, false>{0.02, b, {b}, std::nullopt}, paper_Omega0);
  // The same pieces as formulas (expression_torque, whose copy each run pins).
  const auto formulas = problem<double>(eulervop::time_torque<double>(switched_law(), {}), paper_Omega0);
  for (formulation f : {formulation::euler, formulation::vop, formulation::vop_theta}) {
    const auto r = eulervop::run_fixed(f, eulervop::rk::method::rk4, pieces, s);
    ASSERT_FALSE(r.diverged());
    ASSERT_EQ(r.steps, n);
    for (std::size_t i = 0; i < r.sample_steps.size(); ++i)
      EXPECT_TRUE(r.sample_steps[i] % 5 == 0 || r.sample_steps[i] == n) << r.sample_steps[i];
    EXPECT_EQ(r.sample_steps.back(), n);
    const auto q = eulervop::run_fixed(f, eulervop::rk::method::rk4, across, s);
    ASSERT_FALSE(q.diverged());
    // The split step costs one extra step's evaluations (rk4: 4).
    EXPECT_EQ(r.rhs_evals, q.rhs_evals + 4);
    const auto x = eulervop::run_fixed(f, eulervop::rk::method::rk4, formulas, s);
    ASSERT_FALSE(x.diverged());
    EXPECT_EQ(x.sample_steps, r.sample_steps);
    EXPECT_EQ(x.rhs_evals, r.rhs_evals);
    const double e_split = max_error(r, ref, h), e_across = max_error(q, ref, h), e_formulas = max_error(x, ref, h);
    std::printf("piecewise G, b = %.2f, rk4, h = K/200, tau = 20, %s: max error %.3e split at b (formulas %.3e), "
                "%.3e stepped across\n",
                b, std::string(eulervop::formulation_name(f)).c_str(), e_split, e_formulas, e_across);
    // Measured: split 7.7e-10 (euler), 1.5e-12 (vop), 1.6e-12 (vop-theta), the formulas alike;
    // stepped across 7.6e-6 for all three (the jump of G, |dG| = 0.045, taken to first order
    // over one step).
    EXPECT_LE(e_split, f == formulation::euler ? 4e-9 : 1e-11);
    EXPECT_NEAR(e_formulas, e_split, 0.01 * e_split);
    EXPECT_GE(e_across, 1000 * e_split);
  }
}

}  // namespace
