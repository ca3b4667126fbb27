// Torque expressions: the parser (scene/expression_parser.hpp) and the compiled program
// (model/expression.hpp), in double, quad and MPFR at 256 bits.
//
// Truth: closed forms written out by hand in T, with the same elementary functions (so a value
// "0.25*sin(t)^2" is checked against T(1)/4 * sin(t) * sin(t)), decimals converted by from_text<T>
// (correctly rounded), and pi as a 100-digit decimal. Precision: T's epsilon at the current
// precision, eulervop::epsilon<T>() (2^-52, 2^-112, 2^-256 for mpfr:256, which computes with 257
// bits). Bounds:
//   - equal, bit for bit, where the program and the closed form perform the same roundings:
//     products by 0.25 or by -1 are exact, -(a/b) = (-a)/b, and a decimal or pi is correctly
//     rounded in both (std::numbers::pi, libquadmath's M_PIq and mpfr_const_pi on one side,
//     from_text of 100 digits on the other);
//   - partial derivatives within 16 eps (1 + |exact|): the forward mode and the hand-written
//     derivative each take at most ~8 rounded operations on values of size 0.1 to 3, without
//     cancellation, each within an ulp; the largest difference measured is 1.3 eps (double),
//     0.9 eps in quad and 0.6 eps in MPFR: a margin of 12 or more.
// Every error kind is checked for its message, its culprit and its column; a seeded random
// sweep of short texts checks that the parser throws nothing else and that every program it
// returns is well formed.
#include <eulervop/model/expression.hpp>
#include <eulervop/scene/expression_parser.hpp>

#include "type_test_names.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <utility>

namespace {

using eulervop::compiled_expression;
using eulervop::expression;
using eulervop::expression_op;
using eulervop::mpfr_real;
using eulervop::quad;
using eulervop::vec3;
using eulervop::scene::expression_error;
using eulervop::scene::expression_variables;
using eulervop::scene::parse_expression;

const expression_variables rates{{"t", "omega1", "omega2", "omega3"}};
const expression_variables normalized{{"tau", "Omega1", "Omega2", "Omega3"}};
const expression_variables time_only{{"t", "", "", ""}};

// pi to 100 significant digits.
constexpr const char* pi_100 =
    "3.141592653589793238462643383279502884197169399375105820974944592307816406286208998628034825342117068";

template <class T>
T dec(const char* text) {
  return *eulervop::from_text<T>(text);
}

template <class T>
class Expression : public ::testing::Test {
 protected:
  // MPFR at 256 bits for the whole test; nothing for double and quad.
  std::optional<eulervop::mpfr_precision_scope> scope_ =
      std::is_same_v<T, mpfr_real> ? std::optional<eulervop::mpfr_precision_scope>(256) : std::nullopt;

