// Shared pieces of the general path's kernel tests (test_ball_arithmetic.cpp,
// test_chebyshev_model.cpp): the truth in MPFR at 1000 bits, the functions a model stands for (its
// coefficients at the ends of their balls plus rem sin(17 s + 1)), random models and points.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/core/scalar.hpp>

#include <arb.h>

#include <cmath>
#include <random>
#include <vector>

namespace eulervop::test::ball_support {


using eulervop::ball;
using eulervop::mag_value;
using eulervop::mpfr_real;
using eulervop::detail::chebyshev_model;

inline constexpr unsigned truth_bits = 1000;

inline mpfr_real to_mpfr(const arf_t x) {
  mpfr_real out;
  arf_get_mpfr(out.backend().data(), x, MPFR_RNDN);  // exact at 1000 bits for these inputs
  return out;
}

// True when the ball x holds v (v exact at 1000 bits).
inline bool holds(const ball& x, const mpfr_real& v) {
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

inline represented pick(const chebyshev_model& m, std::mt19937_64& rng) {
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
inline chebyshev_model random_model(std::mt19937_64& rng, slong n, double rho, long rad_bits, double rem) {
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
inline ball decimal(double x) {
  ball b;
  arb_set_d(b.get(), x);
  return b;
}

// int_{-1}^s f, f's polynomial part term by term (int T_0 = s + 1, int T_1 = (s^2 - 1)/2,
// int T_k = T_{k+1}/(2(k+1)) - T_{k-1}/(2(k-1)) - the same at -1), its remainder by the
// quadrature of 1000-bit MPFR's own sin: integral of sin(17 x + 1) = -cos(17 x + 1)/17.
inline mpfr_real integral_of(const represented& f, const mpfr_real& s) {
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

inline ball point(const mpfr_real& s) {
  ball b;
  arb_set_interval_mpfr(b.get(), s.backend().data(), s.backend().data(), truth_bits);
  return b;
}

// Random points in [-1, 1], the ends included.
inline std::vector<mpfr_real> points(std::mt19937_64& rng) {
  std::vector<mpfr_real> s = {mpfr_real(-1), mpfr_real(1), mpfr_real(0)};
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 9; ++i) s.push_back(mpfr_real(u(rng)));
  return s;
}

}  // namespace eulervop::test::ball_support
