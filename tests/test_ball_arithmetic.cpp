// The kernels of the general path of --certify (include/eulervop/certify/: chebyshev_model.hpp,
// ball_node_transform.hpp, field_algebra.hpp, certification_problem.hpp, ball_lohner_box.hpp,
// ball_linear_flow.hpp, short_integer_series.hpp),
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
#include <eulervop/certify/detail/ball_node_transform.hpp>
#include <eulervop/certify/detail/chebyshev_composition.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/field_algebra.hpp>
#include <eulervop/certify/detail/residual_model.hpp>
#include <eulervop/certify/detail/short_integer_series.hpp>
#include <eulervop/certify/jacobi_enclosure.hpp>
#include <eulervop/core/scalar.hpp>
#include <eulervop/scene/expression_parser.hpp>
#include <eulervop/scene/scene.hpp>
#include <eulervop/scene/scene_certification_problem.hpp>
#include <eulervop/scene/scene_problem.hpp>

#include <boost/math/special_functions/jacobi_elliptic.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace {

using eulervop::ball;
using eulervop::mag_value;
using eulervop::mpfr_real;
using eulervop::detail::chebyshev_model;

constexpr unsigned truth_bits = 1000;

mpfr_real to_mpfr(const arf_t x) {
  mpfr_real out;
  arf_get_mpfr(out.backend().data(), x, MPFR_RNDN);  // exact at 1000 bits for these inputs
  return out;
}

// True when the ball x holds v (v exact at 1000 bits).
bool holds(const ball& x, const mpfr_real& v) {
  arb_t t;
  arb_init(t);
  arb_set_interval_mpfr(t, v.backend().data(), v.backend().data(), truth_bits);
  const bool in = arb_contains(x.get(), t);
  arb_clear(t);
  return in;
}

// One function a model stands for: its coefficients each at an end of its ball (chosen at random),
// plus rem sin(17 s + 1) (which is at most rem in size).
struct represented {
  std::vector<mpfr_real> c;
  mpfr_real rem;
  mpfr_real operator()(const mpfr_real& s) const {
    // T_k(s) = cos(k acos s), directly.
    const mpfr_real theta = acos(s);
    mpfr_real sum = 0;
    for (std::size_t k = 0; k < c.size(); ++k) sum += c[k] * cos(mpfr_real(k) * theta);
    return sum + rem * sin(17 * s + 1);
  }
};

represented pick(const chebyshev_model& m, std::mt19937_64& rng) {
  represented f;
  arf_t end, r;
  arf_init(end);
  arf_init(r);
  for (slong k = 0; k < m.length(); ++k) {
    arf_set_mag(r, arb_radref(m.coeff(k)));
    if (rng() % 2) arf_neg(r, r);
    arf_add(end, arb_midref(m.coeff(k)), r, ARF_PREC_EXACT, ARF_RND_DOWN);
    f.c.push_back(to_mpfr(end));
  }
  arf_set_mag(r, m.remainder());
  f.rem = to_mpfr(r) * (static_cast<double>(rng() % 1000) / 1000);
  arf_clear(end);
  arf_clear(r);
  return f;
}

// A model of `n` coefficients decaying like rho^k with random signs, radii of `rad_bits` below
// each coefficient, and a remainder `rem` (0 for none).
chebyshev_model random_model(std::mt19937_64& rng, slong n, double rho, long rad_bits, double rem) {
  chebyshev_model m(n);
  std::uniform_real_distribution<double> u(-1, 1);
  for (slong k = 0; k < n; ++k) {
    arb_set_d(m.coeff(k), u(rng) * std::pow(rho, static_cast<double>(k)));
    ball pi;
    arb_const_pi(pi.get(), 300);
    arb_mul(m.coeff(k), m.coeff(k), pi.get(), 300);  // 300 significant bits
    if (rad_bits > 0) {
      mag_value r;
      arb_get_mag(r.m, m.coeff(k));
      mag_mul_2exp_si(r.m, r.m, -rad_bits);
      arb_add_error_mag(m.coeff(k), r.m);
    }
  }
  mag_set_d(m.remainder(), rem);
  return m;
}