  static T value(const char* text, const T& t, const vec3<T>& y, const expression_variables& vars = rates) {
    return compiled_expression<T>(parse_expression(text, vars))(t, y);
  }
  static T eps() { return eulervop::epsilon<T>(); }
  // A state with components of different sizes and signs: (0.3, 0.2, -0.9).
  static vec3<T> state() { return {dec<T>("0.3"), dec<T>("0.2"), dec<T>("-0.9")}; }
};
using Types = ::testing::Types<double, quad, mpfr_real>;
TYPED_TEST_SUITE(Expression, Types, scalar_test_names);

TYPED_TEST(Expression, ValuesEqualTheirClosedForms) {
  using T = TypeParam;
  using std::cos;
  using std::exp;
  using std::log;
  using std::sin;
  using std::sqrt;
  const T t = dec<T>("0.7");
  const vec3<T> y = this->state();
  // 0.25 (s s) = (s / 4) s exactly: scaling by 1/4 is exact.
  EXPECT_EQ(this->value("0.25*sin(t)^2", t, y), T(1) / 4 * sin(t) * sin(t));
  EXPECT_EQ(this->value("0.75*sin(t)^2", t, y), dec<T>("0.75") * (sin(t) * sin(t)));
  EXPECT_EQ(this->value("-0.1*omega1", t, y), -(dec<T>("0.1") * y[0]));
  EXPECT_EQ(this->value("3*pi", t, y), 3 * dec<T>(pi_100));
  EXPECT_EQ(this->value("exp(-tau/10)*cos(2*tau)", t, y, normalized), exp(-(t / 10)) * cos(2 * t));
  EXPECT_EQ(this->value("sqrt(omega1^2 + omega2^2) - log(1 + t)", t, y),
            sqrt(y[0] * y[0] + y[1] * y[1]) - log(1 + t));
  EXPECT_EQ(this->value("omega3^-2", t, y), 1 / (y[2] * y[2]));
  // Products named one by one: Boost's expression templates may reorder a longer product.
  const T c2 = y[2] * y[2], c3 = c2 * y[2], a2 = y[0] * y[0], a3 = a2 * y[0], a4 = a2 * a2, a5 = a4 * y[0];
  EXPECT_EQ(this->value("omega3^(-3) + omega1^+3", t, y), 1 / c3 + a3);
  // x^5 by binary powering: ((x x)^2) x.
  EXPECT_EQ(this->value("omega1^5", t, y), a5);
  EXPECT_EQ(this->value("omega2^0", t, y), T(1));
  EXPECT_EQ(this->value("Omega1 * Omega2 - Omega3 / tau", t, y, normalized), y[0] * y[1] - y[2] / t);
}

// tanh, atan, sinh and cosh: the program's value is T's own function (the same call, bit for bit),
// and that function agrees with an independent closed form: tanh x = (e^2x - 1) / (e^2x + 1),
// sinh x = (e^x - e^-x) / 2, cosh x = (e^x + e^-x) / 2, atan 1 = pi/4 and
// atan x + atan(1/x) = pi/2 for x > 0. Bounds, relative: each exp within an ulp (glibc and
// libquadmath measure below one, MPFR rounds correctly), each + - / within half of one, and the
// function itself within an ulp; e^1.4 - 1 = 3.06 amplifies exp's error by 4.06 / 3.06 and
// e^0.7 - e^-0.7 = 1.52 by 2.51 / 1.52, so the closed forms stand within 5 eps and the bound is
// 8 eps. atan: 4 atan(1) within 4 ulps of pi (scaling by 4 is exact) and the sum within 4 eps.
// Measured: at most 1.3 eps (sinh in double) and 1 eps (the sum in quad).
TYPED_TEST(Expression, HyperbolicAndArctangentMatchClosedForms) {
  using T = TypeParam;
  using std::abs;
  using std::atan;
  using std::cosh;
  using std::exp;
  using std::sinh;
  using std::tanh;
  const T t = dec<T>("0.7"), eps = this->eps(), pi = dec<T>(pi_100);
  const vec3<T> y = this->state();
  const T tanh_t = this->value("tanh(t)", t, y), sinh_t = this->value("sinh(t)", t, y);
  const T cosh_t = this->value("cosh(t)", t, y);
  EXPECT_EQ(tanh_t, tanh(t));
  EXPECT_EQ(sinh_t, sinh(t));
  EXPECT_EQ(cosh_t, cosh(t));
  EXPECT_EQ(this->value("atan(omega3)", t, y), atan(y[2]));
  EXPECT_EQ(this->value("-0.25*tanh(omega1/0.5)", t, y), -(tanh(y[0] / dec<T>("0.5")) / 4));
  const T e2 = exp(2 * t), e = exp(t), e_minus = exp(-t);
  EXPECT_LE(abs(tanh_t - (e2 - 1) / (e2 + 1)), 8 * eps * tanh_t);
  EXPECT_LE(abs(sinh_t - (e - e_minus) / 2), 8 * eps * sinh_t);
  EXPECT_LE(abs(cosh_t - (e + e_minus) / 2), 8 * eps * cosh_t);
  EXPECT_LE(abs(this->value("4*atan(1)", t, y) - pi), 4 * eps * pi);
  EXPECT_LE(abs(this->value("atan(omega1) + atan(1/omega1)", t, y) - pi / 2), 4 * eps);
  // Odd and even: the same magnitude on both sides, bit for bit (the functions are symmetric in
  // every library used).
  EXPECT_EQ(this->value("tanh(omega3) + tanh(-omega3)", t, y), T(0));
  EXPECT_EQ(this->value("cosh(omega3) - cosh(-omega3)", t, y), T(0));
  // Saturation: 1 - tanh 40 = 2 e^-80 / (1 + e^-80) = 3.6e-35, below half an ulp of 1 in double
  // and quad (tanh rounds to 1) and far above it in MPFR at 256 bits; never above 1.
  const T sat = this->value("tanh(40)", t, y), gap = 2 * exp(T(-80)) / (1 + exp(T(-80)));
  EXPECT_LE(sat, T(1));
  EXPECT_LE(abs((1 - sat) - gap), 2 * eps);
}

TYPED_TEST(Expression, DecimalsAreExactInT) {
  using T = TypeParam;
  const T t = 0;
  const vec3<T> y = this->state();
  EXPECT_EQ(this->value("0.1", t, y), dec<T>("0.1"));
  EXPECT_EQ(this->value(".5", t, y), T(1) / 2);
  EXPECT_EQ(this->value("2.5E+2", t, y), T(250));
  EXPECT_EQ(this->value("1e-3", t, y), dec<T>("0.001"));
  if constexpr (!std::is_same_v<T, double>) {
    // The decimal itself, not the double nearest to it.
    EXPECT_NE(this->value("0.1", t, y), T(0.1));
    EXPECT_NE(this->value("1e-3", t, y), T(1e-3));
  }
}

TYPED_TEST(Expression, PiToFullPrecision) {
  using T = TypeParam;
  using std::abs;
  const T pi = this->value("pi", T(0), this->state());
  EXPECT_EQ(pi, dec<T>(pi_100));
  EXPECT_LE(abs(pi - dec<T>(pi_100)), this->eps() * 2);  // says how far, should EQ fail
  if constexpr (std::is_same_v<T, mpfr_real>) {
    EXPECT_EQ(pi.precision(), T(0).precision());
  }
}

TYPED_TEST(Expression, Precedence) {
  using T = TypeParam;
  const T t = 2;
  const vec3<T> y = this->state();
  auto v = [&](const char* text) { return this->value(text, t, y); };
  EXPECT_EQ(v("-2^2"), T(-4));
  EXPECT_EQ(v("(-2)^2"), T(4));
  EXPECT_EQ(v("2-3-4"), T(-5));
  EXPECT_EQ(v("2/4/2"), T(1) / 4);
  EXPECT_EQ(v("2^3*2"), T(16));
  EXPECT_EQ(v("2*3+4*5"), T(26));
  EXPECT_EQ(v("2+3*4"), T(14));
  EXPECT_EQ(v("-2^-2"), -T(1) / 4);
  EXPECT_EQ(v("2^(-2)"), T(1) / 4);
  EXPECT_EQ(v("1+-2"), T(-1));
  EXPECT_EQ(v("--3"), T(3));
  EXPECT_EQ(v("2*-3"), T(-6));
  EXPECT_EQ(v("+t"), T(2));
  EXPECT_EQ(v("-t^2"), T(-4));
  EXPECT_EQ(v("(t^2)^3"), T(64));
  EXPECT_EQ(v(" 1 \t+\n2 "), T(3));
}

TYPED_TEST(Expression, NonFiniteValuesAreReturned) {
  using T = TypeParam;
  using std::isinf;
  using std::isnan;
  const vec3<T> y = {T(-1), T(0), T(0)};
  EXPECT_TRUE(isnan(this->value("log(omega1)", T(1), y)));
  EXPECT_TRUE(isnan(this->value("sqrt(omega1)", T(1), y)));
  EXPECT_TRUE(isinf(this->value("1/t", T(0), y)));
  EXPECT_TRUE(isinf(this->value("omega2^-1", T(0), y)));
  vec3<T> dy;
  EXPECT_TRUE(isnan(compiled_expression<T>(parse_expression("log(omega1)", rates)).value_and_gradient(T(1), y, dy)));
}

// Each operation's derivative rule against the derivative written by hand.
TYPED_TEST(Expression, GradientsMatchAnalyticDerivatives) {
  using T = TypeParam;
  using std::abs;
  using std::atan;
  using std::cos;
  using std::cosh;
  using std::exp;
  using std::log;
  using std::sin;
  using std::sinh;
  using std::sqrt;
  using std::tanh;
  const T t = dec<T>("0.7");
  const vec3<T> y = {dec<T>("0.3"), dec<T>("0.2"), dec<T>("0.9")};  // positive, for log and sqrt
  const T a = y[0], b = y[1], c = y[2], z = 0;
  auto check = [&](const char* text, const T& value, const vec3<T>& grad) {
    SCOPED_TRACE(text);
    const compiled_expression<T> f(parse_expression(text, rates));
    vec3<T> dy;
    const T v = f.value_and_gradient(t, y, dy);
    EXPECT_EQ(v, f(t, y));  // the same operations as the value alone
    EXPECT_LE(abs(v - value), 16 * this->eps() * (1 + abs(value)));
    for (int k = 0; k < 3; ++k) {
      const T err = abs(dy[k] - grad[k]) / (1 + abs(grad[k]));
      EXPECT_LE(err, 16 * this->eps()) << "d/dy" << k + 1;
    }
  };
  check("2.5", dec<T>("2.5"), {z, z, z});
  check("pi + t", dec<T>(pi_100) + t, {z, z, z});
  check("omega2", b, {z, T(1), z});
  check("omega1 + omega2", a + b, {T(1), T(1), z});
  check("omega1 - omega3", a - c, {T(1), z, T(-1)});
  check("omega1 * omega2", a * b, {b, a, z});
  check("omega1 / omega2", a / b, {1 / b, -a / (b * b), z});
  check("-omega3", -c, {z, z, T(-1)});
  check("omega1^0", T(1), {z, z, z});
  check("omega1^1", a, {T(1), z, z});
  check("omega1^2", a * a, {2 * a, z, z});
  check("omega1^3", a * a * a, {3 * a * a, z, z});
  check("omega3^7", c * c * c * c * c * c * c, {z, z, 7 * c * c * c * c * c * c});
  check("omega1^-1", 1 / a, {-1 / (a * a), z, z});
  check("omega1^-2", 1 / (a * a), {-2 / (a * a * a), z, z});
  check("omega2^-3", 1 / (b * b * b), {z, -3 / (b * b * b * b), z});
  check("sin(omega1)", sin(a), {cos(a), z, z});
  check("cos(omega2)", cos(b), {z, -sin(b), z});
  check("exp(omega3)", exp(c), {z, z, exp(c)});
  check("log(omega1)", log(a), {1 / a, z, z});
  check("sqrt(omega2)", sqrt(b), {z, 1 / (2 * sqrt(b)), z});
  // The program takes tanh' = 1 / cosh^2; here 1 - tanh^2, the other form.
  check("tanh(omega1)", tanh(a), {1 - tanh(a) * tanh(a), z, z});
  check("atan(omega2)", atan(b), {z, 1 / (1 + b * b), z});
  check("sinh(omega3)", sinh(c), {z, z, cosh(c)});
  check("cosh(omega1)", cosh(a), {sinh(a), z, z});
  // A saturation law, d/da -k tanh(a / s) = -(k / s) (1 - tanh(a / s)^2), with k = 0.5, s = 0.25.
  const T th = tanh(a / dec<T>("0.25"));
  check("-0.5*tanh(omega1/0.25)", -(dec<T>("0.5") * th), {-(dec<T>("0.5") / dec<T>("0.25")) * (1 - th * th), z, z});
  check("t * omega1", t * a, {t, z, z});
  // d/da (a b^2 / 2) = b^2 / 2, d/db = a b; d/dc (-sin c / a) = -cos c / a, d/da = sin c / a^2;
  // d/db exp(-t/10) cos(2 b) = -2 exp(-t/10) sin(2 b).
  const T e = exp(-t / 10);
  check("0.5*omega1*omega2^2 - sin(omega3)/omega1 + exp(-t/10)*cos(2*omega2)",
        a * b * b / 2 - sin(c) / a + e * cos(2 * b),
        {b * b / 2 + sin(c) / (a * a), a * b - 2 * e * sin(2 * b), -cos(c) / a});
  check("sqrt(log(omega1 * omega3)^2 + 1)", sqrt(log(a * c) * log(a * c) + 1),
        {log(a * c) / a / sqrt(log(a * c) * log(a * c) + 1), z, log(a * c) / c / sqrt(log(a * c) * log(a * c) + 1)});
}

// Deep in saturation tanh' x = 1 / cosh^2 x is tiny and 1 - tanh^2 x cancels (to 0 in double at
// x = 20, where tanh rounds to 1): the partial keeps its relative accuracy. Truth: 4 / (e^x + e^-x)^2
// at x = 20 and -30 (1.7e-17 and 3.5e-26), three roundings and two exps: within 8 eps of it.
// atan' x = 1 / (1 + x^2) at x = 1e5: 1e-10, within 4 eps. (Measured: equal in all three types.)
TYPED_TEST(Expression, SaturatedPartialsKeepTheirRelativeAccuracy) {
  using T = TypeParam;
  using std::abs;
  using std::exp;
  for (const char* x : {"20", "-30"}) {
    const vec3<T> y = {dec<T>(x), T(0), T(0)};
    vec3<T> dy;
    compiled_expression<T>(parse_expression("tanh(omega1)", rates)).value_and_gradient(T(0), y, dy);
    const T e = exp(y[0]) + exp(-y[0]), truth = 4 / (e * e);
    EXPECT_GT(dy[0], T(0)) << x;
    EXPECT_LE(abs(dy[0] - truth), 8 * this->eps() * truth) << x;
  }
  const vec3<T> y = {dec<T>("1e5"), T(0), T(0)};
  vec3<T> dy;
  compiled_expression<T>(parse_expression("atan(omega1)", rates)).value_and_gradient(T(0), y, dy);
  EXPECT_LE(abs(dy[0] - dec<T>("1e-10") / (1 + dec<T>("1e-10"))), 4 * this->eps() * dy[0]);
}

TEST(Expression, UsesBits) {
  const auto uses = [](const char* text, const expression_variables& vars = rates) {
    return parse_expression(text, vars);
  };
  const expression c = uses("3*pi + 0.25");
  EXPECT_EQ(c.uses, 0u);
  EXPECT_TRUE(c.is_constant());
  EXPECT_FALSE(c.uses_time());
  EXPECT_FALSE(c.uses_state());
  const expression time = uses("0.25*sin(t)^2");
  EXPECT_EQ(time.uses, 1u);
  EXPECT_TRUE(time.uses_time());
  EXPECT_FALSE(time.uses_state());
  EXPECT_FALSE(time.is_constant());
  const expression state = uses("-0.1*omega2");
  EXPECT_EQ(state.uses, 0b100u);
  EXPECT_FALSE(state.uses_time());
  EXPECT_TRUE(state.uses_state());
  EXPECT_EQ(uses("Omega1*Omega3 + tau", normalized).uses, 0b1011u);
  EXPECT_EQ(uses("t*omega1*omega2*omega3").uses, 0b1111u);
}

TEST(Expression, ProgramShape) {
  const expression e = parse_expression("1+(2+(3+4))", rates);
  EXPECT_EQ(e.stack_depth, 4u);
  EXPECT_EQ(e.text, "1+(2+(3+4))");
  const expression d = parse_expression("0.1 + 0.10*t + +1e-3", rates);
  // Canonical decimal texts (no '+'), each kept once.
  EXPECT_EQ(d.constants, (std::vector<std::string>{"0.1", "0.10", "1e-3"}));
  EXPECT_EQ(d.stack_depth, 3u);
  const expression p = parse_expression("t^-2", rates);
  ASSERT_EQ(p.code.size(), 2u);
  EXPECT_EQ(p.code[1].op, expression_op::pow);
  EXPECT_EQ(p.code[1].arg, -2);
  EXPECT_EQ(parse_expression("t^(+1000)", rates).code.back().arg, 1000);
  EXPECT_EQ(parse_expression("t^-1000", rates).code.back().arg, -1000);
  EXPECT_EQ(parse_expression("t^007", rates).code.back().arg, 7);
  // Each function is one step after its argument.
  const std::pair<const char*, expression_op> functions[] = {
      {"sin", expression_op::sin},   {"cos", expression_op::cos},   {"exp", expression_op::exp},
      {"log", expression_op::log},   {"sqrt", expression_op::sqrt}, {"tanh", expression_op::tanh},
      {"atan", expression_op::atan}, {"sinh", expression_op::sinh}, {"cosh", expression_op::cosh}};
  for (const auto& [name, op] : functions) {
    const expression f = parse_expression(std::string(name) + "(omega2)", rates);
    ASSERT_EQ(f.code.size(), 2u) << name;
    EXPECT_EQ(f.code[0].op, expression_op::variable) << name;
    EXPECT_EQ(f.code[1].op, op) << name;
    EXPECT_EQ(f.uses, 0b100u) << name;
  }
}

TEST(Expression, MalformedProgramsAreRefused) {
  expression e;
  e.text = "hand-made";
  e.code = {{expression_op::add}};
  EXPECT_THROW(compiled_expression<double>{e}, std::invalid_argument);
  e.code = {{expression_op::constant, 0}};
  EXPECT_THROW(compiled_expression<double>{e}, std::invalid_argument);  // no constants
  e.code = {{expression_op::variable, 8}};
  EXPECT_THROW(compiled_expression<double>{e}, std::invalid_argument);  // past q3 (slot 7)
  e.code = {{expression_op::variable, -1}};
  EXPECT_THROW(compiled_expression<double>{e}, std::invalid_argument);
  e.code = {{expression_op::pi}, {expression_op::pi}};
  EXPECT_THROW(compiled_expression<double>{e}, std::invalid_argument);  // two values left
  e.code = {};
  EXPECT_THROW(compiled_expression<double>{e}, std::invalid_argument);
  e.code = {{expression_op::pi}, {expression_op::pi}, {expression_op::mul}};
  EXPECT_NO_THROW(compiled_expression<double>{e});  // stack_depth 0 given: computed anew
}

// ---- errors ---------------------------------------------------------------------------------

// The parse throws expression_error: one line holding `kind`, naming the culprit and its column.
void expect_error(std::string_view text, std::string_view kind, const std::string& culprit, std::size_t column,
                  const expression_variables& vars = rates) {
  SCOPED_TRACE(std::string("text: ") + std::string(text));
  try {
    parse_expression(text, vars);
    ADD_FAILURE() << "no error";
  } catch (const expression_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(kind), std::string::npos) << what;
    EXPECT_EQ(e.culprit(), culprit) << what;
    EXPECT_EQ(e.column(), column) << what;
    EXPECT_EQ(what.find_first_of("\n\r"), std::string::npos) << what;
    if (!culprit.empty()) {
      EXPECT_NE(what.find("`" + culprit + "` at column " + std::to_string(column)), std::string::npos) << what;
    }
  }
}

