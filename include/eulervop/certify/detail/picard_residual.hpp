// The Picard residual of a segment's polynomial (docs/certified.md, "How", step 1):
//   r(tau) = P(a) + int_a^tau f(P) - P(tau),   f(y)_i = a_i y_j y_k + G_i,
// (j, k) = euler_problem::quadratic_pair[i], a polynomial of degree 2N + 1 with enclosed Chebyshev
// coefficients (f is quadratic, and the torque constant), so that sup |r| <= sum |r_k|.
//
// The products use T_m T_n = (T_{m+n} + T_{|m-n|}) / 2. Those of the large coefficients run on
// the midpoints put on a grid, as exact integers (grid_integer.hpp), those far below the
// reference's precision in double; both are widened afterwards by a bound of their errors, which
// the integral turns into a bound of the function.
#pragma once

#include <eulervop/certify/detail/bounded_chebyshev.hpp>
#include <eulervop/certify/detail/grid_integer.hpp>
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

  // r, rsup, r1, r_rem of P.
  void compute(const segment_polynomial& P);
  // rd, rrad, r_scale from r.
  void to_doubles();

  std::vector<interval> r;     // 3 x (2N + 2) coefficients
  std::vector<interval> rsup;  // sup |r_i| on the segment
  std::vector<interval> r1;    // r_i(b), signed
  std::vector<interval> r_rem; // [-e, e]: the share of the inexact products in r_i, widening r1
  // r as doubles: 2^-r_scale times rd, rd within rrad (per component, summed over k) of the
  // exact coefficients scaled. At deep MPFR levels r lies far below double's range.
  std::vector<double> rd;
  std::array<double, 3> rrad{};
  long r_scale = 0;

 private:
  void midpoints(const segment_polynomial& P);
  double multiply(const segment_polynomial& P, int i);
  template <std::size_t L>
  double multiply_on_limbs(const segment_polynomial& P, int i);
  template <class IntegerPair>
  double pairs(const segment_polynomial& P, int i, IntegerPair&& integer_pair);
  template <class ExactSum>
  double finish_product(int i, double rem, ExactSum&& exact_sum);
  void product_error(int i, double rem_double);
  void integrate(const segment_polynomial& P, int i);
  void bound(const segment_polynomial& P, int i);

  mpfr_prec_t bits_;
  std::size_t n1_, np_, nr_;
  vec3<interval> G_;
  std::array<int, 3> a_;
  std::array<std::array<int, 2>, 3> factors_;  // the quadratic pairs, ascending
  std::vector<interval> prod_;                  // f_i, 3 x (2N + 1)
  // Midpoints at the working precision: P, and a product's sums rounded back; P's midpoints on
  // the grid of step 2^-shift_, a product's exact sums on the grid 2^-(2 shift_ + 1) (T_m T_n's
  // factor 1/2), one product; the products in double.
  std::vector<real> pmid_, outmid_;
  std::vector<grid_integer> pq_, acc_;
  grid_integer pair_;
  // The same on at most 8 limbs (limbs_ per number; the sums on 2 limbs_ + 1) where they fit, with
  // the limb loops unrolled (grid_integer.hpp, limbs); GMP's integers otherwise.
  std::size_t limbs_;
  bool on_limbs_ = false;
  std::vector<mp_limb_t> pl_, pneg_, lacc_;
  long shift_ = 0;
  std::vector<double> gd_;
  // At 64 bits, rounded up: sum |p^_ik|, sum width(p_ik), the products' error per component.
  std::vector<real> Pabs_, Prad_, product_rem_;
  real bound_scratch_{64}, product_error_scale_{64};
  real tmp_, lo_, hi_;  // scratch at the working precision
  interval t_;
  std::vector<interval> r_scaled_, hl_over_2k_;
};

