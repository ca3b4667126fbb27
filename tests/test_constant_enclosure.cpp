// The enclosure of a constant formula (certify/constant_enclosure.hpp): it holds the formula's
// exact value, and a function undefined on an enclosure is an error, never a wrong enclosure.
// The exact values come from closed forms (2/3, 2^-3 = 1/8, 0, 4 atan(1) = pi) or from MPFR at
// 512 bits (cos, sin, exp, log, sqrt, tanh, atan, sinh, cosh, pi: correctly rounded there, 335
// bits beyond the 177 of the enclosure),
// each compared as an interval that must lie inside the enclosure.
#include <eulervop/certify/constant_enclosure.hpp>
#include <eulervop/scene/expression_parser.hpp>

#include <gtest/gtest.h>

#include <mpfi.h>
#include <mpfr.h>

#include <functional>
#include <string>

namespace {

using eulervop::enclose_constant;
using eulervop::interval;

constexpr mpfr_prec_t bits = 177;

eulervop::expression constant(const std::string& text) {
  return eulervop::scene::parse_expression(text, eulervop::scene::expression_variables{{"t", "", "", ""}});
}

// Whether the enclosure of `text` holds the value `exact` computes at 512 bits (rounded down and
// up: the true value lies between the two), and is at most a few units of 2^-177 wide.
void expect_encloses(const std::string& text, const std::function<void(mpfr_ptr, mpfr_rnd_t)>& exact) {
  const interval x = enclose_constant(constant(text), bits);
  mpfr_t lo, hi, width;
  mpfr_inits2(512, lo, hi, width, static_cast<mpfr_ptr>(nullptr));
  exact(lo, MPFR_RNDD);
  exact(hi, MPFR_RNDU);
  EXPECT_LE(mpfr_cmp(&x.get()->left, lo), 0) << text;
  EXPECT_GE(mpfr_cmp(&x.get()->right, hi), 0) << text;
  mpfr_sub(width, &x.get()->right, &x.get()->left, MPFR_RNDU);
  EXPECT_LE(mpfr_get_d(width, MPFR_RNDU), 0x1p-170) << text;  // a few ulps of 177 bits near 1
  mpfr_clears(lo, hi, width, static_cast<mpfr_ptr>(nullptr));
}

TEST(ConstantEnclosure, HoldsTheExactValue) {
  expect_encloses("2/3", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_ui(r, 2, m), mpfr_div_ui(r, r, 3, m); });
  expect_encloses("2^-3", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_d(r, 0.125, m); });
  expect_encloses("cos(1.1)/2", [](mpfr_ptr r, mpfr_rnd_t m) {
    mpfr_set_str(r, "1.1", 10, m == MPFR_RNDD ? MPFR_RNDU : MPFR_RNDD);  // cos falls on [0, pi]
    mpfr_cos(r, r, m);
    mpfr_div_ui(r, r, 2, m);
  });
  expect_encloses("1.5*sin(1.1)", [](mpfr_ptr r, mpfr_rnd_t m) {
    mpfr_set_str(r, "1.1", 10, m);  // sin rises on [0, pi/2]
    mpfr_sin(r, r, m);
    mpfr_mul_d(r, r, 1.5, m);
  });
  expect_encloses("exp(-1)+log(3)-sqrt(2)", [](mpfr_ptr r, mpfr_rnd_t m) {
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
  expect_encloses("pi/4", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_const_pi(r, m), mpfr_div_ui(r, r, 4, m); });
  expect_encloses("sqrt(1 - 1)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_ui(r, 0, m); });
  // tanh, atan and sinh rise, cosh rises on [0, inf) and is even; the arguments are exact binary.
  expect_encloses("tanh(0.5)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_d(r, 0.5, m), mpfr_tanh(r, r, m); });
  expect_encloses("atan(-2)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_si(r, -2, m), mpfr_atan(r, r, m); });
  expect_encloses("sinh(0.25)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_d(r, 0.25, m), mpfr_sinh(r, r, m); });
  expect_encloses("cosh(-1.5)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_set_d(r, 1.5, m), mpfr_cosh(r, r, m); });
  // 4 atan(1) = pi.
  expect_encloses("4*atan(1)", [](mpfr_ptr r, mpfr_rnd_t m) { mpfr_const_pi(r, m); });
}

TEST(ConstantEnclosure, UndefinedOnTheEnclosureIsAnError) {
  for (const char* text : {"log(1 - 1)", "1/(3 - 3)", "(1 - 1)^-2", "sqrt(0.1 - 0.1 - 1e-30)"})
    EXPECT_THROW(enclose_constant(constant(text), bits), std::domain_error) << text;
  // log(1/3 * 3 - 1): the exact value is log(0), and the enclosure of 1/3 * 3 - 1 holds 0.
  EXPECT_THROW(enclose_constant(constant("log(1/3*3 - 1)"), bits), std::domain_error);
  EXPECT_THROW(enclose_constant(constant("t"), bits), std::invalid_argument);
}

}  // namespace
