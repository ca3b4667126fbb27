// An elementary function of a Chebyshev model (chebyshev_model.hpp), for the general path of
// --certify (docs/certified.md, "Functions of time and state"): the model of f(u) for
// f in {sin, cos, exp, log, sqrt, tanh, atan, sinh, cosh, 1/x}, with a proven remainder.
//
// u is a polynomial p (ball coefficients c_k) plus a remainder d. Then
//   f(u) = f(p) + (f(p + e) - f(p)),  |e| <= d,  |f(p + e) - f(p)| <= sup |f'| d  over u's range,
// and f(p) is analytic in s wherever f is analytic on p's values. Its degree-n interpolant at the
// Lobatto points s_j = -cos(j pi / n), whose coefficients come from the values f(p(s_j)) in balls
// (detail/ball_node_transform.hpp), is within
//   4 M rho^-n / (rho - 1)
// of f(p) on [-1, 1] when f(p) is analytic in the Bernstein ellipse E_rho (foci -1 and 1, semi-axes
// summing to rho) and |f(p)| <= M there (L. N. Trefethen, Approximation Theory and Approximation
// Practice, SIAM 2013, Theorem 8.2). On the closed ellipse |T_k(z)| <= (rho^k + rho^-k) / 2, so
// p(z) lies in the disk of centre c_0 and radius B = sum_{k>=1} |c_k| (rho^k + rho^-k) / 2, and M
// is |f| over that disk (Arb's complex balls). f is analytic on the disk when it avoids f's
// singularities: for log and sqrt (principal branches) when the disk lies in the right half
// plane, for 1/x when it avoids 0, for tanh when it avoids the poles i (pi/2 + k pi), for atan
// when it avoids the branch cuts (+-i) [1, inf) (sin, cos, exp, sinh and cosh are entire).
// Several rho are tried; the one needing the fewest points wins.
#pragma once

#include <eulervop/certify/ball.hpp>
#include <eulervop/certify/detail/ball_node_transform.hpp>
#include <eulervop/certify/detail/chebyshev_model.hpp>
#include <eulervop/certify/detail/trig_of_linear.hpp>

#include <acb.h>
#include <flint/fmpq.h>
#include <arb.h>
#include <arb_mat.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

