// The pieces of the general path's field (include/eulervop/certify/detail/field_algebra.hpp: a
// formula's program step by step) and of its elementary functions of a model
// (chebyshev_composition.hpp: the Bernstein ellipse, its disk and the interpolation's bound),
// tested as an adversary would: every enclosure must hold the exact value.
//
// Truth: Arb at 2000 bits evaluating the same functions directly at points (no Chebyshev model,
// no composition), so that its own radius is far below any radius here; the disk's bound against
// sum c_k T_k(z) at points z of the ellipse, T_k(z) = (w^k + w^-k) / 2 for z = (w + 1/w) / 2,
// |w| = rho (Trefethen, Approximation Theory and Approximation Practice, SIAM 2013, chapter 8).
#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_composition.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/field_algebra.hpp>
#include <eulervop/scene/expression_parser.hpp>

#include <gtest/gtest.h>

#include <acb.h>
#include <arb.h>

#include <string>
#include <vector>

namespace {

using eulervop::ball;
using eulervop::mag_value;
using eulervop::detail::chebyshev_model;
using eulervop::detail::elementary;

constexpr slong truth_prec = 2000;

eulervop::expression parse(const std::string& text) {
  eulervop::scene::expression_variables v;
  v.names[0] = "t";
  v.names[1] = "y1";
  v.names[2] = "y2";
  v.names[3] = "y3";
  return eulervop::scene::parse_expression(text, v);
}

// An exact model sum c_k T_k with c_k = num_k / 64.
chebyshev_model exact_model(const std::vector<long>& num) {
  chebyshev_model m(static_cast<slong>(num.size()));
  for (std::size_t k = 0; k < num.size(); ++k) {
    arb_set_si(m.coeff(static_cast<slong>(k)), num[k]);
    arb_mul_2exp_si(m.coeff(static_cast<slong>(k)), m.coeff(static_cast<slong>(k)), -6);
  }
  return m;
}

// sum_k c_k T_k(s) at 2000 bits (s exact in [-1, 1]).
void value_at(ball& out, const chebyshev_model& m, const ball& s) {
  eulervop::detail::evaluate(out, m, s, truth_prec);
}

bool contains(const ball& enclosure, const ball& truth) { return arb_contains(enclosure.get(), truth.get()) != 0; }

// The formula f = 5/2 y1 y2 / (y3 + 3) - sin(y1)^2 + exp(-y2) / 2 + (1 + 1/4)^-2 y3^3 at 2000 bits,
// and its partial by y1, 5/2 y2 / (y3 + 3) - 2 sin(y1) cos(y1).
void formula_truth(ball& f, ball& d1, const ball& y1, const ball& y2, const ball& y3) {
  const slong p = truth_prec;
  ball t, u, s, c;
  arb_add_ui(u.get(), y3.get(), 3, p);
  arb_mul(t.get(), y1.get(), y2.get(), p);
  arb_mul_ui(t.get(), t.get(), 5, p);
  arb_mul_2exp_si(t.get(), t.get(), -1);
  arb_div(f.get(), t.get(), u.get(), p);
  arb_sin_cos(s.get(), c.get(), y1.get(), p);
  arb_submul(f.get(), s.get(), s.get(), p);
  arb_neg(t.get(), y2.get());
  arb_exp(t.get(), t.get(), p);
  arb_mul_2exp_si(t.get(), t.get(), -1);
  arb_add(f.get(), f.get(), t.get(), p);
  arb_pow_ui(t.get(), y3.get(), 3, p);
  arb_mul_ui(t.get(), t.get(), 16, p);  // (5/4)^-2 = 16/25
  arb_div_ui(t.get(), t.get(), 25, p);
  arb_add(f.get(), f.get(), t.get(), p);
  arb_mul_ui(d1.get(), y2.get(), 5, p);
  arb_mul_2exp_si(d1.get(), d1.get(), -1);
  arb_div(d1.get(), d1.get(), u.get(), p);
  arb_mul(t.get(), s.get(), c.get(), p);
  arb_mul_2exp_si(t.get(), t.get(), 1);
  arb_sub(d1.get(), d1.get(), t.get(), p);
}

TEST(FieldFormula, ValueAndPartialAlongModelsHoldTheFormulaAtEveryPoint) {
  const eulervop::expression e = parse("2.5*y1*y2/(y3 + 3) - sin(y1)^2 + exp(-y2)/2 + (1 + 1/4)^-2 * y3^3");
  const slong prec = 177;
  const eulervop::detail::ball_formula formula(e, prec);
  const eulervop::detail::series_algebra alg(prec, 3);
  const std::vector<chebyshev_model> P = {exact_model({40, -13, 5, 2, -1}), exact_model({-20, 31, 0, -3}),
                                          exact_model({70, 9, -4, 1, 1, -1})};
  std::vector<eulervop::detail::series_jet> x;
  for (std::size_t k = 0; k < 3; ++k) x.push_back(alg.variable(P[k], k));
  eulervop::detail::formula_variables<eulervop::detail::series_algebra> vars;
  for (std::size_t k = 0; k < 3; ++k) vars.state[k] = &x[k];
  const eulervop::detail::series_jet F = formula(alg, vars);
  ASSERT_EQ(F.d.size(), 3u);
  for (int j = -16; j <= 16; ++j) {  // s = j / 16, exact
    ball s(j), y1, y2, y3, truth, dtruth, got, dgot;
    arb_mul_2exp_si(s.get(), s.get(), -4);
    value_at(y1, P[0], s);
    value_at(y2, P[1], s);
    value_at(y3, P[2], s);
    formula_truth(truth, dtruth, y1, y2, y3);
    eulervop::detail::evaluate(got, F.f, s, prec);
    eulervop::detail::evaluate(dgot, F.d[0], s, prec);
    EXPECT_TRUE(contains(got, truth)) << "s = " << j << "/16";
    EXPECT_TRUE(contains(dgot, dtruth)) << "s = " << j << "/16";
    // Tight: the value's radius far below its size (2^-100; the products' grids are 145 bits).
    mag_value r, m;
    arb_get_mag(m.m, truth.get());
    mag_mul_2exp_si(m.m, m.m, -100);
    mag_set(r.m, arb_radref(got.get()));
    EXPECT_LE(mag_cmp(r.m, m.m), 0) << "s = " << j << "/16";
  }
}

// Squares of sin and cos, which the series algebra evaluates as (1 -+ cos 2u) / 2: of the time
// (linear, the closed form of trig_of_linear.hpp) and of a state (interpolated), value and
// partial, against the formula evaluated directly at 2000 bits: 0.25 sin(t)^2 + cos(y2)^2, whose
// partial by y2 is -2 sin(y2) cos(y2).
TEST(FieldFormula, SquaresOfSinAndCosHoldTheirValues) {
  const eulervop::expression e = parse("0.25*sin(t)^2 + cos(y2)^2");
  const slong prec = 177;
  const eulervop::detail::ball_formula formula(e, prec);
  const eulervop::detail::series_algebra alg(prec, 3);
  const chebyshev_model time = exact_model({64 * 37, 64 * 3 / 10});  // t = 37 + 0.296875 s
  const std::vector<chebyshev_model> P = {exact_model({40, -13}), exact_model({-20, 31, 0, -3}), exact_model({70})};
  std::vector<eulervop::detail::series_jet> x;
  for (std::size_t k = 0; k < 3; ++k) x.push_back(alg.variable(P[k], k));
  const eulervop::detail::series_jet tv = alg.independent(time);
  eulervop::detail::formula_variables<eulervop::detail::series_algebra> vars;
  vars.time = &tv;
  for (std::size_t k = 0; k < 3; ++k) vars.state[k] = &x[k];
  const eulervop::detail::series_jet F = formula(alg, vars);
  for (int j = -16; j <= 16; ++j) {  // s = j / 16, exact
    ball s(j), t, y2, st, ct, sy, cy, truth, dtruth, got, dgot;
    arb_mul_2exp_si(s.get(), s.get(), -4);
    value_at(t, time, s);
    value_at(y2, P[1], s);
    arb_sin_cos(st.get(), ct.get(), t.get(), truth_prec);
    arb_sin_cos(sy.get(), cy.get(), y2.get(), truth_prec);
    arb_mul(truth.get(), st.get(), st.get(), truth_prec);
    arb_mul_2exp_si(truth.get(), truth.get(), -2);
    arb_addmul(truth.get(), cy.get(), cy.get(), truth_prec);
    arb_mul(dtruth.get(), sy.get(), cy.get(), truth_prec);
    arb_mul_si(dtruth.get(), dtruth.get(), -2, truth_prec);
    eulervop::detail::evaluate(got, F.f, s, prec);
    eulervop::detail::evaluate(dgot, F.d[1], s, prec);
    EXPECT_TRUE(contains(got, truth)) << "s = " << j << "/16";
    EXPECT_TRUE(contains(dgot, dtruth)) << "s = " << j << "/16";
    EXPECT_TRUE(F.d[0].is_zero() && F.d[2].is_zero());
    mag_value r, m;  // tight: 2^-130 of the value's size
    arb_get_mag(m.m, truth.get());
    mag_mul_2exp_si(m.m, m.m, -130);
    mag_set(r.m, arb_radref(got.get()));
    EXPECT_LE(mag_cmp(r.m, m.m), 0) << "s = " << j << "/16";
  }
}

TEST(FieldFormula, ConstantsFoldAsArbEvaluatesThem) {
  // ball_formula keeps a pointer to its expression: the expression outlives it.
  const eulervop::expression e = parse("(1 + 1/4)^-2 * pi - sqrt(2)/3 + log(7) * cosh(1/2)");
  const eulervop::detail::ball_formula formula(e, 200);
  ASSERT_TRUE(formula.is_constant());
  const ball got = formula.constant_value(200);
  ball truth, t;  // 16/25 pi - sqrt(2) / 3 + log(7) cosh(1/2) at 2000 bits
  arb_const_pi(truth.get(), truth_prec);
  arb_mul_ui(truth.get(), truth.get(), 16, truth_prec);
  arb_div_ui(truth.get(), truth.get(), 25, truth_prec);
  arb_sqrt_ui(t.get(), 2, truth_prec);
  arb_div_ui(t.get(), t.get(), 3, truth_prec);
  arb_sub(truth.get(), truth.get(), t.get(), truth_prec);
  arb_log_ui(t.get(), 7, truth_prec);
  ball half(1), c;
  arb_mul_2exp_si(half.get(), half.get(), -1);
  arb_cosh(c.get(), half.get(), truth_prec);
  arb_addmul(truth.get(), t.get(), c.get(), truth_prec);
  EXPECT_TRUE(contains(got, truth));
  EXPECT_LT(arb_rel_accuracy_bits(got.get()), 201);
  EXPECT_GT(arb_rel_accuracy_bits(got.get()), 190);
}

// The message of the error a formula throws over the box y1 in [-1/2, 1/2], y2 = y3 = 1.
std::string refusal(const std::string& text) {
  const eulervop::expression e = parse(text);
  const eulervop::detail::ball_formula formula(e, 64);
  const eulervop::detail::box_algebra alg(64, 3);
  ball y1;
  mag_set_ui_2exp_si(arb_radref(y1.get()), 1, -1);
  const auto x1 = alg.variable(y1, 0), x2 = alg.variable(ball(1), 1), x3 = alg.variable(ball(1), 2);
  eulervop::detail::formula_variables<eulervop::detail::box_algebra> vars;
  vars.state = {&x1, &x2, &x3};
  try {
    (void)formula(alg, vars);
  } catch (const eulervop::undefined_formula& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(FieldFormula, UndefinedStepsNameTheFormulaAndTheCause) {
  EXPECT_EQ(refusal("log(y1) + y2"), "`log(y1) + y2`: the log of a value that is not certainly positive");
  EXPECT_EQ(refusal("y2/y1"), "`y2/y1`: a division by a value that may be 0");
  EXPECT_EQ(refusal("y1^-2"), "`y1^-2`: a division by a value that may be 0");
  EXPECT_EQ(refusal("y2/(1 - 1)"), "`y2/(1 - 1)`: a division by a number that may be 0");
  EXPECT_EQ(refusal("y2 + 1/(2 - 2)"), "`y2 + 1/(2 - 2)`: a division by a number that may be 0");
  EXPECT_EQ(refusal("y3 * (2 - 2)^-3"), "`y3 * (2 - 2)^-3`: a negative power of a number that may be 0");
  EXPECT_EQ(refusal("y2 + log(1 - 1)"), "`y2 + log(1 - 1)`: the log of a number that is not certainly positive");
  EXPECT_EQ(refusal("sqrt(y2) * y1^0 + y1"), "(no error)");
}

TEST(ChebyshevComposition, EllipseDiskHoldsThePolynomialOnTheEllipse) {
  const std::vector<long> num = {7, -30, 11, 5, -9, 2, 1, -1};
  const chebyshev_model u = exact_model(num);
  std::vector<mag_value> c(num.size());
  for (std::size_t k = 1; k < num.size(); ++k) arb_get_mag(c[k].m, u.coeff(static_cast<slong>(k)));
  for (const double rho : {1.5, 4.0, 32.0}) {
    mag_value B;
    eulervop::detail::ellipse_disk_radius(B.m, c, rho);
    ball Bb;
    arf_set_mag(arb_midref(Bb.get()), B.m);
    // Tight: B is sum |c_k| (rho^k + rho^-k) / 2 itself (the largest |S| on the ellipse, at w = rho
    // for positive c_k), rounded up by at most 2^-20 of it (mags carry 30 bits).
    ball exact, r, term;
    for (std::size_t k = 1; k < num.size(); ++k) {
      arb_set_d(r.get(), rho);
      arb_pow_ui(term.get(), r.get(), k, truth_prec);
      arb_inv(r.get(), term.get(), truth_prec);
      arb_add(term.get(), term.get(), r.get(), truth_prec);
      arb_mul_si(term.get(), term.get(), num[k] < 0 ? -num[k] : num[k], truth_prec);
      arb_mul_2exp_si(term.get(), term.get(), -7);  // c_k = num_k / 64, halved
      arb_add(exact.get(), exact.get(), term.get(), truth_prec);
    }
    EXPECT_TRUE(arb_le(exact.get(), Bb.get())) << "rho " << rho;
    arb_mul_2exp_si(r.get(), exact.get(), -20);
    arb_add(r.get(), r.get(), exact.get(), truth_prec);
    EXPECT_TRUE(arb_le(Bb.get(), r.get())) << "rho " << rho;
    for (int j = 0; j < 64; ++j) {  // w = rho e^(i pi j / 32): S = sum_{k>=1} c_k (w^k + w^-k) / 2
      acb_t w, wk, wi, S, t;
      for (acb_ptr z : {w, wk, wi, S, t}) acb_init(z);
      acb_set_d(w, rho);
      acb_set_si(t, j);
      acb_div_ui(t, t, 32, truth_prec);
      acb_exp_pi_i(t, t, truth_prec);
      acb_mul(w, w, t, truth_prec);
      acb_one(wk);
      acb_one(wi);
      acb_zero(S);
      acb_inv(t, w, truth_prec);
      for (std::size_t k = 1; k < num.size(); ++k) {
        acb_mul(wk, wk, w, truth_prec);
        acb_mul(wi, wi, t, truth_prec);
        acb_t term;
        acb_init(term);
        acb_add(term, wk, wi, truth_prec);
        acb_mul_2exp_si(term, term, -1);
        acb_mul_arb(term, term, u.coeff(static_cast<slong>(k)), truth_prec);
        acb_add(S, S, term, truth_prec);
        acb_clear(term);
      }
      ball absS;
      acb_abs(absS.get(), S, truth_prec);
      EXPECT_TRUE(arb_le(absS.get(), Bb.get())) << "rho " << rho << ", j " << j;
      for (acb_ptr z : {w, wk, wi, S, t}) acb_clear(z);
    }
  }
}

TEST(ChebyshevComposition, ChosenEllipseMeetsTheTargetWithTheLeastPointsForItsRho) {
  const double log2_target = -150;
  const ball zero;
  for (const elementary f : {elementary::exp, elementary::sin, elementary::inverse, elementary::atan}) {
    chebyshev_model u = exact_model({f == elementary::inverse ? 192 : 10, 40, -6, 3, 1});
    if (f == elementary::atan) arb_mul_2exp_si(u.coeff(1), u.coeff(1), -3);  // away from the cuts at |Im| >= 1
    const eulervop::detail::ellipse_choice e = eulervop::detail::choose_ellipse(f, u, log2_target, 300);
    ASSERT_GT(e.n, 0u) << static_cast<int>(f);
    mag_value rem;
    eulervop::detail::composition_remainder(rem.m, e, e.n, zero, u);
    EXPECT_LE(mag_get_d_log2_approx(rem.m), log2_target + 1e-6) << static_cast<int>(f);
    if (e.n > 9) {  // two points fewer miss it by at least rho^2 >= 2.25 (the least n: ceil)
      eulervop::detail::composition_remainder(rem.m, e, e.n - 2, zero, u);
      EXPECT_GT(mag_get_d_log2_approx(rem.m), log2_target) << static_cast<int>(f);
    }
  }
}

TEST(ChebyshevComposition, NoEllipseGivesTheRangeAsAConstantAndARemainder) {
  // u = 1 + 63/64 T_1: its range [1/64, 127/64] is positive, but already the disk of rho = 1.5
  // (radius 63/64 (1.5 + 1/1.5) / 2 > 1) reaches 0, where log is not analytic.
  const chebyshev_model u = exact_model({64, 63});
  chebyshev_model out;
  eulervop::detail::compose(out, elementary::log, u, 200, 150);
  ASSERT_EQ(out.length(), 1);
  for (int j = -8; j <= 8; ++j) {
    ball s(j), x, truth, got;
    arb_mul_2exp_si(s.get(), s.get(), -3);
    value_at(x, u, s);
    arb_log(truth.get(), x.get(), truth_prec);
    eulervop::detail::evaluate(got, out, s, 200);
    EXPECT_TRUE(contains(got, truth)) << "s = " << j << "/8";
  }
}

}  // namespace
