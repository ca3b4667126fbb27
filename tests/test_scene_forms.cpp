// Scenes beyond a constant torque (docs/scenes.md): the coefficient form, torque formulas of time
// and state, pieces, constant formulas for numbers, and moments of no rigid body; and the torque
// they give the integrator (model/expression_torque.hpp).
//
// Truth: values built directly in T from the same decimals (exact comparisons where the
// operations are the same: a constant formula of a physical torque gives bit for bit the G of
// the constant torque, since both divide M by I sqrt(A) dtau/dt in the same order), the chain
// rule for a damping torque through Eqs. 2-4 (M = -k omega gives dG_i/dOmega_i = -k / (I_i
// dtau/dt), derived below; 8 eps for the few roundings of each side), and pi from a 50-digit
// decimal.
#include "type_test_names.hpp"

#include <eulervop/core/scalar.hpp>
#include <eulervop/model/expression_torque.hpp>
#include <eulervop/model/physical_scaling.hpp>
#include <eulervop/oracle.hpp>
#include <eulervop/scene/input_error.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <gtest/gtest.h>

#include <string>

namespace {

using eulervop::quad;
using eulervop::vec3;
using namespace eulervop::scene;

scene parse(const std::string& text) { return parse_scene(text, "test.toml"); }

const std::string sciml =
    "name = \"sciml\"\n[equations]\na = [-2.0, 1.25, -0.5]\n[torque]\nf = [0.0, 0.0, \"0.25*sin(t)^2\"]\n"
    "[initial]\ny = [1.0, 0.0, 0.9]\n[span]\nt_end = 10.0\nsamples = 11\n";

TEST(CoefficientForm, IsTheDirectFormWithTheScenesCoefficients) {
  const scene s = parse(sciml);
  EXPECT_TRUE(s.is_coefficient_form());
  EXPECT_TRUE(uses_direct_form(s));
  EXPECT_EQ(torque_kind_of(s), torque_kind::of_time);
  with_problem<quad>(s, [](const auto& p) {
    EXPECT_EQ(p.form, eulervop::equation_form::direct);
    EXPECT_EQ(p.a, (vec3<quad>{quad(-2), quad("1.25"), quad("-0.5")}));
    EXPECT_EQ(p.Omega0, (vec3<quad>{quad(1), quad(0), quad("0.9")}));
    // f(t) at t = 1: (0, 0, sin(1)^2 / 4), exactly the same operations in quad.
    const quad t = 1;
    const quad s1 = sin(t);
    const vec3<quad> f = p.torque.value(t, p.Omega0);
    EXPECT_EQ(f[0], 0);
    EXPECT_EQ(f[2], quad("0.25") * (s1 * s1));
  });
  EXPECT_EQ(tau_end_of<quad>(s), 10);
}

TEST(CoefficientForm, AConstantTorqueStaysConstant) {
  const scene s = parse(std::string(sciml).replace(sciml.find("\"0.25*sin(t)^2\""), 15, "0.125"));
  EXPECT_EQ(torque_kind_of(s), torque_kind::constant);
  const auto p = to_problem<quad>(s);
  EXPECT_EQ(p.torque.G, (vec3<quad>{0, 0, quad("0.125")}));
  EXPECT_EQ(p.form, eulervop::equation_form::direct);
}

TEST(ConstantFormulas, AreEvaluatedInTheRunsPrecision) {
  const scene s = parse(
      "name = \"hlw\"\n[body]\ninertia = [2.0, 1.0, \"2/3\"]\n[initial]\nomega = [\"cos(1.1)/2\", 0, "
      "\"1.5*sin(1.1)\"]\n[span]\nt_end = 1\nsamples = 2\n");
  ASSERT_TRUE(s.inertia);
  EXPECT_EQ((*s.inertia)[2].to_scalar<quad>(), quad(2) / 3);  // correctly rounded in quad, not via double
  EXPECT_NE((*s.inertia)[2].to_scalar<quad>(), quad(2.0 / 3.0));
  const auto& w = std::get<initial_rates>(s.initial).rates;
  EXPECT_EQ(w[0].to_scalar<quad>(), cos(quad("1.1")) / 2);
  // Moments of no rigid body (1 + 2/3 < 2): integrated, with one note.
  ASSERT_EQ(s.notes.size(), 1u);
  EXPECT_NE(s.notes[0].find("no rigid body"), std::string::npos) << s.notes[0];
  EXPECT_NO_THROW((void)to_problem<quad>(s));
}

TEST(ConstantFormulas, NameNoVariable) {
  EXPECT_THROW(parse("name = \"x\"\n[initial]\nOmega = [\"tau\", 0, 1]\n[span]\ntau_end = 1\nsamples = 2\n"),
               input_error);
}

// A physical torque whose formulas are constants gives exactly the constant torque's G: the
// expression torque maps M by the same operations as physical_scaling::G_of_M.
TEST(PhysicalFormulas, ConstantFormulasGiveTheConstantTorqueExactly) {
  const std::string body = "name = \"p\"\n[body]\ninertia = [150, 100, 200]\n[initial]\nomega = [0.02, 0.1, 0.05]\n"
                           "[span]\nt_end = 10\nsamples = 3\n";
  const scene constant = parse(body + "[torque]\nM = [0.01, -0.02, 0.005]\n");
  const scene formula = parse(body + "[torque]\nM = [\"0.01\", \"-0.02 + 0*t\", \"0.005\"]\n");
  ASSERT_EQ(torque_kind_of(formula), torque_kind::of_time);
  const auto pc = to_problem<quad>(constant);
  const auto pf = to_problem_with_law<quad, false>(formula);
  EXPECT_EQ(pf.Omega0, pc.Omega0);
  EXPECT_EQ(pf.torque.value(quad(3), pc.Omega0), pc.torque.G);
}

// A damping torque M = -k omega in a physical scene: in Omega (Eq. 4, omega_i = sqrt(A_i) Omega_i
// in the principal axes) G_i = -k omega_i / (I_i sqrt(A_i) dtau/dt) = -k Omega_i / (I_i dtau/dt),
// so its Jacobian is diagonal with -k / (I_i dtau/dt), the axes relabelled included.
TEST(PhysicalFormulas, DampingJacobianFollowsEqs2to4) {
  const scene s = parse(
      "name = \"damped\"\n[body]\ninertia = [150, 100, 200]\n[torque]\nM = [\"-0.5*omega1\", \"-0.5*omega2\", "
      "\"-0.5*omega3\"]\n[initial]\nomega = [0.02, 0.1, 0.05]\n[span]\nt_end = 10\nsamples = 3\n");
  ASSERT_EQ(torque_kind_of(s), torque_kind::of_state);
  const auto p = to_problem_with_law<quad, true>(s);
  const eulervop::physical_scaling<quad> scale = scaling_of<quad>(s);
  std::array<vec3<quad>, 3> J{};
  p.torque.add_jacobian(quad(1), p.Omega0, J);
  const quad I[3] = {scale.moments().I1, scale.moments().I2, scale.moments().I3};
  const quad eps = std::numeric_limits<quad>::epsilon();
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      const quad expected = i == k ? quad("-0.5") / (I[i] * scale.tau_rate()) : quad(0);
      EXPECT_LE(abs(J[i][k] - expected), 8 * eps * abs(quad("0.5") / (I[i] * scale.tau_rate()))) << i << k;
    }
  // The value itself: G = -0.5 Omega / (I dtau/dt).
  const vec3<quad> G = p.torque.value(quad(1), p.Omega0);
  for (int i = 0; i < 3; ++i)
    EXPECT_LE(abs(G[i] + quad("0.5") * p.Omega0[i] / (I[i] * scale.tau_rate())), 8 * eps * abs(G[i])) << i;
}

