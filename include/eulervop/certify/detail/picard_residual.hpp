// The Picard residual of a segment's polynomial (docs/certified.md, "How", step 1):
//   r(tau) = P(a) + int_a^tau f(P) - P(tau),   f(y)_i = a_i y_j y_k + G_i,
// (j, k) = euler_problem::quadratic_pair[i], a polynomial of degree 2N + 1 (f is quadratic, and the
// torque constant), so that sup |r| <= sum |r_k|.
//
// The products use T_m T_n = (T_{m+n} + T_{|m-n|}) / 2. Those of the large coefficients run on
// points of P's enclosures put on a grid, as exact integers (grid_integer.hpp), those far below
// the reference's precision in double. The integral and the cancellation against P run on MPFR
// numbers at the working precision, rounded to nearest, with a bound of every rounding carried
// beside them (Higham, "Accuracy and Stability of Numerical Algorithms", 2002, section 2.2: a
// rounded result is within 2^-p of its magnitude): intervals would round every operation twice
// and cost four times as much, for the few digits of r that the certificate uses. The bounds
// hold per component for the sum over the coefficients, which is all that sup |r|, r(1) and the
// doubles of r need.
#pragma once

#include <eulervop/certify/detail/bounded_chebyshev.hpp>
#include <eulervop/certify/detail/grid_integer.hpp>
#include <eulervop/certify/detail/linearized_flow.hpp>
#include <eulervop/certify/detail/real.hpp>
#include <eulervop/certify/detail/segment_polynomial.hpp>
#include <eulervop/certify/exact_problem.hpp>
#include <eulervop/certify/interval.hpp>

#include <mpfi.h>
#include <mpfr.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace eulervop::detail {

class picard_residual {
 public:
  // `a`: the problem's coefficients, each -1, 0 or 1 (unit_coefficients).
  picard_residual(mpfr_prec_t bits, std::size_t degree, const vec3<interval>& G, const std::array<int, 3>& a);

  // rsup, r1, rd, rrad and r_scale of P.
  void compute(const segment_polynomial& P);

  std::vector<interval> rsup;  // >= sup |r_i| on the segment (a point)
  std::vector<interval> r1;    // r_i(b), signed
  // r as doubles: 2^-r_scale times rd, rd within rrad (per component, summed over k) of the
  // exact coefficients scaled. At deep MPFR levels r lies far below double's range.
  std::vector<double> rd;
  std::array<double, 3> rrad{};
  long r_scale = 0;

 private:
  void grid_fallback(const segment_polynomial& P);
  double multiply(const segment_polynomial& P, int i);
  template <std::size_t L>
  double multiply_on_limbs(const segment_polynomial& P, int i);
  template <class IntegerPair>
  double pairs(const segment_polynomial& P, int i, IntegerPair&& integer_pair);
  template <class ExactSum>
  double finish_product(const segment_polynomial& P, int i, double rem, ExactSum&& exact_sum);
  void product_error(const segment_polynomial& P, int i, double rem_double);
  void integrate(const segment_polynomial& P, int i);
  void to_doubles(const segment_polynomial& P);

  mpfr_prec_t bits_;
  std::size_t n1_, np_, nr_;
  vec3<interval> G_;
  std::array<int, 3> a_;
  std::array<std::array<int, 2>, 3> factors_;  // the quadratic pairs, ascending
  // f_i (one component at a time, 2N + 1 coefficients) and r (3 x (2N + 2), from k = 1): MPFR
  // numbers at the working precision, rounded to nearest; hl / (2k) rounded to nearest (hl itself
  // at k = 1).
  std::vector<real> f_, r_, hl_over_2k_;
  // P's points on the grid of step 2^-shift_, a product's exact sums on the grid 2^-(2 shift_ + 1)
  // (T_m T_n's factor 1/2), one product (the first two made where the limbs below do not serve);
  // the products in double.
  std::vector<grid_integer> pq_, acc_;
  grid_integer pair_;
  // A sum on limbs (2 L + 1, P's L) to round; the grid's shift.
  std::vector<mp_limb_t> lacc_;
  long shift_ = 0;
  std::vector<double> gd_;
  double f_abs_ = 0;  // >= sum |f_k|
  // At 64 bits, rounded up: the error of f_i's coefficients (summed), then of r_i's.
  std::vector<real> product_rem_, r_error_;
  real bound_scratch_{64}, product_error_scale_{64}, width_{64}, f_rounding_{64};
  real tmp_;  // scratch at the working precision
  interval t_;
};

