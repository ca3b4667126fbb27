// The general path's setup from a scene in Arb balls: the value type (certify/ball_value.hpp),
// a scene's numbers (scene/scene_balls.hpp) and the problem they give
// (scene/scene_certification_problem.hpp). Each ball must hold a value known independently:
// a closed form (Eqs. 2-4 for moments whose A_i are 1, 1 and 1/3; a rational decimal, compared
// exactly), or MPFR at 1000 bits (sqrt, and Jacobi's functions by Boost's own algorithm). The
// radii are bounded from the operations' count: each of Arb's operations at p bits rounds its
// midpoint once, adding at most one ulp (2^(1-p) relative) to the radius, and carries the
// operands' radii to first order (Johansson 2017), so a setup of a few dozen operations on
// numbers of magnitude at most 10 stays below 2^-(p-12).
#include <eulervop/certify/ball_value.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/scene/expression_parser.hpp>
#include <eulervop/scene/input_error.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_balls.hpp>
#include <eulervop/scene/scene_certification_problem.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <boost/math/constants/constants.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>

#include "ball_test_support.hpp"

#include <arb.h>

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <variant>

namespace {

using eulervop::ball;
using eulervop::ball_value;
using eulervop::mpfr_real;
using eulervop::test::ball_support::holds;
using eulervop::test::ball_support::truth_bits;
namespace sc = eulervop::scene;

constexpr slong prec = 200;

template <class T>
concept ordered = requires(const T& a) { a < a; };
static_assert(ordered<double>);
static_assert(!ordered<ball_value>, "overlapping balls have no order: comparing them must not compile");

// Whether x's radius is at most 2^-e.
bool radius_below(const ball& x, slong e) { return mag_cmp_2exp_si(arb_radref(x.get()), -e) <= 0; }

TEST(BallValue, IntegersAreExactAndAQuotientNeedsAPrecision) {
  const ball_value five = ball_value(2) * ball_value(3) - ball_value(1);
  EXPECT_EQ(five.prec(), 0);
  EXPECT_TRUE(arb_equal_si(five.get().get(), 5));
  EXPECT_TRUE(arb_equal_si((-five).get().get(), -5));
  EXPECT_THROW(ball_value(1) / ball_value(3), std::logic_error);
  EXPECT_THROW(sqrt(ball_value(2)), std::logic_error);
  EXPECT_THROW(ball_value(ball(1), 0), std::invalid_argument);
}

// sqrt(x / 3) - x x - x for x = 0.1 (the decimal): MPFR at 1000 bits. The decimal's rounding and
// five operations at 200 bits on numbers below 1 each add at most 2^-199, and sqrt's derivative
// there is below 3: under 2^-194 in all (bound 2^-190).
TEST(BallValue, OperationsHoldTheExactResult) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  const ball_value x(eulervop::decimal_ball("0.1", prec), prec);
  const ball_value r = sqrt(x / 3) - x * x + (-x);
  EXPECT_EQ(r.prec(), prec);
  const mpfr_real t("0.1");
  EXPECT_TRUE(holds(r.get(), sqrt(t / 3) - t * t - t));
  EXPECT_TRUE(radius_below(r.get(), 190));
}

sc::scene physical_scene() {
  return sc::parse_scene(
      "name = \"t\"\n[body]\ninertia = [0.3, 0.1, 0.2]\n[torque]\nM = [\"0.01*sin(t)\", 0.0, 0.0]\n"
      "[initial]\nomega = [1.0, 2.0, 3.0]\n[span]\nt_end = 1.0\nsamples = 3\n",
      "test");
}

// Inertia [0.3, 0.1, 0.2], listed out of order: the principal moments (0.1, 0.2, 0.3) are the
// listed axes (1, 2, 0), an even permutation; A = (0.1/0.1, 0.2/0.2, 0.1/0.3) = (1, 1, 1/3)
// (Eq. 3), so sqrt(A) = (1, 1, 1/sqrt 3) and dtau/dt = 1/sqrt 3 (Eq. 4).
TEST(SceneBalls, ScalingHoldsEquations2To4) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  const sc::scene s = physical_scene();
  const eulervop::physical_scaling<ball_value> b = sc::ball_scaling_of(s, prec);
  const eulervop::physical_scaling<eulervop::quad> q = sc::scaling_of<eulervop::quad>(s);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(b.axes().axis(i), q.axes().axis(i));  // the plain run's principal axes
    EXPECT_EQ(b.axes().sign(i), q.axes().sign(i));
  }
  EXPECT_EQ(b.axes().axis(0), 1);
  const mpfr_real r3 = 1 / sqrt(mpfr_real(3));
  const std::array<mpfr_real, 3> sqrtA = {mpfr_real(1), mpfr_real(1), r3};
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(holds(b.sqrt_A()[i].get(), sqrtA[static_cast<std::size_t>(i)])) << i;
    EXPECT_TRUE(radius_below(b.sqrt_A()[i].get(), 188)) << i;
  }
  EXPECT_TRUE(holds(b.tau_rate().get(), r3));
  EXPECT_TRUE(radius_below(b.tau_rate().get(), 188));
}