// The double x as a ball (exact).
ball decimal(double x) {
  ball b;
  arb_set_d(b.get(), x);
  return b;
}

// int_{-1}^s f, f's polynomial part term by term (int T_0 = s + 1, int T_1 = (s^2 - 1)/2,
// int T_k = T_{k+1}/(2(k+1)) - T_{k-1}/(2(k-1)) - the same at -1), its remainder by the
// quadrature of 1000-bit MPFR's own sin: integral of sin(17 x + 1) = -cos(17 x + 1)/17.
mpfr_real integral_of(const represented& f, const mpfr_real& s) {
  const auto T = [](std::size_t k, const mpfr_real& x) { return cos(mpfr_real(k) * acos(x)); };
  mpfr_real sum = 0;
  for (std::size_t k = 0; k < f.c.size(); ++k) {
    mpfr_real anti;
    if (k == 0) anti = s + 1;
    else if (k == 1) anti = (s * s - 1) / 2;
    else
      anti = (T(k + 1, s) - T(k + 1, mpfr_real(-1))) / (2 * (k + 1)) -
             (T(k - 1, s) - T(k - 1, mpfr_real(-1))) / (2 * (k - 1));
    sum += f.c[k] * anti;
  }
  return sum + f.rem * (cos(mpfr_real(-16)) - cos(17 * s + 1)) / 17;
}

ball point(const mpfr_real& s) {
  ball b;
  arb_set_interval_mpfr(b.get(), s.backend().data(), s.backend().data(), truth_bits);
  return b;
}

// Random points in [-1, 1], the ends included.
std::vector<mpfr_real> points(std::mt19937_64& rng) {
  std::vector<mpfr_real> s = {mpfr_real(-1), mpfr_real(1), mpfr_real(0)};
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 9; ++i) s.push_back(mpfr_real(u(rng)));
  return s;
}

TEST(ChebyshevModel, ProductsHoldEveryProductOfTheFunctionsTheyStandFor) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(20261127);
  for (int trial = 0; trial < 60; ++trial) {
    const slong la = 1 + static_cast<slong>(rng() % 45), lb = 1 + static_cast<slong>(rng() % 45);
    const double rho = trial % 3 == 0 ? 1.0 : 0.2 + 0.6 * static_cast<double>(rng() % 100) / 100;
    const chebyshev_model a = random_model(rng, la, rho, trial % 2 ? 100 : 0, trial % 4 == 0 ? 1e-20 : 0);
    chebyshev_model b = random_model(rng, lb, rho, trial % 3 ? 60 : 0, trial % 5 == 0 ? 1e-10 : 0);
    if (trial % 7 == 6) {  // a signed power of two, as a variable's derivative (multiply's own branch)
      b = chebyshev_model(1);
      arb_set_si(b.coeff(0), rng() % 2 ? 1 : -1);
      arb_mul_2exp_si(b.coeff(0), b.coeff(0), static_cast<slong>(rng() % 5) - 2);
    }
    for (const slong bits : {56L, 177L}) {
      chebyshev_model c;
      eulervop::detail::multiply(c, a, b, bits);
      for (int pick_round = 0; pick_round < 3; ++pick_round) {
        const represented fa = pick(a, rng), fb = pick(b, rng);
        for (const mpfr_real& s : points(rng)) {
          ball v;
          eulervop::detail::evaluate(v, c, point(s), truth_bits);
          ASSERT_TRUE(holds(v, fa(s) * fb(s))) << "trial " << trial << " bits " << bits << " lengths " << la << ", "
                                               << lb << " at s = " << s;
        }
      }
    }
  }
}