namespace eulervop::detail {

enum class elementary { sin, cos, exp, log, sqrt, tanh, atan, sinh, cosh, inverse };

// Why f is refused on a range (elementary_on_ball false), for the messages.
inline const char* outside_domain(elementary f) {
  return f == elementary::inverse ? "a division by a value that may be 0"
         : f == elementary::log   ? "the log of a value that is not certainly positive"
         : f == elementary::sqrt  ? "the square root of a value that is not certainly positive"
                                  : "a value that is not finite";
}

// The ends of a real ball x, and those of |x|, rounded outward.
struct ball_ends {
  arf_t lo, hi, abs_lo, abs_hi;
  ball_ends(const ball& x, slong prec) {
    arf_init(lo);
    arf_init(hi);
    arf_init(abs_lo);
    arf_init(abs_hi);
    arb_get_lbound_arf(lo, x.get(), prec);
    arb_get_ubound_arf(hi, x.get(), prec);
    arb_get_abs_lbound_arf(abs_lo, x.get(), prec);
    arb_get_abs_ubound_arf(abs_hi, x.get(), prec);
  }
  ~ball_ends() {
    arf_clear(lo);
    arf_clear(hi);
    arf_clear(abs_lo);
    arf_clear(abs_hi);
  }
  ball_ends(const ball_ends&) = delete;
  ball_ends& operator=(const ball_ends&) = delete;
};

// out = g over [a, b] for g monotone there, from g at the two ends (f(a), f(b) in balls). Arb's
// enclosure of g over a wide ball takes the derivative's bound at the midpoint and can be far
// wider, even unbounded: sech(0 +- 40) as 1 / (1 +- 40 sinh 40).
template <class G>
void monotone_over(ball& out, const arf_t a, const arf_t b, G&& g, slong prec) {
  ball ga, gb;
  arb_set_arf(ga.get(), a);
  arb_set_arf(gb.get(), b);
  g(ga.get(), prec);
  g(gb.get(), prec);
  arb_union(out.get(), ga.get(), gb.get(), prec);
}

// Whether the values given are finite (null: not asked for).
inline bool all_finite(const ball* v, const ball* d1, const ball* d2) {
  const auto finite = [](const ball* b) { return !b || arb_is_finite(b->get()); };
  return finite(v) && finite(d1) && finite(d2);
}

// f(x), f'(x) and f''(x) of tanh, atan, sinh and cosh over a real ball, into v, d1 and d2 (any
// may be null), each monotone piece from its ends: tanh, atan and sinh rise; cosh, sech^2 and
// 1 / (1 + x^2) are even and monotone in |x|. tanh' = sech^2, tanh'' = -2 tanh tanh';
// atan' = 1 / (1 + x^2), atan'' = -2 x atan'^2; sinh' = cosh'' = cosh, cosh' = sinh'' = sinh.
// False where a value is not finite.
inline bool hyperbolic_on_ball(elementary f, const ball& x, ball* value_out, ball* d1, ball* d2, slong prec) {
  using arb_function = void (*)(arb_ptr, arb_srcptr, slong);
  const auto in_place = [](arb_function g) { return [g](arb_ptr y, slong p) { g(y, y, p); }; };
  const auto sech2 = [](arb_ptr y, slong p) {
    arb_sech(y, y, p);
    arb_mul(y, y, y, p);
  };
  const auto inverse_1p_square = [](arb_ptr y, slong p) {  // 1 / (1 + y^2)
    arb_mul(y, y, y, p);
    arb_add_ui(y, y, 1, p);
    arb_inv(y, y, p);
  };
  const ball_ends e(x, prec);
  const arb_function value = f == elementary::tanh   ? arb_tanh
                             : f == elementary::atan ? arb_atan
                             : f == elementary::sinh ? arb_sinh
                                                     : arb_cosh;
  ball v;
  if (f == elementary::cosh)
    monotone_over(v, e.abs_lo, e.abs_hi, in_place(value), prec);
  else
    monotone_over(v, e.lo, e.hi, in_place(value), prec);
  if (value_out) arb_set(value_out->get(), v.get());
  if (!d1 && !d2) return all_finite(value_out, d1, d2);
  ball d;  // f'
  switch (f) {
    case elementary::tanh:
      monotone_over(d, e.abs_lo, e.abs_hi, sech2, prec);
      if (d2) arb_mul(d2->get(), v.get(), d.get(), prec);
      break;
    case elementary::atan:
      monotone_over(d, e.abs_lo, e.abs_hi, inverse_1p_square, prec);
      if (d2) {
        arb_mul(d2->get(), d.get(), d.get(), prec);
        arb_mul(d2->get(), d2->get(), x.get(), prec);
      }
      break;
    case elementary::sinh: monotone_over(d, e.abs_lo, e.abs_hi, in_place(arb_cosh), prec); break;
    default: monotone_over(d, e.lo, e.hi, in_place(arb_sinh), prec); break;  // cosh
  }
  if (d1) arb_set(d1->get(), d.get());
  if (d2 && (f == elementary::tanh || f == elementary::atan)) {  // -2 times the product above
    arb_mul_2exp_si(d2->get(), d2->get(), 1);
    arb_neg(d2->get(), d2->get());
  } else if (d2) {
    arb_set(d2->get(), v.get());
  }
  return all_finite(value_out, d1, d2);
}

// f(x), f'(x) and f''(x) over a real ball (any may be null); false where x reaches outside f's
// domain (log, sqrt: x must be certainly positive; 1/x: x must not hold 0).
inline bool elementary_on_ball(elementary f, const ball& x, ball* v, ball* d1, ball* d2, slong prec) {
  const arb_srcptr a = x.get();
  if ((f == elementary::log || f == elementary::sqrt) && !arb_is_positive(a)) return false;
  if (f == elementary::inverse && arb_contains_zero(a)) return false;
  ball s, c, t;
  switch (f) {
    case elementary::sin:
    case elementary::cos:
      arb_sin_cos(s.get(), c.get(), a, prec);
      if (f == elementary::sin) {
        if (v) arb_set(v->get(), s.get());
        if (d1) arb_set(d1->get(), c.get());
        if (d2) arb_neg(d2->get(), s.get());
      } else {
        if (v) arb_set(v->get(), c.get());
        if (d1) arb_neg(d1->get(), s.get());
        if (d2) arb_neg(d2->get(), c.get());
      }
      break;
    case elementary::exp:
      arb_exp(t.get(), a, prec);
      if (v) arb_set(v->get(), t.get());
      if (d1) arb_set(d1->get(), t.get());
      if (d2) arb_set(d2->get(), t.get());
      break;
    case elementary::log:
      if (v) arb_log(v->get(), a, prec);
      arb_inv(t.get(), a, prec);  // 1/x
      if (d1) arb_set(d1->get(), t.get());
      if (d2) {
        arb_mul(d2->get(), t.get(), t.get(), prec);
        arb_neg(d2->get(), d2->get());
      }
      break;
    case elementary::sqrt:
      arb_sqrt(s.get(), a, prec);
      if (v) arb_set(v->get(), s.get());
      arb_inv(t.get(), s.get(), prec);  // x^-1/2
      if (d1) arb_mul_2exp_si(d1->get(), t.get(), -1);
      if (d2) {  // -x^-3/2 / 4
        arb_mul(c.get(), t.get(), t.get(), prec);
        arb_mul(d2->get(), c.get(), t.get(), prec);
        arb_mul_2exp_si(d2->get(), d2->get(), -2);
        arb_neg(d2->get(), d2->get());
      }
      break;
    case elementary::inverse:
      arb_inv(t.get(), a, prec);
      if (v) arb_set(v->get(), t.get());
      arb_mul(s.get(), t.get(), t.get(), prec);  // x^-2
      if (d1) arb_neg(d1->get(), s.get());
      if (d2) {
        arb_mul(d2->get(), s.get(), t.get(), prec);
        arb_mul_2exp_si(d2->get(), d2->get(), 1);
      }
      break;
    default: return hyperbolic_on_ball(f, x, v, d1, d2, prec);  // tanh, atan, sinh, cosh
  }
  return all_finite(v, d1, d2);
}

// Whether every point of the ball y lies in (-h, h).
inline bool certainly_within(const arb_t y, const arb_t h) {
  ball m;
  arb_abs(m.get(), y);
  return arb_lt(m.get(), h) != 0;
}

// f over a complex ball; false where f may not be analytic on it (the conditions above). tanh's
// poles i (pi/2 + k pi) and atan's branch points +-i and cuts (+-i) [1, inf) all lie on the
// imaginary axis, at |Im z| >= pi/2 and >= 1: a ball whose real part excludes 0, or whose
// imaginary part lies within those bounds, avoids them. Arb's acb_atan is the principal branch
// with those cuts; on a ball that meets a cut it encloses the values on both sides, a bound of
// |atan| there but no analytic function, so such a ball is refused here before it is asked.
inline bool elementary_on_complex(elementary f, const acb_t z, acb_t out, slong prec) {
  ball bound;
  switch (f) {
    case elementary::sin: acb_sin(out, z, prec); break;
    case elementary::cos: acb_cos(out, z, prec); break;
    case elementary::exp: acb_exp(out, z, prec); break;
    case elementary::sinh: acb_sinh(out, z, prec); break;
    case elementary::cosh: acb_cosh(out, z, prec); break;
    case elementary::tanh:
    case elementary::atan:
      if (f == elementary::tanh) {
        arb_const_pi(bound.get(), prec);
        arb_mul_2exp_si(bound.get(), bound.get(), -1);
      } else {
        arb_one(bound.get());
      }
      if (!arb_is_nonzero(acb_realref(z)) && !certainly_within(acb_imagref(z), bound.get())) return false;
      if (f == elementary::tanh)
        acb_tanh(out, z, prec);
      else
        acb_atan(out, z, prec);
      break;
    case elementary::log:
    case elementary::sqrt:
      if (!arb_is_positive(acb_realref(z))) return false;
      if (f == elementary::log)
        acb_log(out, z, prec);
      else
        acb_sqrt(out, z, prec);
      break;
    case elementary::inverse:
      if (acb_contains_zero(z)) return false;
      acb_inv(out, z, prec);
      break;
  }
  return acb_is_finite(out);
}

// The Lobatto points and the interpolation transform of degree n at a precision, built once per
// thread (each costs O(n^2) enclosed cosines).
class lobatto_interpolation {
 public:
  lobatto_interpolation(slong prec, std::size_t n) : prec_(prec), transform_(prec, n, 1), points_(n + 1), tables_(n + 1) {
    for (std::size_t j = 0; j <= n; ++j) {  // s_j = -cos(j pi / n)
      fmpq_t angle;
      fmpq_init(angle);
      fmpq_set_si(angle, static_cast<slong>(j), static_cast<ulong>(n));
      arb_cos_pi_fmpq(points_[j].get(), angle, prec);
      arb_neg(points_[j].get(), points_[j].get());
      fmpq_clear(angle);
    }
    arb_mat_init(coefficients_, static_cast<slong>(n + 1), 1);
  }
  ~lobatto_interpolation() { arb_mat_clear(coefficients_); }
  lobatto_interpolation(const lobatto_interpolation&) = delete;
  lobatto_interpolation& operator=(const lobatto_interpolation&) = delete;