// The problem's variables and Omega(0) for the same body and omega = (1, 2, 3): in the principal
// order omega = (2, 3, 1), so Omega = omega / sqrt(A) = (2, 3, sqrt 3) (Eq. 2); dt/dtau = sqrt 3;
// the torque's divisors I_i sqrt(A_i) dtau/dt = (0.1/sqrt 3, 0.2/sqrt 3, 0.1), inverted.
TEST(SceneBalls, ThePhysicalProblemHoldsItsClosedForm) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  const eulervop::certification_problem p = sc::certification_problem_of<eulervop::quad>(physical_scene(), prec);
  const mpfr_real s3 = sqrt(mpfr_real(3));
  const std::array<mpfr_real, 3> Omega = {mpfr_real(2), mpfr_real(3), s3};
  const std::array<mpfr_real, 3> divisor_inverse = {10 * s3, 5 * s3, mpfr_real(10)};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(holds(p.initial[i], Omega[i])) << i;
    EXPECT_TRUE(holds(p.variables.divisor_inverse[i], divisor_inverse[i])) << i;
    EXPECT_TRUE(radius_below(p.initial[i], 186)) << i;
    EXPECT_TRUE(radius_below(p.variables.divisor_inverse[i], 186)) << i;
  }
  EXPECT_TRUE(holds(p.variables.rate_inverse, s3));
}

// Omega(0) = (c1 cn u, c1 sn u, c2 dn u) with k = c1/c2 (Eq. 12) against Boost's Jacobi functions
// at 1000 bits (descending Landen transformation: independent of the theta quotients enclosed).
void expect_elements(const std::string& c1, const std::string& c2, const std::string& u,
                     const mpfr_real& c1_exact, const mpfr_real& c2_exact, const mpfr_real& u_exact) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  const sc::scene s = sc::parse_scene("name = \"t\"\n[torque]\nG = [\"0.01*sin(tau)\", 0.0, 0.0]\n[initial]\nc1 = " + c1 +
                                          "\nc2 = " + c2 + "\nu = " + u + "\n[span]\ntau_end = 1.0\nsamples = 3\n",
                                      "test");
  const std::array<ball, 3> Omega = sc::ball_Omega_of_elements(std::get<sc::initial_elements>(s.initial), prec);
  mpfr_real cn, dn;
  const mpfr_real sn = boost::math::jacobi_elliptic(c1_exact / c2_exact, u_exact, &cn, &dn);
  const std::array<mpfr_real, 3> truth = {c1_exact * cn, c1_exact * sn, c2_exact * dn};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_TRUE(holds(Omega[i], truth[i])) << u << " " << i;
    EXPECT_TRUE(radius_below(Omega[i], 186)) << u << " " << i;
  }
}

TEST(SceneBalls, ElementsGiveEquation12) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  expect_elements("0.5", "1.0", "0.7", mpfr_real("0.5"), mpfr_real(1), mpfr_real("0.7"));
  expect_elements("\"1/3\"", "\"sqrt(2)/2\"", "\"pi/5\"", mpfr_real(1) / 3, sqrt(mpfr_real(2)) / 2,
                  boost::math::constants::pi<mpfr_real>() / 5);
}

// At u = 0 the state is (c1, 0, c2) exactly: no function is evaluated.
TEST(SceneBalls, ElementsAtUZeroAreExact) {
  const sc::scene s = sc::parse_scene(
      "name = \"t\"\n[torque]\nG = [\"0.01*sin(tau)\", 0.0, 0.0]\n[initial]\nc1 = 0.5\nc2 = 1.0\nu = 0.0\n"
      "[span]\ntau_end = 1.0\nsamples = 3\n",
      "test");
  const eulervop::certification_problem p = sc::certification_problem_of<eulervop::quad>(s, prec);
  EXPECT_TRUE(arb_equal_si(p.initial[1].get(), 0));
  ball half;
  arb_set_d(half.get(), 0.5);
  EXPECT_TRUE(arb_equal(p.initial[0].get(), half.get()));
  EXPECT_TRUE(arb_equal_si(p.initial[2].get(), 1));
}

// A decimal holds its rational value exactly; a binary64 number (decimal::binary) is the double
// itself, not its shortest decimal; a formula undefined on its ball is bad input naming the field.
TEST(SceneBalls, NumbersAsWritten) {
  const sc::decimal tenth = *sc::parse_decimal("0.1").number;
  fmpq_t q;
  fmpq_init(q);
  fmpq_set_si(q, 1, 10);
  EXPECT_TRUE(arb_contains_fmpq(sc::ball_of_decimal(tenth, prec, "f").get(), q));
  fmpq_clear(q);
  ball d;
  arb_set_d(d.get(), 0.1);
  EXPECT_TRUE(arb_equal(sc::ball_of_decimal(sc::binary_number(0.1), prec, "f").get(), d.get()));
  EXPECT_FALSE(arb_contains(sc::ball_of_decimal(tenth, prec, "f").get(), d.get()));

  sc::decimal formula;
  formula.text = "sqrt(0.1^2 - 0.01)";
  formula.formula = std::make_shared<const eulervop::expression>(
      sc::parse_expression(formula.text, sc::expression_variables{{"t", "", "", ""}}));
  try {
    sc::ball_of_decimal(formula, prec, "[initial] omega");
    ADD_FAILURE() << "a formula undefined on its ball was enclosed";
  } catch (const sc::input_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--certify: [initial] omega `sqrt(0.1^2 - 0.01)`: ", 0), 0u) << e.what();
  }
}

}  // namespace