// Scaling by a number, exactly where it is a signed power of two (the fields' 1/2 and -1).
TEST(ChebyshevModel, ScalingHoldsEveryScaledFunction) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(3);
  ball third;
  arb_set_ui(third.get(), 1);
  arb_div_ui(third.get(), third.get(), 3, 200);
  for (const ball& x : {decimal(-0.5), decimal(4), decimal(1), decimal(-1), third}) {
    const chebyshev_model a = random_model(rng, 20, 0.5, 80, 1e-12);
    chebyshev_model c = a;
    eulervop::detail::scale(c, x, 200);
    const represented fa = pick(a, rng);
    for (const mpfr_real& s : points(rng)) {
      ball v, y;
      eulervop::detail::evaluate(v, c, point(s), truth_bits);
      // x's own ball: both of its ends.
      for (const int end : {-1, 1}) {
        arf_t e;
        arf_init(e);
        arf_set_mag(e, arb_radref(x.get()));
        if (end < 0) arf_neg(e, e);
        arf_add(e, e, arb_midref(x.get()), ARF_PREC_EXACT, ARF_RND_DOWN);
        ASSERT_TRUE(holds(v, fa(s) * to_mpfr(e))) << "s = " << s;
        arf_clear(e);
      }
    }
  }
}

// The product is as tight as its grid: a product of exact polynomials on 177 bits is within
// 2^-170 of the exact one, relative to the factors' sizes (sum of magnitudes).
TEST(ChebyshevModel, ProductsOfExactPolynomialsAreTight) {
  std::mt19937_64 rng(7);
  const chebyshev_model a = random_model(rng, 42, 0.15, 0, 0), b = random_model(rng, 42, 0.15, 0, 0);
  chebyshev_model c;
  eulervop::detail::multiply(c, a, b, 177);
  mag_value sup, A, B;
  eulervop::detail::sup_bound(sup.m, c);
  eulervop::detail::coefficient_magnitude(A.m, a);
  eulervop::detail::coefficient_magnitude(B.m, b);
  mag_mul(A.m, A.m, B.m);
  mag_mul_2exp_si(A.m, A.m, -170);
  EXPECT_LE(mag_cmp(c.remainder(), A.m), 0) << "remainder " << mag_get_d(c.remainder());
}

TEST(ChebyshevModel, IntegralsHoldTheIntegralOfEveryFunction) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 40; ++trial) {
    const slong n = 1 + static_cast<slong>(rng() % 60);
    const chebyshev_model a = random_model(rng, n, 0.7, trial % 2 ? 80 : 0, trial % 3 == 0 ? 1e-15 : 0);
    ball hl;
    arb_set_d(hl.get(), 0.375 + static_cast<double>(rng() % 1000) / 333);
    chebyshev_model I;
    eulervop::detail::integrate(I, a, hl, 200);
    const represented f = pick(a, rng);
    const mpfr_real h = to_mpfr(arb_midref(hl.get()));
    for (const mpfr_real& s : points(rng)) {
      ball v;
      eulervop::detail::evaluate(v, I, point(s), truth_bits);
      ASSERT_TRUE(holds(v, h * integral_of(f, s))) << "trial " << trial << " at s = " << s;
    }
  }
}

