// The kernels of the general path of --certify (include/eulervop/certify/: chebyshev_composition.hpp
// with trig_of_linear.hpp,
// field_algebra.hpp, certification_problem.hpp, ball_lohner_box.hpp, ball_linear_flow.hpp,
// jacobi_enclosure.hpp; the models themselves in test_chebyshev_model.cpp),
// tested as an adversary would: every enclosure must hold the exact value of every function the
// model stands for, at random and extreme inputs.
//
// Truth: MPFR at 1000 bits (about 300 digits, so that its own rounding is far below any radius
// here), evaluating the functions a model stands for directly: Chebyshev sums with coefficients
// chosen at the ends of their balls, plus a function of size up to the remainder (rem sin(17 s + 1)).
// Exact closed forms where there are some: the interpolant at the Lobatto nodes reproduces a
// polynomial of its degree; the Hessian of Eq. 5 is constant. The linear flow's exact solutions
// are Taylor series at 1000 bits (the Jacobian a polynomial, so the solutions are entire), and
// the 128-bit sums are checked against FLINT's exact products. Jacobi's functions (the initial
// state of Eq. 12) against Boost.Math's jacobi_elliptic at 1000 bits, an independent method (the
// descending Landen transformation, not theta functions).
#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/certification_problem.hpp>
#include <eulervop/certify/detail/ball_linear_flow.hpp>
#include <eulervop/certify/detail/ball_lohner_box.hpp>
#include <eulervop/certify/detail/chebyshev_composition.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/field_algebra.hpp>
#include <eulervop/certify/jacobi_enclosure.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/scene/expression_parser.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_certification_problem.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>

#include "ball_test_support.hpp"

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace eulervop::test::ball_support;

// An elementary function of a model (chebyshev_composition.hpp): the model of f(u) holds f of every
// function u stands for (its coefficients at the ends of their balls, plus a remainder), and where
// u has no remainder its own remainder reaches the target asked for (for an entire f); a range that
// leaves f's domain is refused.
TEST(ChebyshevComposition, HoldsEveryFunctionOfEveryModel) {
  using eulervop::detail::elementary;
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(17);
  const auto exact_f = [](elementary f, const mpfr_real& x) -> mpfr_real {
    switch (f) {
      case elementary::sin: return sin(x);
      case elementary::cos: return cos(x);
      case elementary::exp: return exp(x);
      case elementary::log: return log(x);
      case elementary::sqrt: return sqrt(x);
      case elementary::tanh: return tanh(x);
      case elementary::atan: return atan(x);
      case elementary::sinh: return sinh(x);
      case elementary::cosh: return cosh(x);
      default: return 1 / x;
    }
  };
  for (const elementary f : {elementary::sin, elementary::cos, elementary::exp, elementary::log, elementary::sqrt,
                             elementary::tanh, elementary::atan, elementary::sinh, elementary::cosh, elementary::inverse})
    for (int trial = 0; trial < 6; ++trial) {
      const bool exact = trial < 3;
      chebyshev_model u = random_model(rng, 2 + static_cast<slong>(rng() % 30), 0.35, exact ? 0 : 90, exact ? 0 : 1e-20);
      if (f == elementary::tanh || f == elementary::atan) {
        // u's variation a quarter of the others' (sum |c_k| (1.5^k + 1.5^-k) / 2 <= 0.6 < 1): the
        // ellipse rho = 1.5 then avoids the poles and cuts at |Im| >= 1 wherever c_0 lies, so the
        // target below is reachable. (PolesAndBranchCutsAreAvoided tests the ranges near them.)
        for (slong k = 1; k < u.length(); ++k) arb_mul_2exp_si(u.coeff(k), u.coeff(k), -2);
      }
      if (f == elementary::log || f == elementary::sqrt || f == elementary::inverse) {
        // Shift u to [1/2, ...) or, for 1/x, alternately below -1/2.
        mag_value m;
        eulervop::detail::coefficient_magnitude(m.m, u, 1);
        mag_add(m.m, m.m, u.remainder());
        ball shift;
        arf_set_mag(arb_midref(shift.get()), m.m);
        arb_add_ui(shift.get(), shift.get(), 1, 300);
        arb_set_round(shift.get(), shift.get(), 60);
        mag_zero(arb_radref(shift.get()));
        if (f == elementary::inverse && trial % 2) arb_neg(shift.get(), shift.get());
        arb_set(u.coeff(0), shift.get());
      }
      chebyshev_model out;
      eulervop::detail::compose(out, f, u, 300, 240);
      if (exact) {
        ball range, fr;
        eulervop::detail::range_of(range, u);
        ASSERT_TRUE(eulervop::detail::elementary_on_ball(f, range, &fr, nullptr, nullptr, 300));
        // The target for the entire functions; near a singularity (log, sqrt, 1/x of a u whose
        // variation is comparable to its distance from 0) the ellipse is small and 256 points give
        // less, still 2^-100.
        const bool entire = f == elementary::sin || f == elementary::cos || f == elementary::exp ||
                            f == elementary::sinh || f == elementary::cosh;
        mag_value target;
        arb_get_mag(target.m, fr.get());
        mag_mul_2exp_si(target.m, target.m, entire ? -230 : -100);
        EXPECT_LE(mag_cmp(out.remainder(), target.m), 0) << "f " << static_cast<int>(f) << " trial " << trial;
      }
      for (int pick_round = 0; pick_round < 3; ++pick_round) {
        const represented fu = pick(u, rng);
        for (const mpfr_real& sp : points(rng)) {
          ball v;
          eulervop::detail::evaluate(v, out, point(sp), truth_bits);
          ASSERT_TRUE(holds(v, exact_f(f, fu(sp)))) << "f " << static_cast<int>(f) << " trial " << trial << " s " << sp;
        }
      }
    }
  // Ranges that leave the domain.
  chebyshev_model u = random_model(rng, 8, 0.5, 0, 0);
  arb_zero(u.coeff(0));  // a range around 0
  chebyshev_model out;
  EXPECT_THROW(eulervop::detail::compose(out, elementary::log, u, 300, 240), std::domain_error);
  EXPECT_THROW(eulervop::detail::compose(out, elementary::sqrt, u, 300, 240), std::domain_error);
  EXPECT_THROW(eulervop::detail::compose(out, elementary::inverse, u, 300, 240), std::domain_error);
}