  static lobatto_interpolation& of(slong prec, std::size_t n) {
    thread_local std::map<std::pair<slong, std::size_t>, std::unique_ptr<lobatto_interpolation>> cache;
    auto& slot = cache[{prec, n}];
    if (!slot) slot = std::make_unique<lobatto_interpolation>(prec, n);
    return *slot;
  }

  const ball& point(std::size_t j) const { return points_[j]; }
  // p(s_j) for a polynomial p (its remainder not included), from the values T_k(s_j) kept per
  // point: the points stay, the polynomials change from segment to segment, so each point's
  // values are computed once (grown to the longest p asked).
  void evaluate_at(ball& out, const chebyshev_model& p, std::size_t j) {
    std::unique_ptr<chebyshev_values>& T = tables_[j];
    const slong length = std::max<slong>(p.length(), 1);
    if (!T || T->length() < length) T = std::make_unique<chebyshev_values>(length, points_[j], prec_);
    arb_dot(out.get(), nullptr, 0, p.coeffs(), 1, T->get(), 1, p.length(), prec_);
  }
  arb_ptr value(std::size_t j) { return transform_.value(j, 0); }
  // The interpolant's coefficients from the values set, into out (length n + 1).
  void coefficients(chebyshev_model& out) {
    transform_.apply(coefficients_);
    out.resize(arb_mat_nrows(coefficients_));
    for (slong k = 0; k < arb_mat_nrows(coefficients_); ++k) arb_set(out.coeff(k), arb_mat_entry(coefficients_, k, 0));
  }