TEST(ExpressionErrors, EmptyExpression) {
  expect_error("", "empty expression", "", 1);
  expect_error("  \t ", "empty expression", "", 1);
}

TEST(ExpressionErrors, UnknownIdentifier) {
  expect_error("-0.1*omega1", "unknown identifier `omega1` at column 6", "omega1", 6, time_only);
  expect_error("2*omega4", "unknown identifier", "omega4", 3);
  expect_error("Omega1", "unknown identifier", "Omega1", 1);  // case matters: not omega1
  expect_error("t + tau", "unknown identifier", "tau", 5);
  expect_error("PI", "unknown identifier", "PI", 1);
}

TEST(ExpressionErrors, UnknownFunction) {
  expect_error("foo(t)", "unknown function", "foo", 1);
  expect_error("2*tan (t)", "unknown function", "tan", 3);
  expect_error("t(2)", "unknown function", "t", 1);
  expect_error("sin t", "missing `(` after function", "sin", 1);
  expect_error("1 + exp", "missing `(` after function", "exp", 5);
  expect_error("tanh t", "missing `(` after function", "tanh", 1);
  expect_error("Tanh(t)", "unknown function", "Tanh", 1);  // case matters
  expect_error("atanh(t)", "the functions are sin, cos, exp, log, sqrt, tanh, atan, sinh and cosh", "atanh", 1);
}

