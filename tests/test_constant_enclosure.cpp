// The enclosure of a constant formula, its ball (certify/constant_ball.hpp), holds the formula's
// exact value, and a function undefined on the ball is an error, never a wrong enclosure.
// The exact values come from closed forms (2/3, 2^-3 = 1/8, 0, 4 atan(1) = pi) or from MPFR at
// 512 bits (cos, sin, exp, log, sqrt, tanh, atan, sinh, cosh, pi: correctly rounded there, 335
// bits beyond the 177 of the enclosure),
// each compared as an interval that must lie inside the enclosure.
#include <eulervop/certify/constant_ball.hpp>
#include <eulervop/scene/expression_parser.hpp>

#include <gtest/gtest.h>

#include <arb.h>
#include <mpfr.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace {

using eulervop::ball;
using eulervop::constant_ball;

constexpr mpfr_prec_t bits = 177;

eulervop::expression constant(const std::string& text) {
  return eulervop::scene::parse_expression(text, eulervop::scene::expression_variables{{"t", "", "", ""}});
}

using exact_value = std::function<void(mpfr_ptr, mpfr_rnd_t)>;

// The formulas and their exact values, each computed at 512 bits rounded down and up (the true
// value lies between the two).
std::vector<std::pair<std::string, exact_value>> cases() {
  std::vector<std::pair<std::string, exact_value>> c;
  c.emplace_back("2/3", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_ui(r, 2, m), mpfr_div_ui(r, r, 3, m); });
  c.emplace_back("2^-3", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_d(r, 0.125, m); });
  c.emplace_back("cos(1.1)/2", [](mpfr_ptr r, mpfr_rnd_t m) {
    mpfr_set_str(r, "1.1", 10, m == MPFR_RNDD ? MPFR_RNDU : MPFR_RNDD);  // cos falls on [0, pi]
    mpfr_cos(r, r, m);
    mpfr_div_ui(r, r, 2, m);
  });
  c.emplace_back("1.5*sin(1.1)", [](mpfr_ptr r, mpfr_rnd_t m) {
    mpfr_set_str(r, "1.1", 10, m);  // sin rises on [0, pi/2]
    mpfr_sin(r, r, m);
    mpfr_mul_d(r, r, 1.5, m);
  });
  c.emplace_back("exp(-1)+log(3)-sqrt(2)", [](mpfr_ptr r, mpfr_rnd_t m) {
    // Each term rounded in the direction that moves the sum the same way.
    const mpfr_rnd_t other = m == MPFR_RNDD ? MPFR_RNDU : MPFR_RNDD;
    mpfr_t a, b;
    mpfr_inits2(512, a, b, static_cast<mpfr_ptr>(nullptr));
    mpfr_set_si(a, -1, m);
    mpfr_exp(a, a, m);
    mpfr_set_ui(b, 3, m);
    mpfr_log(b, b, m);
    mpfr_add(a, a, b, m);
    mpfr_sqrt_ui(b, 2, other);
    mpfr_sub(r, a, b, m);
    mpfr_clears(a, b, static_cast<mpfr_ptr>(nullptr));
  });
  c.emplace_back("pi/4", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_const_pi(r, m), mpfr_div_ui(r, r, 4, m); });
  c.emplace_back("sqrt(1 - 1)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_ui(r, 0, m); });
  // tanh, atan and sinh rise, cosh rises on [0, inf) and is even; the arguments are exact binary.
  c.emplace_back("tanh(0.5)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_d(r, 0.5, m), mpfr_tanh(r, r, m); });
  c.emplace_back("atan(-2)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_si(r, -2, m), mpfr_atan(r, r, m); });
  c.emplace_back("sinh(0.25)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_d(r, 0.25, m), mpfr_sinh(r, r, m); });
  c.emplace_back("cosh(-1.5)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_d(r, 1.5, m), mpfr_cosh(r, r, m); });
  // 4 atan(1) = pi.
  c.emplace_back("4*atan(1)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_const_pi(r, m); });
  return c;
}

// The end points of an enclosure at 512 bits (exact: the enclosures have 177-bit ends).
struct ends {
  ends() { mpfr_inits2(512, lo, hi, static_cast<mpfr_ptr>(nullptr)); }
  ~ends() { mpfr_clears(lo, hi, static_cast<mpfr_ptr>(nullptr)); }
  ends(const ends&) = delete;
  ends& operator=(const ends&) = delete;
  mpfr_t lo, hi;
};

// Whether [x.lo, x.hi] holds the value `exact` computes, and is at most a few units of 2^-177 wide
// (the values lie within [-2, 2], so an ulp of 177 bits is at most 2^-176).
void expect_holds(const ends& x, const std::string& text, const exact_value& exact) {
  ends truth;
  exact(truth.lo, MPFR_RNDD);
  exact(truth.hi, MPFR_RNDU);
  EXPECT_LE(mpfr_cmp(x.lo, truth.lo), 0) << text;
  EXPECT_GE(mpfr_cmp(x.hi, truth.hi), 0) << text;
  mpfr_t width;
  mpfr_init2(width, 512);
  mpfr_sub(width, x.hi, x.lo, MPFR_RNDU);
  EXPECT_LE(mpfr_get_d(width, MPFR_RNDU), 0x1p-170) << text;  // a few ulps of 177 bits near 1
  mpfr_clear(width);
}

void ends_of(ends& out, const ball& x) { arb_get_interval_mpfr(out.lo, out.hi, x.get()); }

TEST(ConstantBall, HoldsTheExactValue) {
  for (const auto& [text, exact] : cases()) {
    ends x;
    ends_of(x, constant_ball(constant(text), bits));
    expect_holds(x, text, exact);
  }
}

TEST(ConstantBall, UndefinedOnTheBallIsAnError) {
  for (const char* text : {"log(1 - 1)", "1/(3 - 3)", "(1 - 1)^-2", "sqrt(0.1 - 0.1 - 1e-30)"})
    EXPECT_THROW(constant_ball(constant(text), bits), std::domain_error) << text;
  // log(1/3 * 3 - 1): the exact value is log(0), and the ball of 1/3 * 3 - 1 holds 0.
  EXPECT_THROW(constant_ball(constant("log(1/3*3 - 1)"), bits), std::domain_error);
  EXPECT_THROW(constant_ball(constant("t"), bits), std::invalid_argument);
}

}  // namespace