inline picard_residual::picard_residual(mpfr_prec_t bits, std::size_t degree, const vec3<interval>& G,
                                        const std::array<int, 3>& a)
    : r(3 * (2 * degree + 2), interval::zero(bits)), rsup(3, interval::zero(bits)), r1(3, interval::zero(bits)),
      r_rem(3, interval::zero(bits)), rd(3 * (2 * degree + 2), 0.0), bits_(bits), n1_(degree + 1),
      np_(2 * degree + 1), nr_(2 * degree + 2), G_(G), a_(a), prod_(3 * np_, interval::zero(bits)),
      pmid_(3 * n1_, real(bits)), outmid_(np_, real(bits)), pq_(3 * n1_, grid_integer(bits + 64)),
      acc_(np_, grid_integer(2 * bits + 128)), pair_(2 * bits + 128),
      limbs_((static_cast<std::size_t>(bits) + 64) / 64), pl_(3 * n1_ * limbs_), pneg_(3 * n1_),
      lacc_(2 * limbs_ + 1), gd_(np_, 0.0),
      Pabs_(3, real(64)), Prad_(3, real(64)), product_rem_(3, real(64)), tmp_(bits), lo_(bits), hi_(bits),
      t_(interval::zero(bits)), r_scaled_(3 * nr_, interval::zero(bits)), hl_over_2k_(nr_, interval::zero(bits)) {
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
  // hl / (2k) for k >= 2 (hl for k = 1, and the halving of f_2 there), once for the three
  // components: one interval product per coefficient instead of a division and a product.
  for (std::size_t k = 1; k < nr_; ++k) {
    mpfi_set(hl_over_2k_[k].get(), P.hl.get());
    if (k > 1) mpfi_div_ui(hl_over_2k_[k].get(), hl_over_2k_[k].get(), static_cast<unsigned long>(2 * k));
  }
  midpoints(P);
  for (int i = 0; i < 3; ++i) {
    product_error(i, multiply(P, i));
    mpfi_add(prod_[i * np_].get(), prod_[i * np_].get(), G_[i].get());
    integrate(P, i);
    bound(P, i);
  }
}

// p^ = mid p, |p - p^| <= width, and q = p^ on the grid 2^-shift_ (under the largest p^, p bits
// deep; |p^ - q| < a step): Pabs >= sum |q_k| and Prad >= sum |p_k - q_k| per component, each
// with n1 steps added to the midpoints' sums.
inline void picard_residual::midpoints(const segment_polynomial& P) {
  for (int c = 0; c < 3; ++c) {
    mpfr_set_ui(Pabs_[c].get(), 0, MPFR_RNDU);
    mpfr_set_ui(Prad_[c].get(), 0, MPFR_RNDU);
    for (std::size_t k = 0; k < n1_; ++k) {
      const std::size_t q = c * n1_ + k;
      mpfi_mid(pmid_[q].get(), P.p[q].get());
      add_abs_up(Pabs_[c], pmid_[q].get());
      width_up(hi_, P.p[q], lo_);
      mpfr_add(Prad_[c].get(), Prad_[c].get(), hi_.get(), MPFR_RNDU);
    }
  }
  shift_ = grid_shift(pmid_, [](const real& x) { return x.get(); }, bits_);
  for (std::size_t q = 0; q < 3 * n1_; ++q) to_grid(pq_[q], pmid_[q].get(), shift_);
  on_limbs_ = limbs_ <= 8;  // |q| <= 2^bits < 2^(64 limbs_): always fits
  for (std::size_t q = 0; on_limbs_ && q < 3 * n1_; ++q)
    on_limbs_ = limbs::load(pq_[q].get(), limbs_, &pl_[q * limbs_], pneg_[q]);
  mpfr_ptr steps = bound_scratch_.get();
  mpfr_set_ui_2exp(steps, static_cast<unsigned long>(n1_), -shift_, MPFR_RNDU);
  for (int c = 0; c < 3; ++c) {
    mpfr_add(Pabs_[c].get(), Pabs_[c].get(), steps, MPFR_RNDU);
    mpfr_add(Prad_[c].get(), Prad_[c].get(), steps, MPFR_RNDU);
  }
}

// prod_ row i = a_i P_j P_k, on the grid (exact) and in double (pairs); returns the bound of the
// double part's error.
inline double picard_residual::multiply(const segment_polynomial& P, int i) {
  double rem = 0;
  if (on_limbs_ &&
      limbs::with_limb_count(limbs_, [&](auto L) { rem = multiply_on_limbs<decltype(L)::value>(P, i); }))
    return rem;
  const grid_integer* A = &pq_[factors_[i][0] * n1_];
  const grid_integer* B = &pq_[factors_[i][1] * n1_];
  for (std::size_t k = 0; k < np_; ++k) mpz_set_ui(acc_[k].get(), 0);
  rem = pairs(P, i, [&](std::size_t m, std::size_t n, std::size_t d) {
    mpz_mul(pair_.get(), A[m].get(), B[n].get());
    mpz_add(acc_[m + n].get(), acc_[m + n].get(), pair_.get());
    mpz_add(acc_[d].get(), acc_[d].get(), pair_.get());
  });
  return finish_product(i, rem, [&](std::size_t k, mpfr_ptr y, long shift) {
    mpfr_set_z_2exp(y, acc_[k].get(), -shift, MPFR_RNDN);
  });
}