TEST(ExpressionErrors, UnbalancedParentheses) {
  expect_error("(1+t", "unbalanced parentheses: missing `)`", "(", 1);
  expect_error("2*(1+(t)", "unbalanced parentheses: missing `)`", "(", 3);
  expect_error("sin(t", "unbalanced parentheses: missing `)`", "(", 4);
  expect_error("(", "unbalanced parentheses: missing `)`", "(", 1);
  expect_error("1+t)", "unbalanced parentheses: unexpected", ")", 4);
  expect_error(")", "unbalanced parentheses: unexpected", ")", 1);
  expect_error("(t))", "unbalanced parentheses: unexpected", ")", 4);
  expect_error("2*()", "empty parentheses", "()", 3);
}

TEST(ExpressionErrors, DanglingOperator) {
  expect_error("2*", "dangling operator", "*", 2);
  expect_error("*2", "dangling operator", "*", 1);
  expect_error("2**3", "dangling operator", "*", 3);
  expect_error("2 + ", "dangling operator", "+", 3);
  expect_error("-", "dangling operator", "-", 1);
  expect_error("(2/)", "dangling operator", "/", 3);
  expect_error("t^", "dangling operator", "^", 2);
  expect_error("^2", "dangling operator", "^", 1);
  expect_error("sin(t,)", "missing argument after", ",", 6);
}

