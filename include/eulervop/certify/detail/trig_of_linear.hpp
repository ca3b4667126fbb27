// sin and cos of a linear model u = c0 + c1 s (the time on a segment, tau = a + hl (s + 1)), by
// their Chebyshev series in closed form instead of interpolation (chebyshev_composition.hpp):
//   cos(x s) = J_0(x) + 2 sum_{k>=1} (-1)^k J_2k(x) T_2k(s),
//   sin(x s) = 2 sum_{k>=0} (-1)^k J_2k+1(x) T_2k+1(s)
// (M. Abramowitz and I. A. Stegun, Handbook of Mathematical Functions, 9.1.44 and 9.1.45, with
// s = cos theta and T_n(s) = cos n theta), and sin(c0 + x s) = sin c0 cos(x s) + cos c0 sin(x s),
// cos(c0 + x s) = cos c0 cos(x s) - sin c0 sin(x s). The Bessel values come from their power
// series at the two highest orders (9.1.10) and the recurrence J_(n-1) = (2n / x) J_n - J_(n+1)
// (9.1.27) downward, in balls; the terms beyond the degree n are at most
// 2 sum_{k>n} |J_k(x)| <= 4 |x/2|^(n+1) / (n+1)! where |x| / 2 <= (n + 2) / 2 (9.1.62:
// |J_k(x)| <= |x/2|^k / k! for real x). Why: a forcing of the time such as SciML's sin(t)^2
// composed by interpolation took 6% of that run's instructions, with an ellipse's bound chosen
// for each segment; here a segment's model is a few dozen ball operations.
//
// Downward, the recurrence's radii grow like I_n(x) (the modified Bessel function, whose
// recurrence has the same coefficients with positive signs) while the values grow like J_n(x):
// it is taken for |x| <= 4, where I_0(4) / J_0-sized values cost a few bits of the working
// precision.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>

#include <arb.h>

#include <cmath>
#include <vector>