inline picard_residual::picard_residual(mpfr_prec_t bits, std::size_t degree, const vec3<interval>& G,
                                        const std::array<int, 3>& a)
    : rsup(3, interval::zero(error_bits)), r1(3, interval::zero(error_bits)), rd(3 * (2 * degree + 2), 0.0), bits_(bits),
      n1_(degree + 1), np_(2 * degree + 1), nr_(2 * degree + 2), G_(G), a_(a), f_(np_, real(bits)),
      r_(3 * nr_, real(bits)), hl_over_2k_(nr_, real(bits)), pair_(2 * bits + 128),
      lacc_(2 * ((static_cast<std::size_t>(bits) + 64) / 64) + 1), gd_(np_, 0.0), product_rem_(3, real(64)),
      r_error_(3, real(64)), tmp_(bits), t_(interval::zero(error_bits)) {
  for (int i = 0; i < 3; ++i) {
    const auto [j, k] = exact_problem::quadratic_pair[i];
    factors_[i] = {std::min(j, k), std::max(j, k)};
  }
  // 2^-p (1 + 2^-20): the relative rounding of a product's exact sums back to p bits.
  mpfr_ptr s = product_error_scale_.get();
  mpfr_set_ui_2exp(s, 1, -static_cast<long>(bits), MPFR_RNDU);
  mpfr_mul_d(s, s, 1 + std::ldexp(1.0, -20), MPFR_RNDU);
}

inline void picard_residual::compute(const segment_polynomial& P) {
  // hl is exact (segment_polynomial::place); hl / (2k) for k >= 2 once for the three components.
  mpfr_srcptr hl = &P.hl.get()->left;
  if (!mpfr_equal_p(hl, &P.hl.get()->right)) P.fail(outcome_kind::certify_non_finite);
  mpfr_set(hl_over_2k_[1].get(), hl, MPFR_RNDN);
  for (std::size_t k = 2; k < nr_; ++k)
    mpfr_div_ui(hl_over_2k_[k].get(), hl, static_cast<unsigned long>(2 * k), MPFR_RNDN);
  grid_fallback(P);
  for (int i = 0; i < 3; ++i) {
    product_error(P, i, multiply(P, i));
    integrate(P, i);
  }
  to_doubles(P);
}

// P's coefficients on their grid (segment_polynomial::grid), as GMP's integers where they do not
// fit on limbs.
inline void picard_residual::grid_fallback(const segment_polynomial& P) {
  shift_ = P.grid.shift;
  if (P.grid.on_limbs) return;
  if (pq_.empty()) pq_.assign(3 * n1_, grid_integer(bits_ + 64));
  for (std::size_t q = 0; q < 3 * n1_; ++q) to_grid(pq_[q], &P.p[q].get()->left, shift_);
}