TEST(ExpressionErrors, TwoOperandsInARow) {
  expect_error("2 t", "two operands in a row", "t", 3);
  expect_error("2t", "two operands in a row", "t", 2);
  expect_error("t 2", "two operands in a row", "2", 3);
  expect_error("2 (t)", "two operands in a row", "(", 3);
  expect_error("(t)(t)", "two operands in a row", "(", 4);
  expect_error("2exp(t)", "two operands in a row", "exp", 2);
  expect_error("t^2 t", "two operands in a row", "t", 5);
}

TEST(ExpressionErrors, UnexpectedCharacter) {
  expect_error("2#", "unexpected character", "#", 2);
  expect_error("t = 1", "unexpected character", "=", 3);
  expect_error("1,2", "unexpected `,`", ",", 2);
  expect_error("2 \xc3\xa9", "unexpected character", "\xc3\xa9", 3);  // whole UTF-8 character
  expect_error("\xc3\xa9 + t", "unexpected character", "\xc3\xa9", 1);
  expect_error("t+\x01", "unexpected character", "\\x01", 3);   // control characters escaped
  expect_error("t+\xff", "unexpected character", "\\xff", 3);   // and invalid UTF-8
  expect_error("t+\n#", "unexpected character", "#", 4);       // a newline is a blank
  expect_error(std::string_view("t+\0", 3), "unexpected character", "\\x00", 3);
}