// The Picard residual start + hl int_{-1}^s F - P of every F and P the models stand for, and r(1),
// against the same integral at 1000 bits.
TEST(ChebyshevModel, PicardResidualsHoldEveryResidual) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 40; ++trial) {
    const slong nf = 1 + static_cast<slong>(rng() % 84), np = 1 + static_cast<slong>(rng() % 42);
    const chebyshev_model F = random_model(rng, nf, 0.7, trial % 2 ? 80 : 0, trial % 3 == 0 ? 1e-15 : 0);
    const chebyshev_model P = random_model(rng, np, 0.5, trial % 4 ? 100 : 0, trial % 5 == 0 ? 1e-20 : 0);
    ball hl, start = decimal(static_cast<double>(rng() % 2001) / 1000 - 1);
    arb_set_d(hl.get(), 0.375 + static_cast<double>(rng() % 1000) / 333);
    eulervop::detail::integral_weights w;
    w.set(hl, nf, np, 177);
    chebyshev_model r;
    ball r1;
    eulervop::detail::picard_residual_model(r, r1, F, hl, w, start, P, 177);
    const represented f = pick(F, rng), p = pick(P, rng);
    const mpfr_real h = to_mpfr(arb_midref(hl.get())), y0 = to_mpfr(arb_midref(start.get()));
    const auto truth = [&](const mpfr_real& s) { return y0 + h * integral_of(f, s) - p(s); };
    for (const mpfr_real& s : points(rng)) {
      ball v;
      eulervop::detail::evaluate(v, r, point(s), truth_bits);
      ASSERT_TRUE(holds(v, truth(s))) << "trial " << trial << " at s = " << s;
    }
    ASSERT_TRUE(holds(r1, truth(mpfr_real(1)))) << "trial " << trial << ": r(1)";
  }
}

// The coefficients of the Lobatto interpolant: c_k = (2/N) sum_j'' v_j (-1)^k cos(k j pi / N),
// the ends halved (the transform the reference's dense output also rests on), from quad node
// values of every size and sign.
TEST(BallNodeTransform, HoldsTheInterpolantsCoefficients) {
  const eulervop::mpfr_precision_scope scope(truth_bits);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const std::size_t N : {4u, 5u, 17u, 41u, 64u}) {
    eulervop::detail::ball_node_transform transform(177, N, 2);
    std::vector<std::vector<mpfr_real>> v(2, std::vector<mpfr_real>(N + 1));
    for (std::size_t j = 0; j <= N; ++j)
      for (std::size_t i = 0; i < 2; ++i) {
        const eulervop::quad q = eulervop::quad(u(rng)) * eulervop::quad(std::ldexp(1.0, static_cast<int>(rng() % 200) - 100)) / 3;
        ball b;
        eulervop::set_exact(b, q);
        arb_set(transform.value(j, i), b.get());
        v[i][j] = mpfr_real(q);
      }
    arb_mat_t c;
    arb_mat_init(c, static_cast<slong>(N + 1), 2);
    transform.apply(c);
    const mpfr_real pi = boost::math::constants::pi<mpfr_real>();
    for (std::size_t i = 0; i < 2; ++i)
      for (std::size_t k = 0; k <= N; ++k) {
        mpfr_real sum = 0;
        for (std::size_t j = 0; j <= N; ++j) {
          mpfr_real term = v[i][j] * cos(pi * mpfr_real(k * j) / N);
          if (j == 0 || j == N) term /= 2;
          sum += term;
        }
        sum *= mpfr_real(2) / N;
        if (k % 2) sum = -sum;
        if (k == 0 || k == N) sum /= 2;
        ball x;
        arb_set(x.get(), arb_mat_entry(c, static_cast<slong>(k), static_cast<slong>(i)));
        EXPECT_TRUE(holds(x, sum)) << "N " << N << " k " << k;
        // As tight as the working precision: within 2^-170 of the values' sum of magnitudes.
        mpfr_real size = 0;
        for (const mpfr_real& vj : v[i]) size += abs(vj);
        EXPECT_LT(mpfr_real(mag_get_d(arb_radref(x.get()))), size * pow(mpfr_real(2), -170)) << "N " << N << " k " << k;
      }
    arb_mat_clear(c);
  }
}

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