// f_ = a_i P_j P_k + G_i, on the grid (exact) and in double (pairs); returns the bound of the
// double products' error.
inline double picard_residual::multiply(const segment_polynomial& P, int i) {
  double rem = 0;
  if (P.grid.on_limbs &&
      limbs::with_limb_count(P.grid.limbs, [&](auto L) { rem = multiply_on_limbs<decltype(L)::value>(P, i); }))
    return rem;
  if (acc_.empty()) acc_.assign(np_, grid_integer(2 * bits_ + 128));
  const grid_integer* A = &pq_[factors_[i][0] * n1_];
  const grid_integer* B = &pq_[factors_[i][1] * n1_];
  for (std::size_t k = 0; k < np_; ++k) mpz_set_ui(acc_[k].get(), 0);
  rem = pairs(P, i, [&](std::size_t m, std::size_t n, std::size_t d) {
    mpz_mul(pair_.get(), A[m].get(), B[n].get());
    mpz_add(acc_[m + n].get(), acc_[m + n].get(), pair_.get());
    mpz_add(acc_[d].get(), acc_[d].get(), pair_.get());
  });
  return finish_product(P, i, rem, [&](std::size_t k, mpfr_ptr y, long shift, double) {
    mpfr_set_z_2exp(y, acc_[k].get(), -shift, MPFR_RNDN);
    return false;
  });
}

template <std::size_t L>
double picard_residual::multiply_on_limbs(const segment_polynomial& P, int i) {
  constexpr std::size_t W = 2 * L + 1;
  const mp_limb_t* A = &P.grid.q[factors_[i][0] * n1_ * L];
  const mp_limb_t* B = &P.grid.q[factors_[i][1] * n1_ * L];
  const mp_limb_t* A_neg = &P.grid.negative[factors_[i][0] * n1_];
  const mp_limb_t* B_neg = &P.grid.negative[factors_[i][1] * n1_];
  std::vector<limbs::column_sum<L>> sums(np_);
  const double rem = pairs(P, i, [&](std::size_t m, std::size_t n, std::size_t d) {
    limbs::product_columns<L> p;
    limbs::columns_of<L>(&A[m * L], &B[n * L], p);
    const unsigned negative = (A_neg[m] ^ B_neg[n]) & 1;
    sums[m + n].add(p, negative);
    sums[d].add(p, negative);
  });
  return finish_product(P, i, rem, [&](std::size_t k, mpfr_ptr y, long shift, double d) {
    sums[k].to_limbs(lacc_.data(), W);
    const bool added = limbs::add_double(lacc_.data(), W, d, shift);
    limbs::round_to(lacc_.data(), W, y, shift);
    return added;
  });
}

// Runs over the pairs (m, n) of product i: those far below the precision of the reference
// (|a_m| |b_n| < 2^-(bits - 77) of the state squared) in double, the others by `integer_pair`
// (m, n, |m - n|) on the grid. Returns a bound of the double products' total error: the sums have
// at most 2 (N+1) terms each, the exact coefficients differ from cd by crad, and an underflow
// allowance covers results near zero.
template <class IntegerPair>
double picard_residual::pairs(const segment_polynomial& P, int i, IntegerPair&& integer_pair) {
  const int ca = factors_[i][0], cb = factors_[i][1];
  const double* cmag = P.cmag.data();
  std::fill(gd_.begin(), gd_.end(), 0.0);
  double rem = 0, small = 0;
  std::size_t in_double = 0;
  for (std::size_t m = 0; m < n1_; ++m)
    for (std::size_t n = 0; n < n1_; ++n) {
      const std::size_t d = m > n ? m - n : n - m;
      if (cmag[ca * n1_ + m] * cmag[cb * n1_ + n] < P.tail_level) {
        const double pr = 0.5 * P.cd[ca * n1_ + m] * P.cd[cb * n1_ + n];
        gd_[m + n] += pr;
        gd_[d] += pr;
        small += std::abs(pr);
        ++in_double;
        rem += cmag[ca * n1_ + m] * P.crad[cb * n1_ + n] + P.crad[ca * n1_ + m] * cmag[cb * n1_ + n];
        continue;
      }
      integer_pair(m, n, d);
    }
  return in_double ? (gamma_of(2 * n1_ + 2) * 2 * small + rem + underflow_allowance(4 * n1_ * n1_)) * (1 + 1e-12)
                   : 0.0;
}