template <std::size_t L>
double picard_residual::multiply_on_limbs(const segment_polynomial& P, int i) {
  constexpr std::size_t W = 2 * L + 1;
  const mp_limb_t* A = &pl_[factors_[i][0] * n1_ * L];
  const mp_limb_t* B = &pl_[factors_[i][1] * n1_ * L];
  const mp_limb_t* A_neg = &pneg_[factors_[i][0] * n1_];
  const mp_limb_t* B_neg = &pneg_[factors_[i][1] * n1_];
  std::vector<limbs::column_sum<L>> sums(np_);
  const double rem = pairs(P, i, [&](std::size_t m, std::size_t n, std::size_t d) {
    limbs::product_columns<L> p;
    limbs::columns_of<L>(&A[m * L], &B[n * L], p);
    const unsigned negative = (A_neg[m] ^ B_neg[n]) & 1;
    sums[m + n].add(p, negative);
    sums[d].add(p, negative);
  });
  return finish_product(i, rem, [&](std::size_t k, mpfr_ptr y, long shift) {
    sums[k].to_limbs(lacc_.data(), W);
    limbs::round_to(lacc_.data(), W, y, shift);
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

// prod_ row i from the exact sums on the grid 2^-(2 shift + 1) (`exact_sum(k, y, shift)` rounds
// sum k to nearest into y) and the double ones: back to p bits (one rounding each), times a_i,
// exact (-1, 0 or 1). Returns `rem`.
template <class ExactSum>
double picard_residual::finish_product(int i, double rem, ExactSum&& exact_sum) {
  interval* out = &prod_[i * np_];
  for (std::size_t k = 0; k < np_; ++k) {
    mpfr_ptr y = outmid_[k].get();
    exact_sum(k, y, 2 * shift_ + 1);
    if (a_[i] < 0) mpfr_neg(y, y, MPFR_RNDN);
    if (a_[i] == 0) mpfr_set_ui(y, 0, MPFR_RNDN);
    if (gd_[k] == 0) {
      mpfi_set_fr(out[k].get(), y);
      continue;
    }
    // y + a_i gd_k with the end points rounded outward (the double enters exactly).
    mpfr_set_d(tmp_.get(), a_[i] * gd_[k], MPFR_RNDN);
    mpfr_add(&out[k].get()->left, y, tmp_.get(), MPFR_RNDD);
    mpfr_add(&out[k].get()->right, y, tmp_.get(), MPFR_RNDU);
  }
  return rem;
}

// Summed over the coefficients of one product, the grid products' error is at most
// A B' + A' B + A' B' + 2^-p (1 + 2^-20) A B, with A = sum |q_m|, A' = sum |a_m - q_m| (the same
// for b): sum_k |g_k - g^_k| <= sum_mn |a_m b_n - q_m r_n| (each pair's two halves), and the
// rounding of each exact sum to p bits is at most 2^-p |g^_k|, sum_k |g^_k| <= A B. |a_i| <= 1
// leaves it a bound of a_i's multiple.
inline void picard_residual::product_error(int i, double rem_double) {
  const int ca = factors_[i][0], cb = factors_[i][1];
  real& e = product_rem_[i];
  real& w = bound_scratch_;
  mpfr_mul(e.get(), Pabs_[ca].get(), Prad_[cb].get(), MPFR_RNDU);
  mpfr_mul(w.get(), Prad_[ca].get(), Pabs_[cb].get(), MPFR_RNDU);
  mpfr_add(e.get(), e.get(), w.get(), MPFR_RNDU);
  mpfr_mul(w.get(), Prad_[ca].get(), Prad_[cb].get(), MPFR_RNDU);
  mpfr_add(e.get(), e.get(), w.get(), MPFR_RNDU);
  mpfr_mul(w.get(), Pabs_[ca].get(), Pabs_[cb].get(), MPFR_RNDU);
  mpfr_mul(w.get(), w.get(), product_error_scale_.get(), MPFR_RNDU);
  mpfr_add(e.get(), e.get(), w.get(), MPFR_RNDU);
  mpfr_add_d(e.get(), e.get(), rem_double, MPFR_RNDU);
}

// F = int_{-1}^s f: b_1 = a_0 - a_2/2, b_k = (a_{k-1} - a_{k+1}) / (2k), b_0 so that F(-1) = 0.
// Then r = v_0 - q + hl F (q the increment polynomial, q(-1) = v_0 exactly: node 0 is s = -1).
// hl b_k is formed directly as (a_{k-1} - a_{k+1}) times the enclosure of hl / (2k).
inline void picard_residual::integrate(const segment_polynomial& P, int i) {
  const interval* f = &prod_[i * np_];
  interval* out = &r[i * nr_];
  for (std::size_t k = 1; k < nr_; ++k) {
    if (k + 1 < np_ && k == 1) {
      mpfi_mul_2si(t_.get(), f[2].get(), -1);
      mpfi_sub(out[1].get(), f[0].get(), t_.get());
    } else if (k + 1 < np_) {
      mpfi_sub(out[k].get(), f[k - 1].get(), f[k + 1].get());
    } else if (k - 1 < np_) {
      mpfi_set(out[k].get(), f[k - 1].get());
    } else {
      mpfi_set_ui(out[k].get(), 0);
    }
    mpfi_mul(out[k].get(), out[k].get(), hl_over_2k_[k].get());
  }
  mpfi_set_ui(out[0].get(), 0);
  for (std::size_t k = 1; k < nr_; ++k) {
    if (k % 2) mpfi_add(out[0].get(), out[0].get(), out[k].get());
    else mpfi_sub(out[0].get(), out[0].get(), out[k].get());
  }
  for (std::size_t k = 0; k < n1_; ++k) mpfi_sub(out[k].get(), out[k].get(), P.c[i * n1_ + k].get());
  mpfi_add(out[0].get(), out[0].get(), P.v[i * n1_].get());
}

// sup |r| <= sum |r_k| (a point: the sum of the magnitudes rounded up); r(1) = sum r_k; both
// widened by the inexact products' error, integrated:
// |hl int_{-1}^s e| <= 2 |hl| rem.
inline void picard_residual::bound(const segment_polynomial& P, int i) {
  const interval* ri = &r[i * nr_];
  mpfr_set_ui(lo_.get(), 0, MPFR_RNDU);  // sum_k max |r_k|, rounded up
  mpfi_set_ui(r1[i].get(), 0);
  for (std::size_t k = 0; k < nr_; ++k) {
    mpfi_mag(hi_.get(), ri[k].get());
    mpfr_add(lo_.get(), lo_.get(), hi_.get(), MPFR_RNDU);
    mpfi_add(r1[i].get(), r1[i].get(), ri[k].get());
  }
  mpfi_set_fr(rsup[i].get(), lo_.get());
  mpfi_set_fr(t_.get(), product_rem_[i].get());
  mpfi_mul(t_.get(), t_.get(), P.hl.get());
  mpfi_mul_2si(t_.get(), t_.get(), 1);
  mpfi_abs(t_.get(), t_.get());
  to_upper_point(t_);
  mpfi_add(rsup[i].get(), rsup[i].get(), t_.get());
  mpfi_set(r_rem[i].get(), t_.get());
  to_symmetric_hull(r_rem[i], t_);  // [-b, b]
  mpfi_add(r1[i].get(), r1[i].get(), r_rem[i].get());
}

// r scaled by 2^r_scale to about 1 before it becomes doubles; the integral term is linear in r,
// so its results are scaled back exactly (signed_integral_term.hpp).
inline void picard_residual::to_doubles() {
  mpfr_exp_t top = std::numeric_limits<mpfr_exp_t>::min();
  for (const interval& x : r) {
    mpfi_mag(hi_.get(), x.get());
    if (mpfr_regular_p(hi_.get())) top = std::max(top, mpfr_get_exp(hi_.get()));
  }
  r_scale = top == std::numeric_limits<mpfr_exp_t>::min() ? 0 : -static_cast<long>(top);
  for (std::size_t q = 0; q < r.size(); ++q) mpfi_mul_2si(r_scaled_[q].get(), r[q].get(), r_scale);
  for (int i = 0; i < 3; ++i) {
    rrad[i] = 0;
    for (std::size_t k = 0; k < nr_; ++k) {
      double rad = 0;
      rd[i * nr_ + k] = to_double(r_scaled_[i * nr_ + k], rad, lo_, hi_);
      rrad[i] += rad;
    }
    rrad[i] *= 1 + 1e-12;
  }
  for (int i = 0; i < 3; ++i) {  // the inexact products' share of r, scaled like r
    mpfi_mul_2si(t_.get(), r_rem[i].get(), r_scale);
    rrad[i] += magnitude_up(t_) * (1 + 1e-12);
  }
}

}  // namespace eulervop::detail