// sin and cos of a linear model c0 + c1 s (trig_of_linear.hpp: the closed form in Bessel
// functions that compose() takes for the time): the model holds f(c0 + c1 s) for every c0, c1 in
// their balls (MPFR at 1000 bits, at the ends and the middles of the balls), meets the target, and
// is refused (the interpolation's path then) where c1 may be 0, is beyond 4, or the model has a
// remainder. Slopes from 1e-12 to 4 and both signs, offsets up to 1e5, with and without radii.
TEST(ChebyshevComposition, SinAndCosOfALinearModelInClosedForm) {
  using eulervop::detail::elementary;
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> unit(-1, 1);
  int cases = 0;
  for (const double slope : {1e-12, 1e-3, 0.05, 0.1, 0.7, 1.0, 2.5, 3.9, -0.3, -3.5})
    for (const double offset : {0.0, 0.4, -2.0, 31.4, 1e5}) {
      const bool radius = (cases++) % 2 == 1;
      chebyshev_model u;
      u.resize(2);
      arb_set_d(u.coeff(0), offset + unit(rng));
      arb_set_d(u.coeff(1), slope * (1 + 0.01 * unit(rng)));
      if (radius) {
        mag_set_d(arb_radref(u.coeff(0)), 1e-40);
        mag_set_d(arb_radref(u.coeff(1)), std::abs(slope) * 1e-38);
      }
      for (const bool cosine : {false, true}) {
        const elementary f = cosine ? elementary::cos : elementary::sin;
        chebyshev_model direct;
        ASSERT_TRUE(eulervop::detail::trig_of_linear_model(direct, cosine, u, -230, 300, 256)) << slope;
        mag_value target;
        mag_set_ui_2exp_si(target.m, 1, -230);
        EXPECT_LE(mag_cmp(direct.remainder(), target.m), 0) << "slope " << slope << " offset " << offset;
        chebyshev_model out;
        eulervop::detail::compose(out, f, u, 300, 240);  // takes the closed form
        for (const chebyshev_model* m : {&direct, &out})
          for (int pick_round = 0; pick_round < 3; ++pick_round) {
            const represented fu = pick(u, rng);
            for (const mpfr_real& sp : points(rng)) {
              ball v;
              eulervop::detail::evaluate(v, *m, point(sp), truth_bits);
              const mpfr_real x = fu(sp);
              const mpfr_real fx = cosine ? mpfr_real(cos(x)) : mpfr_real(sin(x));
              ASSERT_TRUE(holds(v, fx))
                  << (cosine ? "cos" : "sin") << " slope " << slope << " offset " << offset << " s " << sp;
            }
          }
      }
    }
  // Refused: a slope that may be 0, one beyond 4, a remainder, a longer model.
  chebyshev_model u, out;
  u.resize(2);
  arb_set_d(u.coeff(0), 0.5);
  arb_zero_pm_one(u.coeff(1));
  EXPECT_FALSE(eulervop::detail::trig_of_linear_model(out, false, u, -200, 300, 256));
  arb_set_d(u.coeff(1), 4.5);
  EXPECT_FALSE(eulervop::detail::trig_of_linear_model(out, false, u, -200, 300, 256));
  arb_set_d(u.coeff(1), 0.5);
  mag_set_d(u.remainder(), 1e-30);
  EXPECT_FALSE(eulervop::detail::trig_of_linear_model(out, true, u, -200, 300, 256));
  mag_zero(u.remainder());
  u.resize(3);
  arb_set_d(u.coeff(2), 0.1);
  EXPECT_FALSE(eulervop::detail::trig_of_linear_model(out, true, u, -200, 300, 256));
}