TEST(ExpressionErrors, BadNumber) {
  expect_error("1.2.3", "invalid number", "1.2.3", 1);
  expect_error("2*1e", "invalid number", "1e", 3);
  expect_error("1e+", "invalid number", "1e+", 1);
  expect_error(".", "invalid number", ".", 1);
  expect_error("1e999", "out of the range of a double", "1e999", 1);
  expect_error("t + 1e-999", "out of the range of a double", "1e-999", 5);
}

TEST(ExpressionErrors, NonIntegerPower) {
  expect_error("t^0.5", "non-integer power", "0.5", 3);
  expect_error("t^t", "non-integer power", "t", 3);
  expect_error("t^(1/2)", "non-integer power", "(1/2)", 3);
  expect_error("t^-t", "non-integer power", "-t", 3);
  expect_error("t^ 2.0", "non-integer power", "2.0", 4);
  expect_error("t^sin(t)", "non-integer power", "sin(t)", 3);
  expect_error("t^(2", "unbalanced parentheses: missing `)`", "(", 3);
  expect_error("t^(1/)", "dangling operator", "/", 5);
}

TEST(ExpressionErrors, ChainedPower) {
  expect_error("t^2^3", "chained power", "^", 4);
  expect_error("(t^2)^3^4", "chained power", "^", 8);
  expect_error("t^(2)^3", "chained power", "^", 6);
}

