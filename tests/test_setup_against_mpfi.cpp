// The general path's setup in Arb balls (scene/scene_balls.hpp) against the MPFI intervals the
// fast path still computes from the same scene (scene/scene_exact_problem.hpp): every ball must
// overlap its interval (both hold the exact value; a ball of another number, a wrong axis or a
// wrong formula would not), for a body listed out of order, moments, rates and elements written
// as formulas, and elements at u != 0. This file goes with the fast path and MPFI; the balls'
// independent values are in test_scene_balls.cpp.
#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_balls.hpp>
#include <eulervop/scene/scene_exact_problem.hpp>

#include <gtest/gtest.h>

#include <arb.h>

#include <array>
#include <string>
#include <variant>

namespace {

using eulervop::ball;
using eulervop::interval;
namespace sc = eulervop::scene;

constexpr slong prec = 177;

bool overlap(const ball& b, const interval& x) { return arb_overlaps(b.get(), eulervop::ball_of(x, prec).get()); }

TEST(SetupAgainstMpfi, PhysicalScalingAndRates) {
  for (const char* body : {"inertia = [0.3, 0.1, 0.2]\n[initial]\nomega = [1.0, -2.0, 3.5]",
                           "inertia = [1.0, 0.9, \"2/3\"]\n[initial]\nomega = [\"cos(1.1)/2\", 0.1, \"1.5*sin(1.1)\"]"}) {
    const sc::scene s = sc::parse_scene(std::string("name = \"t\"\n[body]\n") + body +
                                            "\n[torque]\nM = [\"0.01*sin(t)\", 0.0, 0.0]\n[span]\nt_end = 1.0\nsamples = 3\n",
                                        "test");
    const auto b = sc::ball_scaling_of(s, prec);
    const auto x = sc::exact_scaling_of(s, prec);
    const auto& rates = std::get<sc::initial_rates>(s.initial).rates;
    const auto bO = b.Omega_of_omega(sc::ball_values_of(rates, prec, "[initial] omega"));
    const auto xO = x.Omega_of_omega(sc::detail::decimals_of(rates, prec));
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(b.axes().axis(i), x.axes().axis(i)) << body;
      EXPECT_EQ(b.axes().sign(i), x.axes().sign(i)) << body;
      EXPECT_TRUE(overlap(b.sqrt_A()[i].get(), x.sqrt_A()[i])) << body << " sqrt(A) " << i;
      EXPECT_TRUE(overlap(bO[i].get(), xO[i])) << body << " Omega " << i;
    }
    EXPECT_TRUE(overlap(b.tau_rate().get(), x.tau_rate())) << body;
    EXPECT_TRUE(overlap(b.moments().I3.get(), x.moments().I3)) << body;
  }
}

TEST(SetupAgainstMpfi, OmegaOfElements) {
  for (const char* elements : {"c1 = 0.5\nc2 = 1.0\nu = 0.7", "c1 = \"1/3\"\nc2 = \"sqrt(2)/2\"\nu = \"pi/5\"",
                               "c1 = 0.999\nc2 = 1.0\nu = -12.25", "c1 = 0.5\nc2 = 1.0\nu = 0.0"}) {
    const sc::scene s = sc::parse_scene(std::string("name = \"t\"\n[initial]\n") + elements +
                                            "\n[span]\ntau_end = 1.0\nsamples = 3\n",
                                        "test");
    const auto& e = std::get<sc::initial_elements>(s.initial);
    const std::array<ball, 3> b = sc::ball_Omega_of_elements(e, prec);
    const eulervop::vec3<interval> x = sc::exact_Omega_of_elements(e, prec);
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(overlap(b[static_cast<std::size_t>(i)], x[i])) << elements << " " << i;
  }
}

}  // namespace