namespace eulervop::detail {

namespace trig_of_linear {

constexpr double largest_slope = 4;  // |x| at most this (above)

// J_n(x) by its power series (x/2)^n sum_m (-x^2/4)^m / (m! (n+m)!), from its first term `first`
// ((x/2)^n / n!), summed until a term is below 2^-prec of the first and the ratio of terms below
// 1/2: the alternating rest is then at most the first term left out.
inline void bessel_series(ball& out, slong n, const ball& first, const ball& minus_y2, slong prec) {
  ball term;
  arb_set(term.get(), first.get());
  arb_set(out.get(), term.get());
  mag_value level, t, ratio, y2m;
  arb_get_mag(level.m, first.get());
  mag_mul_2exp_si(level.m, level.m, -prec);
  arb_get_mag(y2m.m, minus_y2.get());
  for (slong m = 1; m < 4 * prec; ++m) {
    arb_mul(term.get(), term.get(), minus_y2.get(), prec);
    arb_div_ui(term.get(), term.get(), static_cast<ulong>(m * (n + m)), prec);
    // The next ratio |x^2/4| / ((m+1)(n+m+1)) at most 1/2 and this term below 2^-prec of the
    // first: the terms from here on decrease, and their sum is at most this one.
    mag_div_ui(ratio.m, y2m.m, static_cast<ulong>((m + 1) * (n + m + 1)));
    arb_get_mag(t.m, term.get());
    if (mag_cmp_2exp_si(ratio.m, -1) <= 0 && mag_cmp(t.m, level.m) <= 0) {
      arb_add_error_mag(out.get(), t.m);
      return;
    }
    arb_add(out.get(), out.get(), term.get(), prec);
  }
  arb_indeterminate(out.get());  // never for |x| <= largest_slope
}

// J_n and J_(n+1) at x by their series, then J_(k-1) = (2k / x) J_k - J_(k+1) down to J_0.
inline void bessel_values(std::vector<ball>& J, slong n, const ball& x, slong prec) {
  J.resize(static_cast<std::size_t>(n + 2));
  ball y, minus_y2, first, t, inverse;
  arb_mul_2exp_si(y.get(), x.get(), -1);
  arb_mul(minus_y2.get(), y.get(), y.get(), prec);
  arb_neg(minus_y2.get(), minus_y2.get());
  arb_pow_ui(first.get(), y.get(), static_cast<ulong>(n), prec);
  // n! at prec, kept per thread (every segment's degree is about the same).
  thread_local slong fac_n = -1, fac_prec = 0;
  thread_local ball fac;
  if (fac_n != n || fac_prec != prec) {
    arb_fac_ui(fac.get(), static_cast<ulong>(n), prec);
    fac_n = n;
    fac_prec = prec;
  }
  arb_div(first.get(), first.get(), fac.get(), prec);  // (x/2)^n / n!
  bessel_series(J[static_cast<std::size_t>(n)], n, first, minus_y2, prec);
  arb_mul(first.get(), first.get(), y.get(), prec);
  arb_div_ui(first.get(), first.get(), static_cast<ulong>(n + 1), prec);  // (x/2)^(n+1) / (n+1)!
  bessel_series(J[static_cast<std::size_t>(n + 1)], n + 1, first, minus_y2, prec);
  arb_inv(inverse.get(), x.get(), prec);
  for (slong k = n; k >= 1; --k) {
    arb_mul_ui(t.get(), inverse.get(), static_cast<ulong>(2 * k), prec);
    arb_mul(t.get(), t.get(), J[static_cast<std::size_t>(k)].get(), prec);
    arb_sub(J[static_cast<std::size_t>(k - 1)].get(), t.get(), J[static_cast<std::size_t>(k + 1)].get(), prec);
  }
}

// The degree n whose rest 4 |x/2|^(n+1) / (n+1)! lies below 2^log2_target, at most max_degree
// (0 where none does), and that bound in `rest`.
inline slong degree_for(mag_t rest, const ball& x, double log2_target, slong max_degree) {
  mag_value half;
  arb_get_mag(half.m, x.get());
  mag_mul_2exp_si(half.m, half.m, -1);
  mag_value power, inverse_factorial;
  for (slong n = 1; n <= max_degree; ++n) {
    if (mag_cmp_2exp_si(half.m, 0) > 0 && mag_get_d(half.m) > 0.5 * static_cast<double>(n + 2)) continue;
    mag_pow_ui(power.m, half.m, static_cast<ulong>(n + 1));
    mag_rfac_ui(inverse_factorial.m, static_cast<ulong>(n + 1));
    mag_mul(rest, power.m, inverse_factorial.m);
    mag_mul_2exp_si(rest, rest, 2);
    if (mag_cmp_2exp_si(rest, static_cast<slong>(std::floor(log2_target))) <= 0) return n;
  }
  return 0;
}

}  // namespace trig_of_linear

// out = sin(u) or cos(u) (`cosine`) for u = c0 + c1 s with no remainder and |c1| <= 4, of the
// degree whose rest lies below 2^log2_target; false (out untouched) where u is not such a model or
// no degree up to max_degree reaches the target.
inline bool trig_of_linear_model(chebyshev_model& out, bool cosine, const chebyshev_model& u, double log2_target,
                                 slong prec, slong max_degree) {
  using namespace trig_of_linear;
  if (u.length() > 2 || !mag_is_zero(u.remainder())) return false;
  ball x;
  if (u.length() == 2) arb_set(x.get(), u.coeff(1));
  mag_value xm;
  arb_get_mag(xm.m, x.get());
  if (arb_contains_zero(x.get()) || mag_get_d(xm.m) > largest_slope) return false;
  mag_value rest;
  const slong n = degree_for(rest.m, x, log2_target, max_degree);
  if (n == 0) return false;
  thread_local std::vector<ball> J;  // J_0 .. J_(n+1)
  bessel_values(J, n, x, prec);
  ball s0, c0;
  arb_sin_cos(s0.get(), c0.get(), u.coeff(0), prec);
  // The factor of 2 J_k for even k (the cos(x s) part) and for odd k (the sin(x s) part).
  ball even, odd;
  arb_set(even.get(), (cosine ? c0 : s0).get());
  arb_set(odd.get(), c0.get());
  if (cosine) arb_neg(odd.get(), s0.get());
  out.resize(n + 1);
  for (slong k = 0; k <= n; ++k) {
    arb_ptr c = out.coeff(k);
    arb_mul(c, J[static_cast<std::size_t>(k)].get(), (k % 2 == 0 ? even : odd).get(), prec);
    if (k > 0) arb_mul_2exp_si(c, c, 1);
    if ((k / 2) % 2 == 1) arb_neg(c, c);
  }
  mag_set(out.remainder(), rest.m);  // |sin c0|, |cos c0| <= 1
  return true;
}

}  // namespace eulervop::detail
