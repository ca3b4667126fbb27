// The torque of the runs whose kind is data (runs/varying_torque.hpp): it evaluates, breaks and
// pins exactly as the kind it holds, and the runs refuse a torque of the attitude without q as
// they did under its own type (runs/comparison_run.hpp).
#include "vop_varying_torque_support.hpp"

#include <eulervop/model/attitude_torque.hpp>
#include <eulervop/model/staged_attitude_torque.hpp>
#include <eulervop/runs/comparison_run.hpp>
#include <eulervop/runs/varying_torque.hpp>

#include <gtest/gtest.h>

#include <optional>
#include <stdexcept>
#include <vector>

namespace {

using namespace vop_varying;
using eulervop::varying_torque;

// The kind's own answers and the varying_torque's, at times on both sides of the breakpoints and
// pinned to each interval: the same doubles (the same evaluation, behind one switch).
template <class Kind>
void expect_same_as_kind(const Kind& own) {
  const varying_torque<double> g{typename varying_torque<double>::kinds(own)};
  ASSERT_EQ(g.breakpoints(), own.breakpoints());
  const vec3<double> y{0.3, -0.2, 0.9};
  for (const double t : {0.0, 1.25, 7.76, 7.77, 7.78, 50.0, 120.0}) {
    EXPECT_EQ(g.interval_at(t), own.interval_at(t)) << t;
    EXPECT_EQ(g.value(t, y), own.value(t, y)) << t;
  }
  for (std::size_t i = 0; i <= own.breakpoints().size(); ++i) {
    g.pin(i);
    own.pin(i);
    EXPECT_EQ(g.value(50.0, y), own.value(50.0, y)) << "pinned to " << i;
  }
  g.unpin();
  own.unpin();
  EXPECT_EQ(g.value(7.77, y), own.value(7.77, y));
}

TEST(VaryingTorque, EvaluatesAsTheKindItHolds) {
  expect_same_as_kind(eulervop::time_torque<double>(switched_law(), {}));
  expect_same_as_kind(eulervop::state_torque<double>(switched_law(), {}));
  const eulervop::staged_attitude_torque<double> staged(
      eulervop::attitude_torque<double>(switched_law(), {}, std::nullopt), eulervop::quaternion<double>{1, 0, 0, 0});
  expect_same_as_kind(staged);
  const varying_torque<double> formulas{varying_torque<double>::kinds(eulervop::time_torque<double>(wobble_law(), {}))};
  EXPECT_FALSE(formulas.reads_attitude());
  EXPECT_TRUE(varying_torque<double>{varying_torque<double>::kinds(staged)}.reads_attitude());
}

// A torque of the attitude runs only with q (its kind is data now, so the check is at run time):
// without attitude settings a run is refused with a reason; with them it runs.
TEST(VaryingTorque, AttitudeTorqueRefusesARunWithoutQ) {
  const auto p = problem<double>(
      eulervop::staged_attitude_torque<double>(eulervop::attitude_torque<double>(wobble_law(), {}, std::nullopt),
                                               eulervop::quaternion<double>{1, 0, 0, 0}),
      paper_Omega0);
  eulervop::fixed_run_settings s{0.01, 10, 1};
  EXPECT_THROW((void)eulervop::run_fixed(formulation::euler, eulervop::rk::method::rk4, p, s), std::invalid_argument);
  eulervop::adaptive_run_settings a;
  a.tau_end = 1;
  a.atol = a.rtol = 1e-9;
  EXPECT_THROW((void)eulervop::run_adaptive(formulation::vop, eulervop::rk::method::dp45, p, a), std::invalid_argument);
  s.attitude = eulervop::attitude_settings{};
  const auto r = eulervop::run_fixed(formulation::euler, eulervop::rk::method::rk4, p, s);
  EXPECT_EQ(r.steps, 10u);
  EXPECT_EQ(r.q.size(), r.Omega.size());
}

}  // namespace