// The 128-bit sums of Chebyshev products equal FLINT's exact ones, at the largest sizes fits()
// admits (and fits() refuses a size that could overflow).
TEST(ShortIntegerSeries, SumsOfProductsEqualFlintsExactOnes) {
  using eulervop::detail::short_integer_series;
  using eulervop::detail::wide_int;
  std::mt19937_64 rng(4);
  const auto random_poly = [&](eulervop::detail::integer_poly& p, std::size_t n, unsigned bits) {
    fmpz_poly_zero(p.p);
    for (std::size_t k = 0; k < n; ++k) {
      const auto magnitude = static_cast<std::int64_t>(rng() >> (64 - bits));  // below 2^bits, often at its top
      fmpz_poly_set_coeff_si(p.p, static_cast<slong>(k), rng() % 2 ? magnitude : -magnitude);
    }
  };
  EXPECT_FALSE(eulervop::detail::fits(62, 62, 90, 7));
  for (const auto& [la, lb, abits, bbits, count] :
       std::vector<std::tuple<std::size_t, std::size_t, unsigned, unsigned, std::size_t>>{
           {25, 15, 56, 40, 7}, {30, 90, 56, 58, 7}, {1, 40, 60, 50, 3}, {65, 65, 52, 56, 7}}) {
    ASSERT_TRUE(eulervop::detail::fits(abits, bbits, std::min(la, lb), count));
    std::vector<wide_int> sums(la + lb, 0);
    eulervop::detail::integer_poly total, term, a, b;
    for (std::size_t c = 0; c < count; ++c) {
      random_poly(a, la, abits);
      random_poly(b, lb, bbits);
      short_integer_series sa, sb;
      ASSERT_TRUE(sa.load(a.p));
      ASSERT_TRUE(sb.load(b.p));
      eulervop::detail::add_chebyshev_product(sums, sa, sb);
      eulervop::detail::grid_product_flint(term.p, a.p, b.p);
      fmpz_poly_add(total.p, total.p, term.p);
    }
    arf_t x, y;
    arf_init(x);
    arf_init(y);
    for (std::size_t k = 0; k < sums.size(); ++k) {
      eulervop::detail::set_wide(x, sums[k]);
      fmpz_t f;
      fmpz_init(f);
      fmpz_poly_get_coeff_fmpz(f, total.p, static_cast<slong>(k));
      arf_set_fmpz(y, f);
      fmpz_clear(f);
      EXPECT_TRUE(arf_equal(x, y)) << "coefficient " << k << " of lengths " << la << ", " << lb;
    }
    arf_clear(x);
    arf_clear(y);
  }
}