// f_ from the exact sums on the grid 2^-(2 shift + 1) and the double ones gd_k:
// `exact_sum(k, y, shift, d)` rounds sum k plus d to nearest into y where d falls on the grid
// (true), or sum k alone (false), and gd_k is then added rounded to nearest. Back at p bits (the
// one rounding of an exact sum is product_error's), times a_i, exact (-1, 0 or 1), plus G_i's left
// end at k = 0, rounded to nearest. Those other roundings, the double sums' share of the first and
// G_i's width go to f_rounding_. Returns `rem`.
template <class ExactSum>
double picard_residual::finish_product(const segment_polynomial& P, int i, double rem, ExactSum&& exact_sum) {
  double small = 0;  // sum |gd_k|
  for (std::size_t k = 0; k < np_; ++k) {
    mpfr_ptr y = f_[k].get();
    const bool with_double = gd_[k] != 0 && a_[i] != 0;
    const bool added = exact_sum(k, y, 2 * shift_ + 1, with_double ? gd_[k] : 0.0);
    if (a_[i] < 0) mpfr_neg(y, y, MPFR_RNDN);
    if (a_[i] == 0) mpfr_set_ui(y, 0, MPFR_RNDN);
    if (with_double) {
      if (!added) mpfr_add_d(y, y, a_[i] * gd_[k], MPFR_RNDN);
      small += std::abs(gd_[k]);
    }
  }
  const auto& G = *G_[i].get();
  mpfr_add(f_[0].get(), f_[0].get(), &G.left, MPFR_RNDN);
  // f_abs_ >= sum |f_k|: the exact sums are at most A B (product_error), each rounded twice at
  // most, plus the double ones and G.
  mpfr_ptr e = f_rounding_.get();
  mpfr_mul(e, P.grid.abs[factors_[i][0]].get(), P.grid.abs[factors_[i][1]].get(), MPFR_RNDU);
  f_abs_ = (mpfr_get_d(e, MPFR_RNDU) + small + std::abs(mpfr_get_d(&G.left, MPFR_RNDA))) * (1 + 1e-9);
  mpfr_set_d(e, f_abs_, MPFR_RNDU);
  mpfr_mul_2si(e, e, -static_cast<long>(bits_), MPFR_RNDU);
  mpfr_sub(width_.get(), &G.right, &G.left, MPFR_RNDU);
  mpfr_add(e, e, width_.get(), MPFR_RNDU);
  return rem;
}

// Summed over the coefficients of one product, the grid products' error is at most
// A B' + A' B + A' B' + 2^-p (1 + 2^-20) A B, with A = sum |q_m|, A' = sum |a_m - q_m| (the same
// for b): sum_k |g_k - g^_k| <= sum_mn |a_m b_n - q_m r_n| (each pair's two halves), and the
// rounding of each exact sum to p bits is at most 2^-p |g^_k|, sum_k |g^_k| <= A B. |a_i| <= 1
// leaves it a bound of a_i's multiple. Then the double products' error `rem_double` (pairs) and
// the roundings after the exact sums (finish_product).
inline void picard_residual::product_error(const segment_polynomial& P, int i, double rem_double) {
  const int ca = factors_[i][0], cb = factors_[i][1];
  real& e = product_rem_[i];
  real& w = bound_scratch_;
  const std::vector<real>& A = P.grid.abs;
  const std::vector<real>& R = P.grid.rad;
  mpfr_mul(e.get(), A[ca].get(), R[cb].get(), MPFR_RNDU);
  mpfr_mul(w.get(), R[ca].get(), A[cb].get(), MPFR_RNDU);
  mpfr_add(e.get(), e.get(), w.get(), MPFR_RNDU);
  mpfr_mul(w.get(), R[ca].get(), R[cb].get(), MPFR_RNDU);
  mpfr_add(e.get(), e.get(), w.get(), MPFR_RNDU);
  mpfr_mul(w.get(), A[ca].get(), A[cb].get(), MPFR_RNDU);
  mpfr_mul(w.get(), w.get(), product_error_scale_.get(), MPFR_RNDU);
  mpfr_add(e.get(), e.get(), w.get(), MPFR_RNDU);
  mpfr_add_d(e.get(), e.get(), rem_double, MPFR_RNDU);
  mpfr_add(e.get(), e.get(), f_rounding_.get(), MPFR_RNDU);
}

