// What the certificate proves at a row's tau inside a segment (docs/certified.md, "How", step 6):
//   |y(tau) - P(tau)|_2 <= exp(mu dt) |e(a)| + sup|r| + dt exp(mu dt) (|J| sup|r| + c R^2),
// dt = tau - a, and the row's radius adds |printed - P(tau)|_2, evaluated in intervals from the
// printed decimals, so the rounding of the printed digits is included.
#pragma once

#include <eulervop/certify/detail/a_priori_bound.hpp>
#include <eulervop/certify/detail/real.hpp>
#include <eulervop/certify/detail/segment_polynomial.hpp>
#include <eulervop/certify/exact_problem.hpp>
#include <eulervop/certify/interval.hpp>
#include <eulervop/core/scalar.hpp>

#include <mpfi.h>

#include <array>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace eulervop {

// At tau: `error` = [0, e] with |y(tau) - P(tau)|_2 <= e, and P(tau) enclosed; `state` = [0, Y]
// with |y| <= Y on the whole segment, and `rate` = [0, F] with |y'| <= F wherever |y| <= 2 Y (for
// moving a bound along tau by a rounding's worth).
struct row_enclosure {
  interval error;
  std::vector<interval> P;
  interval state, rate;
};

// An upper bound of |y(tau) - printed|_2 (Eq. 20's norm) from the enclosure at tau, the row
// printed as the decimals `printed`: [0, the bound].
inline interval row_radius(const row_enclosure& at, const std::array<std::string, 3>& printed) {
  const mpfr_prec_t bits = at.error.bits();
  interval out = interval::zero(bits), t = interval::zero(bits), sq = interval::zero(bits);
  for (int i = 0; i < 3; ++i) {
    detail::set_decimal(t, printed[i]);
    mpfi_sub(t.get(), t.get(), at.P[i].get());
    mpfi_abs(t.get(), t.get());
    mpfi_sqr(t.get(), t.get());
    mpfi_add(sq.get(), sq.get(), t.get());
  }
  mpfi_sqrt(sq.get(), sq.get());
  mpfi_add(out.get(), at.error.get(), sq.get());
  detail::to_zero_hull(out);  // the upper end only: [0, sup]
  return out;
}