// The Kronecker kernel's Chebyshev products (kronecker_product.hpp) equal FLINT's exact ones
// (grid_product_flint(), two fmpz_poly_mul), bit for bit, on random integer polynomials: lengths
// 1 to 90, 1 to 1200 bits, random signs and zeros, decaying magnitudes as a segment's, and
// coefficients all at +-(2^bits - 1) (every slot's sum at its bound); up to the largest factor the
// kernel takes, and one past it (then grid_product() falls back to FLINT).
TEST(KroneckerProduct, ChebyshevProductsEqualFlintsExactOnes) {
  namespace kr = eulervop::detail::kronecker;
  flint_rand_t state;
  flint_randinit(state);
  std::mt19937_64 rng(51);
  fmpz_t f;
  fmpz_init(f);
  // kind 0: random bit lengths up to `bits`, a sixth zero; 1: all +-(2^bits - 1), one sign when
  // same_sign; 2: decaying from `bits` bits by bits/len per index, as a segment's coefficients.
  const auto random_poly = [&](eulervop::detail::integer_poly& p, slong len, ulong bits, int kind, bool same_sign) {
    fmpz_poly_zero(p.p);
    for (slong k = 0; k < len; ++k) {
      if (kind == 1) {
        fmpz_one(f);
        fmpz_mul_2exp(f, f, bits);
        fmpz_sub_ui(f, f, 1);
        if (!same_sign && rng() % 2) fmpz_neg(f, f);
      } else {
        const ulong b = kind == 2 ? std::max<ulong>(1, bits - bits * static_cast<ulong>(k) / static_cast<ulong>(len))
                                  : 1 + rng() % bits;
        if (kind == 0 && rng() % 6 == 0) fmpz_zero(f); else fmpz_randbits(f, state, static_cast<flint_bitcnt_t>(b));
      }
      fmpz_poly_set_coeff_fmpz(p.p, k, f);
    }
    if (fmpz_poly_length(p.p) == 0) fmpz_poly_set_si(p.p, rng() % 2 ? 1 : -1);  // a nonzero factor
  };
  eulervop::detail::integer_poly a, b, fast, flint;
  const auto check = [&](const char* what) {
    ASSERT_TRUE(eulervop::detail::kronecker_grid_product(fast.p, a.p, b.p)) << what;
    eulervop::detail::grid_product_flint(flint.p, a.p, b.p);
    EXPECT_TRUE(fmpz_poly_equal(fast.p, flint.p))
        << what << ": lengths " << fmpz_poly_length(a.p) << ", " << fmpz_poly_length(b.p) << ", bits "
        << fmpz_poly_max_bits(a.p) << ", " << fmpz_poly_max_bits(b.p);
  };
  for (int trial = 0; trial < 3000; ++trial) {
    const slong la = 1 + static_cast<slong>(rng() % 90), lb = 1 + static_cast<slong>(rng() % 90);
    const ulong bits = trial % 10 == 0 ? 1 + rng() % 1200 : 1 + rng() % 200;
    const int kind = static_cast<int>(rng() % 3);
    random_poly(a, la, bits, kind, rng() % 2);
    if (trial % 7 == 0) fmpz_poly_set(b.p, a.p); else random_poly(b, lb, 1 + rng() % 200, kind, rng() % 2);
    check("random");
  }
  // The largest factors taken: 2 + len b / 64 limbs at most kr::max_limbs, b = (w + 1) / 2 and
  // w = 2 bits + ceil(log2 len) + 1, so b = bits + 4 at len = 128 (then exactly kr::max_limbs).
  const slong len = 128;
  const ulong bits = static_cast<ulong>(kr::max_limbs - 2) * kr::limb_bits / len - 4;
  for (int kind = 0; kind < 3; ++kind) {
    random_poly(a, len, bits, kind == 0 ? 1 : kind, kind == 0);
    random_poly(b, len, bits, kind == 0 ? 1 : kind, false);
    check("largest");
  }
  random_poly(a, len, bits + 1, 1, true);  // one bit more: b + 1, two limbs more, FLINT's
  EXPECT_FALSE(eulervop::detail::kronecker_grid_product(fast.p, a.p, b.p));
  eulervop::detail::grid_product(fast.p, a.p, b.p);
  eulervop::detail::grid_product_flint(flint.p, a.p, b.p);
  EXPECT_TRUE(fmpz_poly_equal(fast.p, flint.p));
  fmpz_clear(f);
  flint_randclear(state);
}