// F = int_{-1}^s f: b_1 = f_0 - f_2/2, b_k = (f_{k-1} - f_{k+1}) / (2k) for k >= 1. Then
// r = v_0 - q + hl F (q the increment polynomial, q(-1) = v_0 exactly: node 0 is s = -1), so for
// k >= 1, r_k = t_k - q_k with t_k = hl b_k formed as (f_{k-1} - f_{k+1}) times hl / (2k) and q_k
// taken at the left end of its enclosure (q_k = p_k for k >= 1; none beyond N). r_0 follows from
// r(-1) = 0 (to_doubles). With u = 2^-p, each rounded result x errs by at most u |x|:
//   - t_k: its difference, hl / (2k) and the product, together at most 3 u |t_k| (1 + 3u);
//   - r_k = t_k - q_k adds u |r_k|, and q_k's width;
//   - an error e_m of f_m moves sum_k |t_k| by at most |hl| e_m (f_m enters t_{m-1} and t_{m+1},
//     with factors below 1 together).
inline void picard_residual::integrate(const segment_polynomial& P, int i) {
  const real* f = f_.data();
  real* r = &r_[i * nr_];
  const interval* q = &P.p[i * n1_];
  mpfr_ptr half = tmp_.get();
  for (std::size_t k = 1; k < nr_; ++k) {
    mpfr_ptr t = r[k].get();
    if (k == 1 && k + 1 < np_) {
      mpfr_mul_2si(half, f[2].get(), -1, MPFR_RNDN);  // exact
      mpfr_sub(t, f[0].get(), half, MPFR_RNDN);
      mpfr_mul(t, t, hl_over_2k_[k].get(), MPFR_RNDN);
    } else if (k + 1 < np_) {
      mpfr_sub(t, f[k - 1].get(), f[k + 1].get(), MPFR_RNDN);
      mpfr_mul(t, t, hl_over_2k_[k].get(), MPFR_RNDN);
    } else if (k - 1 < np_) {
      mpfr_mul(t, f[k - 1].get(), hl_over_2k_[k].get(), MPFR_RNDN);
    } else {
      mpfr_set_ui(t, 0, MPFR_RNDN);
    }
    if (k < n1_) mpfr_sub(t, t, &q[k].get()->left, MPFR_RNDN);
  }
  // The magnitudes that the roundings scale with: sum |t_k| <= T = |hl| sum |f_m| (1 + 4u) (the
  // factors of each f_m are below 1 together), sum |r_k| <= (T + sum_{k >= 1} |q_k|) (1 + u).
  double q_abs = 0;
  for (std::size_t k = 1; k < n1_; ++k) q_abs += P.cmag[i * n1_ + k];
  const double t_abs = std::abs(mpfr_get_d(hl_over_2k_[1].get(), MPFR_RNDA)) * f_abs_ * (1 + 1e-9);
  const double units = (3 * (1 + 1e-6) * t_abs + (t_abs + q_abs) * (1 + 1e-9)) * (1 + 1e-12);
  // The bound of sum_{k >= 1} |r_k - exact r_k|: q's widths, u times the magnitudes, the products'.
  mpfr_ptr E = r_error_[i].get();
  mpfr_set(E, P.c_width[i].get(), MPFR_RNDU);
  mpfr_ptr e = bound_scratch_.get();
  mpfr_set_d(e, units, MPFR_RNDU);
  if (!mpfr_number_p(e)) P.fail(outcome_kind::certify_non_finite);
  mpfr_mul_2si(e, e, -static_cast<long>(bits_), MPFR_RNDU);
  mpfr_add(E, E, e, MPFR_RNDU);
  mpfr_abs(e, hl_over_2k_[1].get(), MPFR_RNDU);
  mpfr_mul(e, e, product_rem_[i].get(), MPFR_RNDU);
  mpfr_add(E, E, e, MPFR_RNDU);
}