 private:
  slong prec_;
  ball_node_transform transform_;
  std::vector<ball> points_;
  std::vector<std::unique_ptr<chebyshev_values>> tables_;
  arb_mat_t coefficients_;
};

// The Bernstein ellipse taken for f(p): its rho, the points' degree n it needs, and M >= |f| on it.
struct ellipse_choice {
  std::size_t n = 0;  // 0: no ellipse avoids f's singularities
  double rho = 0;
  mag_value M;
};

// B = sum_{k>=1} |c_k| (rho^k + rho^-k) / 2, upward (rho is exact in double): the radius of the
// disk about c_0 that holds p(z) on E_rho, since |T_k(z)| <= (rho^k + rho^-k) / 2 there.
inline void ellipse_disk_radius(mag_t B, const std::vector<mag_value>& c, double rho) {
  mag_value power, inv_power, term, r, ri, rl;
  mag_zero(B);
  mag_set_d(r.m, rho);
  mag_set_d_lower(rl.m, rho);
  mag_one(ri.m);
  mag_div(ri.m, ri.m, rl.m);
  mag_one(power.m);
  mag_one(inv_power.m);
  for (std::size_t k = 1; k < c.size(); ++k) {
    mag_mul(power.m, power.m, r.m);
    mag_mul(inv_power.m, inv_power.m, ri.m);
    mag_add(term.m, power.m, inv_power.m);
    mag_mul(term.m, term.m, c[k].m);
    mag_add(B, B, term.m);
  }
  mag_mul_2exp_si(B, B, -1);
}

// |f| over the disk of centre c_0 (with its radius) and radius B, as M; false where f may not be
// analytic on it or M is not finite.
inline bool bound_on_disk(mag_t M, elementary f, arb_srcptr c0, const mag_t B, slong prec) {
  acb_t disk, image;
  acb_init(disk);
  acb_init(image);
  if (c0)
    arb_set(acb_realref(disk), c0);
  else
    arb_zero(acb_realref(disk));
  arb_add_error_mag(acb_realref(disk), B);
  arb_zero(acb_imagref(disk));
  arb_add_error_mag(acb_imagref(disk), B);
  const bool analytic = elementary_on_complex(f, disk, image, prec);
  if (analytic) acb_get_mag(M, image);
  acb_clear(disk);
  acb_clear(image);
  return analytic && mag_is_finite(M);
}

// The ellipse among rho in {1.5, ..., 256} whose bound 4 M rho^-n / (rho - 1) (Trefethen,
// Theorem 8.2) reaches 2^log2_target with the fewest points (at least 8). The rho grow, and so do
// the disks: the first that fails ends the search.
inline ellipse_choice choose_ellipse(elementary f, const chebyshev_model& u, double log2_target, slong prec) {
  const slong L = u.length();
  std::vector<mag_value> c(static_cast<std::size_t>(std::max<slong>(L, 1)));  // |c_k|, k >= 1
  for (slong k = 1; k < L; ++k) arb_get_mag(c[static_cast<std::size_t>(k)].m, u.coeff(k));
  ellipse_choice best;
  for (const double rho : {1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0, 64.0, 128.0, 256.0}) {
    mag_value B, M;
    ellipse_disk_radius(B.m, c, rho);
    if (!mag_is_finite(B.m)) break;
    if (!bound_on_disk(M.m, f, L > 0 ? u.coeff(0) : nullptr, B.m, prec)) break;
    // The least n with 4 M rho^-n / (rho - 1) <= target: the choice only (the bound is computed
    // upward for the n taken, composition_remainder).
    const double need = 2 + mag_get_d_log2_approx(M.m) - std::log2(rho - 1) - log2_target;
    const double n = std::max(8.0, std::ceil(need / std::log2(rho)));
    if (!std::isfinite(n)) continue;
    const auto ni = static_cast<std::size_t>(std::min(n, 1e6));
    if (best.n == 0 || ni < best.n) {
      best.n = ni;
      best.rho = rho;
      mag_set(best.M.m, M.m);
    }
  }
  return best;
}

// out = the degree-n interpolant of f(p) at the Lobatto points (p: u's polynomial, without its
// remainder), from the values f(p(s_j)) in balls.
inline void interpolate(chebyshev_model& out, elementary f, const chebyshev_model& u, std::size_t n, slong prec) {
  lobatto_interpolation& li = lobatto_interpolation::of(prec, n);
  ball p, v;
  for (std::size_t j = 0; j <= n; ++j) {
    li.evaluate_at(p, u, j);
    if (!elementary_on_ball(f, p, &v, nullptr, nullptr, prec))
      throw std::domain_error("a value outside the function's domain on the segment");
    arb_set(li.value(j), v.get());
  }
  li.coefficients(out);
}

// The remainder of f(u)'s model: the interpolation's bound 4 M rho^-n / (rho - 1) (rho and rho - 1
// rounded down, so the bound rounds up), and u's remainder times d1 >= sup |f'| over u's range
// (the mean value theorem).
inline void composition_remainder(mag_t out, const ellipse_choice& e, std::size_t n, const ball& d1,
                                  const chebyshev_model& u) {
  mag_value t, rhom, rho_minus_one;
  mag_set_d_lower(rhom.m, e.rho);
  mag_set_d_lower(rho_minus_one.m, e.rho - 1);
  mag_pow_ui_lower(t.m, rhom.m, n);
  mag_div(out, e.M.m, t.m);
  mag_div(out, out, rho_minus_one.m);
  mag_mul_2exp_si(out, out, 2);
  arb_get_mag(t.m, d1.get());
  mag_addmul(out, t.m, u.remainder());
}

// out = the model of f(u) (out distinct from u), its remainder within 2^-target_bits of sup |f|
// over u's range where at most `max_degree` points reach that; std::domain_error where u's range
// leaves f's domain.
inline void compose(chebyshev_model& out, elementary f, const chebyshev_model& u, slong prec, slong target_bits,
                    std::size_t max_degree = 256) {
  ball range, fr, d1;
  range_of(range, u);
  if (!elementary_on_ball(f, range, &fr, &d1, nullptr, prec)) throw std::domain_error(outside_domain(f));
  // The target: 2^-target_bits of sup |f| over the range (of 1 where f may vanish throughout).
  mag_value scale;
  arb_get_mag(scale.m, fr.get());
  if (mag_is_zero(scale.m)) mag_one(scale.m);
  const double log2_target = mag_get_d_log2_approx(scale.m) - static_cast<double>(target_bits);
  if ((f == elementary::sin || f == elementary::cos) &&
      trig_of_linear_model(out, f == elementary::cos, u, log2_target, prec, static_cast<slong>(max_degree)))
    return;  // a linear argument (the time): the series in closed form
  const ellipse_choice e = choose_ellipse(f, u, log2_target, prec);
  if (e.n == 0) {
    // No ellipse avoids f's singularities (u comes close to one): f over the whole range, as a
    // constant and a remainder.
    out.resize(1);
    arf_set(arb_midref(out.coeff(0)), arb_midref(fr.get()));
    mag_zero(arb_radref(out.coeff(0)));
    mag_set(out.remainder(), arb_radref(fr.get()));
    return;
  }
  const std::size_t n = std::min(e.n, max_degree);
  interpolate(out, f, u, n, prec);
  mag_value rem;
  composition_remainder(rem.m, e, n, d1, u);
  mag_set(out.remainder(), rem.m);
}

}  // namespace eulervop::detail