// Pieces: breakpoints in the integrator's time (a physical scene's tau = t dtau/dt), the formulas
// of each window, zero outside, and pinning at a breakpoint.
TEST(Pieces, BreakpointsAndWindows) {
  const scene s = parse(
      "name = \"eulr\"\n[body]\ninertia = [0.5, 2, 3]\n[initial]\nomega = [1, 0, 0.9]\n[[torque.piece]]\nfrom = "
      "\"3*pi\"\nto = \"4*pi\"\nM = [0, 0, \"0.75*sin(t)^2\"]\n[span]\nt_end = 20\nsamples = 3\n");
  ASSERT_EQ(torque_kind_of(s), torque_kind::of_time);
  const auto p = to_problem_with_law<quad, false>(s);
  const eulervop::physical_scaling<quad> scale = scaling_of<quad>(s);
  const quad pi("3.1415926535897932384626433832795028841971693993751");
  ASSERT_EQ(p.torque.breakpoints().size(), 2u);
  const quad eps = std::numeric_limits<quad>::epsilon();
  EXPECT_LE(abs(p.torque.breakpoints()[0] - 3 * pi * scale.tau_rate()), 16 * eps * 10 * scale.tau_rate());
  EXPECT_LE(abs(p.torque.breakpoints()[1] - 4 * pi * scale.tau_rate()), 16 * eps * 13 * scale.tau_rate());
  const vec3<quad> y = p.Omega0;
  const quad inside = scale.tau_of_t(quad("3.5") * pi);
  EXPECT_NE(p.torque.value(inside, y)[2], 0);  // sin^2(3.5 pi) = 1: M3 = 0.75
  EXPECT_EQ(p.torque.value(scale.tau_of_t(quad(1)), y), (vec3<quad>{0, 0, 0}));
  EXPECT_EQ(p.torque.value(scale.tau_of_t(quad(15)), y), (vec3<quad>{0, 0, 0}));
  // At the window's start the formulas of the window apply (right-continuous), unless the
  // interval before is pinned; 0.75 sin^2(3 pi) rounds to a tiny value, not exactly 0.
  const quad b = p.torque.breakpoints()[0];
  EXPECT_EQ(p.torque.interval_at(b), 1u);
  p.torque.pin(0);
  EXPECT_EQ(p.torque.value(b, y), (vec3<quad>{0, 0, 0}));
  p.torque.unpin();
}

// The oracle API takes a scene's problem of any torque type: the SciML rigid body's reference at
// t = 10 equals the one the integrator gives directly (the same computation).
TEST(Oracle, ReferenceOfATorqueOfTime) {
  const scene s = parse(sciml);
  const auto ref = with_problem<quad>(s, [&](const auto& p) { return eulervop::oracle::reference<quad>(p, quad(10)); });
  const auto direct = with_problem<quad>(s, [&](const auto& p) { return eulervop::integrate_reference(p, quad(10)); });
  EXPECT_EQ(ref(quad(10)), direct(quad(10)));
  EXPECT_EQ(ref(quad(0)), (vec3<quad>{1, 0, quad("0.9")}));
}

}  // namespace