TEST(ExpressionErrors, PowerTooLarge) {
  expect_error("t^1001", "power too large", "1001", 3);
  expect_error("t^-1001", "power too large", "-1001", 3);
  expect_error("t^(-5000)", "power too large", "(-5000)", 3);
  expect_error("t^99999999999999999999999", "power too large", "99999999999999999999999", 3);
}

TEST(ExpressionErrors, ArgumentCount) {
  expect_error("sin()", "sin takes 1 argument, got 0", "sin()", 1);
  expect_error("2*sin(t, 1)", "sin takes 1 argument, got 2", "sin(t, 1)", 3);
  expect_error("sqrt(t,t,t)", "sqrt takes 1 argument, got 3", "sqrt(t,t,t)", 1);
  expect_error("atan(omega2, omega1)", "atan takes 1 argument, got 2", "atan(omega2, omega1)", 1);  // no atan2
}

TEST(ExpressionErrors, Limits) {
  // Length: 4096 bytes parse, 4097 do not.
  std::string text = "1";
  while (text.size() + 2 <= eulervop::scene::max_expression_length) text += "+1";
  text += " ";
  ASSERT_EQ(text.size(), 4096u);
  EXPECT_NO_THROW(parse_expression(text, rates));
  text += " ";
  expect_error(text, "expression too long", "", 4097);
  // Nesting: 64 parentheses parse, 65 do not.
  const auto nested = [](std::size_t n) { return std::string(n, '(') + "t" + std::string(n, ')'); };
  EXPECT_NO_THROW(parse_expression(nested(64), rates));
  expect_error(nested(65), "nesting too deep", "(", 65);
  expect_error("sin(" + nested(64) + ")", "nesting too deep", "(", 68);  // sin's own counts
  // Signs are a loop, not a recursion: thousands of them are fine.
  EXPECT_NO_THROW(parse_expression(std::string(4000, '-') + "t", rates));
}