// tanh's poles i (pi/2 + k pi) and atan's branch points +-i with their cuts up and down the
// imaginary axis: a complex ball that may meet one is refused, one that avoids them is not, and
// the values returned hold the closed forms (MPFR at 1000 bits):
//   tanh(x + iy) = (sinh 2x + i sin 2y) / (cosh 2x + cos 2y),
//   atan(x + iy) = (atan2(x, 1 + y) + atan2(x, 1 - y)) / 2 + i log(((1 + y)^2 + x^2) / ((1 - y)^2 + x^2)) / 4
// (the principal branch, from atan z = (i/2) (log(1 - iz) - log(1 + iz))). A model whose every
// ellipse meets a pole or a cut becomes the function's range as a constant and a remainder, which
// still holds the function; one whose ellipses avoid them meets the target.
TEST(ChebyshevComposition, PolesAndBranchCutsAreAvoided) {
  using eulervop::detail::elementary;
  const eulervop::mpfr_precision_scope scope(truth_bits);
  struct complex_case {
    elementary f;
    double x, rx, y, ry;
    bool analytic;
  };
  acb_t z, out;
  acb_init(z);
  acb_init(out);
  for (const complex_case& c : {complex_case{elementary::tanh, 0, 0.01, 1.5708, 0.01, false},  // at i pi/2
                                complex_case{elementary::tanh, 0, 0.5, 0, 1.6, false},         // holds i pi/2
                                complex_case{elementary::tanh, 0, 0.5, 0, 1.5, true},
                                complex_case{elementary::tanh, 0.5, 0.2, 1.5708, 0.5, true},   // off the axis
                                complex_case{elementary::atan, 0, 0.01, 1, 0.01, false},       // at i
                                complex_case{elementary::atan, 0, 0.01, -2, 0.01, false},      // on the cut
                                complex_case{elementary::atan, 0, 0.5, 0, 0.9, true},
                                complex_case{elementary::atan, 0.2, 0.1, 0, 5, true},          // off the axis
                                complex_case{elementary::sinh, 0, 3, 0, 3, true},
                                complex_case{elementary::cosh, 0, 3, 0, 3, true}}) {
    arb_set_d(acb_realref(z), c.x);  // the ball c.x +- c.rx + i (c.y +- c.ry)
    mag_set_d(arb_radref(acb_realref(z)), c.rx);
    arb_set_d(acb_imagref(z), c.y);
    mag_set_d(arb_radref(acb_imagref(z)), c.ry);
    const bool analytic = eulervop::detail::elementary_on_complex(c.f, z, out, 300);
    EXPECT_EQ(analytic, c.analytic) << "f " << static_cast<int>(c.f) << " at " << c.x << " + " << c.y << "i";
    if (!analytic || c.f == elementary::sinh || c.f == elementary::cosh) continue;
    // The closed form at a point of the ball: its centre shifted by (rx, ry) / 2.
    const mpfr_real x = mpfr_real(c.x) + mpfr_real(c.rx) / 2, y = mpfr_real(c.y) + mpfr_real(c.ry) / 2;
    mpfr_real re, im;
    if (c.f == elementary::tanh) {
      const mpfr_real d = cosh(2 * x) + cos(2 * y);
      re = sinh(2 * x) / d;
      im = sin(2 * y) / d;
    } else {
      re = (atan2(x, 1 + y) + atan2(x, 1 - y)) / 2;
      im = log(((1 + y) * (1 + y) + x * x) / ((1 - y) * (1 - y) + x * x)) / 4;
    }
    ball r, i;
    arb_set(r.get(), acb_realref(out));
    arb_set(i.get(), acb_imagref(out));
    EXPECT_TRUE(holds(r, re) && holds(i, im)) << "f " << static_cast<int>(c.f) << " at " << x << " + " << y << "i";
  }
  acb_clear(z);
  acb_clear(out);
  // u = c1 s over [-1, 1].
  std::mt19937_64 rng(23);
  for (const elementary f : {elementary::tanh, elementary::atan})
    for (const double c1 : {40.0, 0.5}) {
      chebyshev_model u(2), out_model;
      arb_zero(u.coeff(0));
      arb_set_d(u.coeff(1), c1);
      eulervop::detail::compose(out_model, f, u, 300, 240);
      if (c1 > 1) {
        EXPECT_EQ(out_model.length(), 1) << "f " << static_cast<int>(f) << ": no ellipse avoids the singularities";
      } else {
        EXPECT_GT(out_model.length(), 8) << "f " << static_cast<int>(f);
        EXPECT_LE(mag_cmp_2exp_si(out_model.remainder(), -200), 0) << "f " << static_cast<int>(f);
      }
      for (const mpfr_real& sp : points(rng)) {
        ball v;
        eulervop::detail::evaluate(v, out_model, point(sp), truth_bits);
        const mpfr_real arg = c1 * sp;
        EXPECT_TRUE(holds(v, f == elementary::tanh ? mpfr_real(tanh(arg)) : mpfr_real(atan(arg))))
            << "f " << static_cast<int>(f) << " c1 " << c1 << " s " << sp;
      }
    }
}