namespace detail {

// t_k = T_k(s^) for k < n1 on the grid 2^-bits (toward zero, L limbs each, their signs apart) and
// deviation_k >= |T_k(s) - t_k| (polynomial_on_grid, below).
template <std::size_t L>
bool chebyshev_on_grid(const interval& s, std::size_t n1, mpfr_prec_t bits, std::vector<mp_limb_t>& t,
                       std::vector<mp_limb_t>& t_negative, std::vector<double>& deviation) {
  const double unit = std::ldexp(1.0, -static_cast<int>(bits));
  real w(64), two_s(bits), prev(bits), cur(bits), next(bits);
  mpfr_srcptr s_hat = &s.get()->left;
  width_up(w, s);
  const double d = mpfr_get_d(w.get(), MPFR_RNDU);
  const double s_abs = std::abs(mpfr_get_d(s_hat, MPFR_RNDA));
  mpfr_mul_2ui(two_s.get(), s_hat, 1, MPFR_RNDN);  // exact
  double e_prev = 0, e_cur = d;
  mpfr_set_ui(prev.get(), 1, MPFR_RNDN);
  mpfr_set(cur.get(), s_hat, MPFR_RNDN);
  for (std::size_t k = 0; k < n1; ++k) {
    mpfr_srcptr tk = prev.get();
    double ek = e_prev;
    if (k == 1) {
      tk = cur.get();
      ek = e_cur;
    } else if (k >= 2) {
      mpfr_fms(next.get(), two_s.get(), cur.get(), prev.get(), MPFR_RNDN);
      const double e_next =
          (2 * s_abs * e_cur + e_prev + 2 * d + unit * std::abs(mpfr_get_d(next.get(), MPFR_RNDA))) * (1 + 1e-12);
      mpfr_swap(prev.get(), cur.get());
      mpfr_swap(cur.get(), next.get());
      e_prev = e_cur;
      e_cur = e_next;
      tk = cur.get();
      ek = e_cur;
    }
    if (!limbs::load_truncated(tk, bits, L, &t[k * L], t_negative[k])) return false;
    deviation[k] = (ek + unit) * (1 + 1e-12);
  }
  return true;
}

// Component i of P: sum q_k t_k as one exact integer, rounded once to nearest, widened by the
// bound (polynomial_on_grid, below).
template <std::size_t L>
void component_on_grid(const segment_polynomial& S, int i, const std::vector<mp_limb_t>& t,
                       const std::vector<mp_limb_t>& t_negative, const std::vector<double>& deviation, interval& P) {
  constexpr std::size_t W = 2 * L + 1;
  const std::size_t n1 = S.n1;
  const mpfr_prec_t bits = S.bits;
  limbs::column_sum<L> sum;
  double weighted = 0;
  for (std::size_t k = 0; k < n1; ++k) {
    const std::size_t q = i * n1 + k;
    limbs::product_columns<L> product;
    limbs::columns_of<L>(&S.grid.q[q * L], &t[k * L], product);
    sum.add(product, (S.grid.negative[q] ^ t_negative[k]) & 1);
    weighted += S.cmag[q] * deviation[k];
  }
  mp_limb_t acc[W];
  real y(bits), e(64);
  sum.to_limbs(acc, W);
  limbs::round_to(acc, W, y.get(), S.grid.shift + static_cast<long>(bits));
  // The bound: rad + the weighted deviations (their products may underflow: n1 denorm_min more)
  // + 2^-bits |y|, rounded up.
  mpfr_abs(e.get(), y.get(), MPFR_RNDU);
  mpfr_mul_2si(e.get(), e.get(), -static_cast<long>(bits), MPFR_RNDU);  // exact
  mpfr_add(e.get(), e.get(), S.grid.rad[i].get(), MPFR_RNDU);
  mpfr_add_d(e.get(), e.get(),
             (weighted + static_cast<double>(n1) * std::numeric_limits<double>::denorm_min()) * (1 + 1e-12),
             MPFR_RNDU);
  interval spread = interval::zero(64);
  mpfi_interv_fr(spread.get(), e.get(), e.get());
  mpfi_neg(spread.get(), spread.get());
  mpfi_put_fr(spread.get(), e.get());  // [-e, e]
  mpfi_set_fr(P.get(), y.get());
  mpfi_add(P.get(), P.get(), spread.get());
}

// P from its coefficients on their grid (segment_polynomial::grid) at s, an enclosure of
// dt / hl - 1 within [-1, 1]: with s^ its left end (|s - s^| <= d, its width), t_k = T_k(s^) by the
// three-term recurrence at the working precision (one rounding each, a fused multiply-subtract)
// and e_k >= |t_k - T_k(s)|:
//   e_0 = 0, e_1 = d, e_k = 2 |s^| e_(k-1) + e_(k-2) + 2 d + 2^-bits |t_k|   (|T_(k-1)(s)| <= 1),
// in double rounded up. Then with q_k t_k summed as one exact integer per component (t_k on the
// grid 2^-bits, toward zero: one step more) and rounded once to nearest,
//   |P(s) - sum q_k t_k| <= sum |p_k - q_k| |T_k| + sum |q_k| |T_k - t_k|
//                        <= rad + sum cmag_k (e_k + 2^-bits),
// plus the rounding's 2^-bits of the result. e_k grows like 2.4^k but multiplies p_k, which
// decay faster (as below). False where a t_k needs more than L limbs, or where 2^-bits is below
// double's range.
template <std::size_t L>
bool polynomial_on_grid(const segment_polynomial& S, const interval& s, std::vector<interval>& P) {
  const std::size_t n1 = S.n1;
  if (S.bits > 1000) return false;
  std::vector<mp_limb_t> t(n1 * L), t_negative(n1);
  std::vector<double> deviation(n1);
  if (!chebyshev_on_grid<L>(s, n1, S.bits, t, t_negative, deviation)) return false;
  for (int i = 0; i < 3; ++i) component_on_grid<L>(S, i, t, t_negative, deviation, P[i]);
  return true;
}

// P = sum p_k T_k(s) at s = dt / hl - 1, summed directly: T_k from the three-term recurrence,
// each clipped to [-1, 1] (where the exact T_k(s) lies). The recurrence's widths grow like
// 2.4^k, but they multiply p_k, which decay faster; Clenshaw's algorithm instead multiplies the
// coefficients' own widths by 2.4^k (2^118 at mpfr:256's degree), which would swamp the bound.
inline void polynomial_at(const segment_polynomial& S, const interval& dt, std::vector<interval>& P) {
  interval s = interval::zero(S.bits), t = interval::zero(S.bits), unit = interval::zero(S.bits);
  mpfi_div(s.get(), dt.get(), S.hl.get());
  mpfi_sub_ui(s.get(), s.get(), 1);
  mpfi_interv_si(unit.get(), -1, 1);
  mpfi_intersect(s.get(), s.get(), unit.get());  // the exact s lies in [-1, 1]
  bool done = false;
  if (S.grid.on_limbs)
    limbs::with_limb_count(S.grid.limbs, [&](auto L) { done = polynomial_on_grid<decltype(L)::value>(S, s, P); });
  if (done) return;
  std::vector<interval> Tk(S.n1, interval::zero(S.bits));
  mpfi_set_ui(Tk[0].get(), 1);
  if (S.n1 > 1) mpfi_set(Tk[1].get(), s.get());
  for (std::size_t k = 2; k < S.n1; ++k) {
    mpfi_mul(Tk[k].get(), Tk[k - 1].get(), s.get());
    mpfi_mul_2si(Tk[k].get(), Tk[k].get(), 1);
    mpfi_sub(Tk[k].get(), Tk[k].get(), Tk[k - 2].get());
    mpfi_intersect(Tk[k].get(), Tk[k].get(), unit.get());
  }
  for (int i = 0; i < 3; ++i) {
    mpfi_set_ui(P[i].get(), 0);
    for (std::size_t k = 0; k < S.n1; ++k) {
      mpfi_mul(t.get(), S.p[i * S.n1 + k].get(), Tk[k].get());
      mpfi_add(P[i].get(), P[i].get(), t.get());
    }
  }
}

// The enclosure at tau in the segment of S with the bounds B.
template <scalar T>
row_enclosure enclose_row(const T& tau, const exact_problem& problem, const segment_polynomial& S,
                          const segment_bounds& B) {
  const interval_precision_scope scope(S.bits);
  const interval zero = interval::zero(S.bits);
  row_enclosure out{zero, std::vector<interval>(3, zero), zero, zero};
  interval dt = zero, s = zero, e = zero, t = zero;
  set_exact(dt, tau);
  mpfi_sub(dt.get(), dt.get(), S.a.get());
  mpfi_mul(e.get(), B.mu.get(), dt.get());
  exp_at_64_bits(e);
  mpfi_mul(out.error.get(), e.get(), B.rho_a.get());
  mpfi_add(out.error.get(), out.error.get(), B.rsup2.get());
  mpfi_sqr(t.get(), B.R.get());
  t = remainder_bound(problem, t);
  mpfi_mul(s.get(), B.jmax.get(), B.rsup2.get());
  mpfi_add(t.get(), t.get(), s.get());
  mpfi_mul(t.get(), t.get(), e.get());
  mpfi_mul(t.get(), t.get(), dt.get());
  mpfi_add(out.error.get(), out.error.get(), t.get());
  to_zero_hull(out.error);
  polynomial_at(S, dt, out.P);
  // Y = |sup P|_2 + R; F = |G|_2 + c (2 Y)^2.
  for (int i = 0; i < 3; ++i) {
    mpfi_sqr(t.get(), S.psup[i].get());
    mpfi_add(out.state.get(), out.state.get(), t.get());
    mpfi_sqr(t.get(), problem.torque.G[i].get());
    mpfi_add(out.rate.get(), out.rate.get(), t.get());
  }
  mpfi_sqrt(out.state.get(), out.state.get());
  mpfi_add(out.state.get(), out.state.get(), B.R.get());
  to_zero_hull(out.state);
  mpfi_sqrt(out.rate.get(), out.rate.get());
  mpfi_mul_ui(t.get(), out.state.get(), 2);
  mpfi_sqr(t.get(), t.get());
  t = remainder_bound(problem, t);
  mpfi_add(out.rate.get(), out.rate.get(), t.get());
  to_zero_hull(out.rate);
  return out;
}

}  // namespace detail
}  // namespace eulervop