// Short random texts over the grammar's characters: each parses into a well-formed program
// (compiled_expression checks it) or throws expression_error, never anything else.
TEST(ExpressionErrors, RandomTextsParseOrThrowExpressionError) {
  const std::vector<std::string> pieces = {"t", "omega1", "omega3", "pi", "sin", "cos", "log", "(", ")", "(",
                                           ")", "+", "-", "*", "/", "^", "2", "0.5", "1e3", ".", ",", " ",
                                           "e", "x", "#", "-1", "sqrt(", "exp(", "tanh(", "atan", "sinh(", "cosh"};
  std::mt19937 rng(20240501);
  std::uniform_int_distribution<std::size_t> piece(0, pieces.size() - 1), length(0, 12);
  int parsed = 0;
  for (int i = 0; i < 20000; ++i) {
    std::string text;
    for (std::size_t n = length(rng); n > 0; --n) text += pieces[piece(rng)];
    try {
      const expression e = parse_expression(text, rates);
      const compiled_expression<double> f(e);
      vec3<double> dy;
      (void)f.value_and_gradient(0.5, {0.1, 0.2, 0.3}, dy);
      ++parsed;
    } catch (const expression_error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << text;
      EXPECT_GE(e.column(), 1u) << text;
      EXPECT_LE(e.column(), text.size() + 1) << text;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "`" << text << "`: " << e.what();
    }
  }
  EXPECT_GT(parsed, 100);  // the sweep reaches valid expressions too
}

}  // namespace