// The field along a segment's polynomial and its Jacobian (certification_problem.hpp, in the
// series algebra with forward derivatives) hold the problem's own right-hand side and Jacobian
// (model/coupled_problem.hpp, euler_problem.hpp with expression_torque.hpp: the reference's
// equations, written separately), evaluated at 1000 bits at points of the polynomial: for a PD law
// on a body listed out of order (7 states, normalized with a permutation), rate damping (3), an
// axisymmetric body with an attitude (the direct form, 7 states as a cascade), functions of the
// time and the rates (3: sin cos exp log sqrt, then tanh atan sinh cosh of arguments that vary
// by less than 1 over P, so that their ellipses avoid the poles and cuts and the models are
// tight), and the gravity gradient with a formula of q (7).
struct field_case {
  const char* label;
  const char* scene;
};

class FieldAlongP : public ::testing::TestWithParam<field_case> {};

TEST_P(FieldAlongP, ValuesAndJacobianHoldTheProblemsOwn) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  namespace sc = eulervop::scene;
  const sc::scene s = sc::parse_scene(GetParam().scene, "test");
  const eulervop::certification_problem p = sc::certification_problem_of<eulervop::quad>(s, 400);
  const std::size_t D = p.dimension;
  std::mt19937_64 rng(5);
  std::vector<chebyshev_model> P;
  for (std::size_t i = 0; i < D; ++i) P.push_back(random_model(rng, 10, 0.5, 0, 0));
  ball a, hl;
  arb_set_d(a.get(), 0.3);
  arb_set_d(hl.get(), 0.7);
  const eulervop::detail::series_algebra alg(400, D);
  chebyshev_model t(2);
  arb_add(t.coeff(0), a.get(), hl.get(), 400);
  arb_set(t.coeff(1), hl.get());
  std::vector<eulervop::detail::series_jet> x, F;
  for (std::size_t k = 0; k < D; ++k) x.push_back(alg.variable(P[k], k));
  eulervop::field(p, 0, alg, alg.independent(t), x, F);
  ASSERT_EQ(F.size(), D);
  for (const mpfr_real& sp : points(rng)) {
    std::vector<mpfr_real> y(D);
    ball v;
    for (std::size_t i = 0; i < D; ++i) {
      eulervop::detail::evaluate(v, P[i], point(sp), truth_bits);
      y[i] = to_mpfr(arb_midref(v.get()));  // exact: P's coefficients are exact
    }
    const mpfr_real time = to_mpfr(arb_midref(a.get())) + to_mpfr(arb_midref(hl.get())) * (sp + 1);
    std::vector<mpfr_real> f(D);
    std::vector<std::vector<mpfr_real>> J(D, std::vector<mpfr_real>(D));
    if (s.couples_attitude()) {
      const eulervop::coupled_problem<mpfr_real> cp = sc::to_coupled_problem<mpfr_real>(s);
      std::array<mpfr_real, 7> xs, dx;
      std::array<std::array<mpfr_real, 7>, 7> Jc;
      for (std::size_t i = 0; i < 7; ++i) xs[i] = y[i];
      cp.rhs(time, xs, dx);
      cp.jacobian(time, xs, Jc);
      for (std::size_t i = 0; i < 7; ++i) {
        f[i] = dx[i];
        for (std::size_t k = 0; k < 7; ++k) J[i][k] = Jc[i][k];
      }
    } else {
      sc::with_problem<mpfr_real>(s, [&](const auto& prob) {
        const eulervop::vec3<mpfr_real> yr = {y[0], y[1], y[2]};
        eulervop::vec3<mpfr_real> dy;
        std::array<eulervop::vec3<mpfr_real>, 3> Jr;
        prob.rhs(time, yr, dy);
        prob.jacobian(time, yr, Jr);
        for (std::size_t i = 0; i < 3; ++i) {
          f[i] = dy[i];
          for (std::size_t k = 0; k < 3; ++k) J[i][k] = Jr[i][k];
        }
      });
      if (D == 7) {  // q' = 1/2 q (x) (0, W), W the body rates of y (body_rates.hpp)
        const eulervop::vec3<mpfr_real> W = sc::body_rates_of<mpfr_real>(s)({y[0], y[1], y[2]});
        const mpfr_real q0 = y[3], q1 = y[4], q2 = y[5], q3 = y[6];
        f[3] = (-q1 * W[0] - q2 * W[1] - q3 * W[2]) / 2;
        f[4] = (q0 * W[0] + q2 * W[2] - q3 * W[1]) / 2;
        f[5] = (q0 * W[1] - q1 * W[2] + q3 * W[0]) / 2;
        f[6] = (q0 * W[2] + q1 * W[1] - q2 * W[0]) / 2;
      }
    }
    for (std::size_t i = 0; i < D; ++i) {
      eulervop::detail::evaluate(v, F[i].f, point(sp), truth_bits);
      EXPECT_TRUE(holds(v, f[i])) << GetParam().label << ": F" << i << " at s = " << sp;
      if (D == 7 && i >= 3 && !s.couples_attitude()) continue;  // q's Jacobian: below, by the rates'
      for (std::size_t k = 0; k < D; ++k) {
        eulervop::detail::evaluate(v, F[i].d[k], point(sp), truth_bits);
        EXPECT_TRUE(holds(v, J[i][k])) << GetParam().label << ": J" << i << k << " at s = " << sp;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, FieldAlongP,
    ::testing::Values(field_case{"pd_law", R"(name = "pd"
[body]
inertia = [100.0, 150.0, 120.0]
[torque]
M = ["-2*q1 - 40*omega1", "-2*q2 - 40*omega2*t", "-2*q3 - 40*omega3"]
[initial]
omega = [0.01, -0.02, 0.005]
q = [0.5, 0.5, -0.5, 0.5]
[span]
t_end = 10.0
samples = 3
)"},
                      field_case{"damped", R"(name = "damped"
[body]
inertia = [150.0, 200.0, 100.0]
[torque]
M = ["0.01 - 0.5*omega1*t^2", "-0.02 - 0.3*omega2", "0.005 - 0.2*omega3^3"]
[initial]
omega = [0.1, 0.05, 0.02]
[span]
t_end = 10.0
samples = 3
)"},
                      field_case{"axisymmetric", R"(name = "axisymmetric"
[body]
inertia = [1000.0, 1000.0, 2000.0]
[torque]
M = [0.002, -0.001, 0.0015]
[initial]
omega = [0.02, 0.01, 0.05]
q = [0.5, 0.5, 0.5, 0.5]
[span]
t_end = 10.0
samples = 3
)"},
                      field_case{"functions", R"toml(name = "functions"
[body]
inertia = [150.0, 200.0, 100.0]
[torque]
M = ["0.01*sin(t)^2 - 0.5*exp(-omega1^2)", "0.02*cos(2*t)*omega2/(2 + omega3^2)", "sqrt(1 + omega1^2) + log(2 + omega2^2)"]
[initial]
omega = [0.1, 0.05, 0.02]
[span]
t_end = 10.0
samples = 3
)toml"},
                      field_case{"saturation", R"toml(name = "saturation"
[body]
inertia = [150.0, 200.0, 100.0]
[torque]
M = ["-0.5*tanh(omega1/8) + 0.01*atan(t - 1)", "0.02*sinh(omega2/4)*cosh(t/4)", "-0.3*atan(omega3/8) + cosh(omega1/4)/50"]
[initial]
omega = [0.1, 0.05, 0.02]
[span]
t_end = 10.0
samples = 3
)toml"},
                      field_case{"gravity", R"toml(name = "gravity"
[body]
inertia = [100.0, 150.0, 220.0]
[torque]
M = ["0.1*omega1/(40 + q1^2)", "0.0", "-0.01*omega3*exp(-t/5)"]
[torque.gravity_gradient]
mean_motion = 0.3
[initial]
omega = [0.01, -0.02, 0.005]
q = [0.5, 0.5, -0.5, 0.5]
[span]
t_end = 10.0
samples = 3
)toml"}),
    [](const auto& info) { return std::string(info.param.label); });

// Over a box, c bounds Taylor's remainder: |W (F(x + e) - F(x) - J e)| <= c |W e|^2 for every e
// with x + e in the box, for a cubic torque (omega3^3) and for Eq. 5 (where c = sqrt(3)/2 from
// Hessians of row sums 1).
TEST(BoxBounds, TheQuadraticConstantBoundsTaylorsRemainder) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  namespace sc = eulervop::scene;
  const sc::scene s = sc::parse_scene(R"(name = "damped"
[body]
inertia = [150.0, 200.0, 100.0]
[torque]
M = ["0.01 - 0.5*omega1", "-0.02 - 0.3*omega2", "0.005 - 0.2*omega3^3"]
[initial]
omega = [0.1, 0.05, 0.02]
[span]
t_end = 10.0
samples = 3
)", "test");
  const eulervop::certification_problem p = sc::certification_problem_of<eulervop::quad>(s, 300);
  std::vector<ball> box(3);
  for (std::size_t i = 0; i < 3; ++i) {
    arb_set_d(box[i].get(), 0.3 - 0.2 * static_cast<double>(i));
    mag_value r;
    mag_set_d(r.m, 0.05);
    arb_add_error_mag(box[i].get(), r.m);
  }
  ball t;
  arb_set_d(t.get(), 1.5);
  mag_value c;
  std::vector<mag_value> fabs;
  eulervop::box_bounds(p, 0, t, box, {1, 1, 1}, c.m, fabs);
  ASSERT_TRUE(mag_is_finite(c.m));
  sc::with_problem<mpfr_real>(s, [&](const auto& prob) {
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    for (int trial = 0; trial < 200; ++trial) {
      eulervop::vec3<mpfr_real> x0, x1, f0, f1;
      std::array<eulervop::vec3<mpfr_real>, 3> J;
      for (std::size_t i = 0; i < 3; ++i) {
        x0[i] = mpfr_real(0.3 - 0.2 * static_cast<double>(i)) + mpfr_real(u(rng)) / 2;
        x1[i] = x0[i] + mpfr_real(u(rng)) / 2;
      }
      const mpfr_real tt = 1.5;
      prob.rhs(tt, x0, f0);
      prob.rhs(tt, x1, f1);
      prob.jacobian(tt, x0, J);
      mpfr_real rem2 = 0, e2 = 0;
      for (std::size_t i = 0; i < 3; ++i) {
        mpfr_real r = f1[i] - f0[i];
        for (std::size_t k = 0; k < 3; ++k) r -= J[i][k] * (x1[k] - x0[k]);
        rem2 += r * r;
        e2 += (x1[i] - x0[i]) * (x1[i] - x0[i]);
        EXPECT_LE(abs(f0[i]), mpfr_real(mag_get_d(fabs[i].m))) << "|F_" << i << "| over the box";
      }
      EXPECT_LE(sqrt(rem2), mpfr_real(mag_get_d(c.m)) * e2) << "trial " << trial;
    }
  });
}

// A linear map applied to the parallelepiped: every image of a point of the set lies in the
// stepped set, for a shear that makes the parallelepiped ill-conditioned step after step.
TEST(BallLohnerBox, HoldsTheImageOfEveryPointUnderAShear) {
  const std::size_t D = 4;
  eulervop::detail::ball_lohner_box box(D, 200);
  std::vector<ball> e0(D);
  for (std::size_t i = 0; i < D; ++i) {
    arb_set_d(e0[i].get(), 1e-3 * static_cast<double>(i + 1));
    mag_value r;
    mag_set_d(r.m, 1e-6);
    arb_add_error_mag(e0[i].get(), r.m);
  }
  box.start(e0);
  // Phi: a rotation in the first plane and a shear of the second component into the rest.
  std::vector<ball> Phi(D * D);
  const double c = std::cos(0.7), sn = std::sin(0.7);
  const double M[16] = {c, -sn, 0, 0, sn, c, 0, 0, 0, 3, 1, 0, 0, 5, 0, 1};
  for (std::size_t q = 0; q < D * D; ++q) arb_set_d(Phi[q].get(), M[q]);
  std::vector<ball> w(D);
  std::vector<mag_value> b(D);
  // Corners of the initial box, followed exactly (in double-double-free rationals: the map's
  // entries are doubles, the corners dyadic; 200 bits hold them exactly for these few steps).
  std::vector<std::vector<ball>> corners;
  for (int m = 0; m < 16; ++m) {
    std::vector<ball> p(D);
    for (std::size_t i = 0; i < D; ++i) {
      arb_set_d(p[i].get(), 1e-3 * static_cast<double>(i + 1) + ((m >> i) & 1 ? 1e-6 : -1e-6));
    }
    corners.push_back(p);
  }
  for (int step = 0; step < 12; ++step) {
    ASSERT_TRUE(box.step(Phi, w, b));
    for (auto& p : corners) {
      std::vector<ball> n(D);
      for (std::size_t i = 0; i < D; ++i)
        for (std::size_t k = 0; k < D; ++k) arb_addmul(n[i].get(), Phi[i * D + k].get(), p[k].get(), 400);
      p = n;
    }
    std::vector<ball> e;
    box.image_of_identity(e);
    for (const auto& p : corners)
      for (std::size_t i = 0; i < D; ++i) EXPECT_TRUE(arb_contains(e[i].get(), p[i].get())) << "step " << step;
  }
}

}  // namespace

namespace {

// sn, cn, dn of Eq. 12's initial state (jacobi_enclosure.hpp): each ball holds Boost's value at
// 1000 bits and is tight (its radius within 2^-230 at 256 bits), from the circle to the
// separatrix, for large and negative u; k = 1 and beyond is refused, never enclosed.
TEST(JacobiEnclosure, HoldsBoostsValuesAt1000Bits) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  const double ks[] = {0.0, 1e-9, 0.1, 0.5, 0.9, 0.999999, 1 - 0x1p-40};
  const double us[] = {0.3, -1.7, 2.5, 40.0, -123.456, 1e-12};
  for (double kd : ks) {
    for (double ud : us) {
      ball k, u;
      arb_set_d(k.get(), kd);
      arb_set_d(u.get(), ud);
      const eulervop::jacobi_enclosures v = eulervop::jacobi_enclosure(k, u, 256);
      mpfr_real cn, dn;
      const mpfr_real sn = boost::math::jacobi_elliptic(mpfr_real(kd), mpfr_real(ud), &cn, &dn);
      const std::string where = "k " + std::to_string(kd) + " u " + std::to_string(ud);
      EXPECT_TRUE(holds(v.sn, sn)) << where;
      EXPECT_TRUE(holds(v.cn, cn)) << where;
      EXPECT_TRUE(holds(v.dn, dn)) << where;
      for (const ball* x : {&v.sn, &v.cn, &v.dn})
        EXPECT_LT(mag_get_d(arb_radref(x->get())), 0x1p-230) << where;
    }
  }
  for (double kd : {1.0, 1.5, -0.1}) {
    ball k, u;
    arb_set_d(k.get(), kd);
    arb_set_d(u.get(), 0.5);
    EXPECT_THROW(eulervop::jacobi_enclosure(k, u, 256), std::domain_error) << kd;
  }
}

}  // namespace