// r scaled by 2^r_scale to about 1 and rounded to doubles (the integral term is linear in r, so
// its results are scaled back exactly, signed_integral_term.hpp); then r_0 = sum_{k >= 1}
// (-1)^(k+1) r_k, as the exact r vanishes at s = -1 (r(a) = P(a) - P(a)), summed in double; rsup
// and r1 from the doubles. Each d_k (k >= 1) is within eps |d_k| + denorm_min of r_k 2^r_scale, so
// with D >= the sum of those and of r's error scaled, d_0 is within D + gamma sum_{k >= 1} |d_k|
// of r_0 2^r_scale; a sum of n doubles is within gamma_n times the sum of their magnitudes of the
// exact sum (bounded_chebyshev.hpp).
inline void picard_residual::to_doubles(const segment_polynomial& P) {
  mpfr_exp_t top = std::numeric_limits<mpfr_exp_t>::min();
  for (int i = 0; i < 3; ++i)
    for (std::size_t k = 1; k < nr_; ++k) {
      mpfr_srcptr x = r_[i * nr_ + k].get();
      if (mpfr_regular_p(x)) top = std::max(top, mpfr_get_exp(x));
    }
  r_scale = top == std::numeric_limits<mpfr_exp_t>::min() ? 0 : -static_cast<long>(top);
  const double eps = std::numeric_limits<double>::epsilon(), tiny = std::numeric_limits<double>::denorm_min();
  const double gamma = gamma_of(nr_ + 1);
  for (int i = 0; i < 3; ++i) {
    double* d = &rd[i * nr_];
    double first = 0, above = 0, rounding = 0;  // d_0; sum_{k >= 1} |d_k|; their distances
    for (std::size_t k = 1; k < nr_; ++k) {
      long e = 0;
      const double m = mpfr_get_d_2exp(&e, r_[i * nr_ + k].get(), MPFR_RNDN);
      d[k] = std::ldexp(m, static_cast<int>(std::max(e + r_scale, -4000L)));  // 2^-4000: zero
      first += (k % 2) ? d[k] : -d[k];
      above += std::abs(d[k]);
      rounding += eps * std::abs(d[k]) + tiny;
    }
    d[0] = first;
    mpfr_ptr scaled = bound_scratch_.get();
    mpfr_mul_2si(scaled, r_error_[i].get(), r_scale, MPFR_RNDU);
    const double D = rounding + mpfr_get_d(scaled, MPFR_RNDU);
    rrad[i] = (2 * D + gamma * above) * (1 + 1e-12);
    double sum = 0, magnitude = 0;
    for (std::size_t k = 0; k < nr_; ++k) {
      sum += d[k];
      magnitude += std::abs(d[k]);
    }
    if (!std::isfinite(rrad[i]) || !std::isfinite(magnitude)) P.fail(outcome_kind::certify_non_finite);
    mpfi_set_d(rsup[i].get(), (magnitude * (1 + gamma) + rrad[i]) * (1 + 1e-12));
    mpfi_mul_2si(rsup[i].get(), rsup[i].get(), -r_scale);
    const double spread = (gamma * magnitude + rrad[i]) * (1 + 1e-12);
    mpfi_interv_d(t_.get(), -spread, spread);
    mpfi_set_d(r1[i].get(), sum);
    mpfi_add(r1[i].get(), r1[i].get(), t_.get());
    mpfi_mul_2si(r1[i].get(), r1[i].get(), -r_scale);
  }
}

}  // namespace eulervop::detail