// The linear flow (ball_linear_flow.hpp) for a Jacobian J(s) of random polynomials: at points of
// the segment, the exact Phi (Phi' = hl J Phi, Phi(-1) = I) and u (u' = hl J (u + r), u(-1) = 0)
// lie within the proven distance of Phi_num and u_num, in the weighted norm:
//   |W (Phi - Phi_num) W^-1|_2 <= phi_residual (1 + dt exp(j dt) j) and the same for u, with
// dt = hl (s + 1) and j >= |W J W^-1|_2 (>= its logarithmic norm), here the Frobenius norm of
// the entries' sup bounds. The exact solutions: Taylor series in t = s + 1 at 400 bits, in steps
// of at most 1/8 (J and r re-expanded at each step's start; 60 terms leave less than 2^-200).
TEST(BallLinearFlow, PhiAndUHoldTheExactSolutions) {
  const eulervop::mpfr_precision_scope scope(400);
  struct flow_case {
    std::size_t D;
    double size, hl;  // J's entries up to `size`; half the segment's length
    int q_weight;     // the weight 2^-q_weight of components 3..6
    double r_size;    // the residual r's size (its grid against u's decides the 128-bit path)
  };
  using poly = std::vector<mpfr_real>;
  // T_k(t - 1) as polynomials in t, k < 40.
  std::vector<poly> T = {{mpfr_real(1)}, {mpfr_real(-1), mpfr_real(1)}};
  for (std::size_t k = 2; k < 40; ++k) {
    poly next(k + 1, mpfr_real(0));
    for (std::size_t i = 0; i < T[k - 1].size(); ++i) {
      next[i + 1] += 2 * T[k - 1][i];
      next[i] -= 2 * T[k - 1][i];
    }
    for (std::size_t i = 0; i < T[k - 2].size(); ++i) next[i] -= T[k - 2][i];
    T.push_back(next);
  }
  const auto monomial = [&](const chebyshev_model& c) {
    poly out(40, mpfr_real(0));
    for (slong k = 0; k < c.length(); ++k) {
      const mpfr_real ck = to_mpfr(arb_midref(c.coeff(k)));
      for (std::size_t i = 0; i < T[static_cast<std::size_t>(k)].size(); ++i) out[i] += ck * T[static_cast<std::size_t>(k)][i];
    }
    return out;
  };
  // p(t0 + x) as a polynomial in x (Horner's shifts).
  const auto shifted = [](poly p, const mpfr_real& t0) {
    for (std::size_t i = 0; i + 1 < p.size(); ++i)
      for (std::size_t j = p.size() - 1; j-- > i;) p[j] += t0 * p[j + 1];
    return p;
  };
  std::mt19937_64 rng(11);
  for (const flow_case& fc : {flow_case{3, 1.0, 0.8, 0, 1e-30}, flow_case{7, 0.6, 1.5, 3, 1e-33},
                              flow_case{7, 2e-3, 0.9, 0, 1e-20}, flow_case{3, 2.0, 1.2, 0, 1e-34}}) {
    const std::size_t D = fc.D, DD = D * D;
    std::vector<chebyshev_model> J(DD);
    for (std::size_t q = 0; q < DD; ++q) {
      if (rng() % 5 == 0) continue;  // a zero entry: the iteration skips what stays zero
      J[q] = random_model(rng, 14, 0.4, 0, 0);
      eulervop::detail::scale(J[q], decimal(fc.size), 300);
    }
    std::vector<chebyshev_model> r(D);
    for (std::size_t i = 0; i < D; ++i) {
      r[i] = random_model(rng, 40, 0.9, 0, 0);
      eulervop::detail::scale(r[i], decimal(fc.r_size), 300);
    }
    std::vector<double> weight(D, 1.0);
    for (std::size_t i = 3; i < D; ++i) weight[i] = std::ldexp(1.0, -fc.q_weight);
    const ball hl = decimal(fc.hl);
    // j: the Frobenius norm of W J W^-1 from the entries' sup bounds.
    mag_value jm, m;
    for (std::size_t i = 0; i < D; ++i)
      for (std::size_t k = 0; k < D; ++k) {
        eulervop::detail::sup_bound(m.m, J[i * D + k]);
        mag_mul_2exp_si(m.m, m.m, std::ilogb(weight[i]) - std::ilogb(weight[k]));
        mag_addmul(jm.m, m.m, m.m);
      }
    mag_sqrt(jm.m, jm.m);
    const double j = mag_get_d(jm.m);
    eulervop::detail::ball_linear_flow flow(D, 400);
    flow.load_jacobian(J, weight);
    ASSERT_TRUE(flow.variational(hl, j * 2 * fc.hl));
    ASSERT_TRUE(flow.integral_term(r, hl));
    const double phi_res = mag_get_d(flow.phi_residual()), u_res = mag_get_d(flow.u_residual());
    // The bounds are of use: Phi to about six digits or more, u's far below r.
    EXPECT_LT(phi_res, 1e-6) << "D " << D;
    EXPECT_LT(u_res, 1e-4 * fc.r_size) << "D " << D;
    std::vector<poly> Jm(DD), rm(D);
    for (std::size_t q = 0; q < DD; ++q) Jm[q] = monomial(J[q]);
    for (std::size_t i = 0; i < D; ++i) rm[i] = monomial(r[i]);
    const mpfr_real h = to_mpfr(arb_midref(hl.get()));
    std::vector<mpfr_real> phi(DD, mpfr_real(0)), ue(D, mpfr_real(0));
    for (std::size_t i = 0; i < D; ++i) phi[i * D + i] = 1;
    mpfr_real t0 = 0;
    const std::size_t terms = 60;
    for (const double sd : {-0.5, 0.0, 0.37, 1.0}) {
      const mpfr_real target = mpfr_real(sd) + 1;
      while (t0 < target) {
        const mpfr_real step = min(target - t0, mpfr_real(0.125));
        std::vector<poly> Js(DD), rs(D);
        for (std::size_t q = 0; q < DD; ++q) Js[q] = shifted(Jm[q], t0);
        for (std::size_t i = 0; i < D; ++i) rs[i] = shifted(rm[i], t0);
        std::vector<std::vector<mpfr_real>> P(terms, std::vector<mpfr_real>(DD, mpfr_real(0))),
            U(terms, std::vector<mpfr_real>(D, mpfr_real(0)));
        P[0] = phi;
        U[0] = ue;
        for (std::size_t n = 0; n + 1 < terms; ++n)
          for (std::size_t i = 0; i < D; ++i) {
            for (std::size_t c = 0; c < D; ++c) {
              mpfr_real acc = 0;
              for (std::size_t a = 0; a <= n && a < 40; ++a)
                for (std::size_t k = 0; k < D; ++k) acc += Js[i * D + k][a] * P[n - a][k * D + c];
              P[n + 1][i * D + c] = h * acc / mpfr_real(n + 1);
            }
            mpfr_real acc = 0;
            for (std::size_t a = 0; a <= n && a < 40; ++a)
              for (std::size_t k = 0; k < D; ++k)
                acc += Js[i * D + k][a] * (U[n - a][k] + (n - a < 40 ? rs[k][n - a] : mpfr_real(0)));
            U[n + 1][i] = h * acc / mpfr_real(n + 1);
          }
        std::fill(phi.begin(), phi.end(), mpfr_real(0));
        std::fill(ue.begin(), ue.end(), mpfr_real(0));
        for (std::size_t n = terms; n-- > 0;) {
          for (std::size_t q = 0; q < DD; ++q) phi[q] = phi[q] * step + P[n][q];
          for (std::size_t i = 0; i < D; ++i) ue[i] = ue[i] * step + U[n][i];
        }
        t0 += step;
      }
      const eulervop::detail::chebyshev_values Ts(flow.max_length(), point(mpfr_real(sd)), 400);
      std::vector<ball> Pn, un;
      flow.Phi_at(Ts, Pn);
      flow.u_at(Ts, un);
      const double dt = fc.hl * (sd + 1);
      const double factor = 1 + dt * std::exp(j * dt) * j;
      mpfr_real phi_err2 = 0, u_err2 = 0;
      for (std::size_t i = 0; i < D; ++i) {
        for (std::size_t k = 0; k < D; ++k) {
          const mpfr_real d = (phi[i * D + k] - to_mpfr(arb_midref(Pn[i * D + k].get()))) * weight[i] / weight[k];
          phi_err2 += d * d;
        }
        const mpfr_real d = (ue[i] - to_mpfr(arb_midref(un[i].get()))) * weight[i];
        u_err2 += d * d;
      }
      const double phi_err = static_cast<double>(sqrt(phi_err2)), u_err = static_cast<double>(sqrt(u_err2));
      EXPECT_LE(phi_err, phi_res * factor) << "D " << D << " s " << sd;
      EXPECT_LE(u_err, u_res * factor) << "D " << D << " s " << sd;
      // Not vacuous: Phi_num's distance is within a few orders of its residual (the factor is
      // this test's own, from a crude j).
      if (sd > -1) EXPECT_GT(phi_err, 1e-4 * phi_res) << "D " << D << " s " << sd;
    }
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
